#pragma once
// The threads of an AnnexSession, created once with it: the tracker pool and, for
// ScanMode::background, the scan worker. Private to annex_session.cpp.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#if defined(__linux__)
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include "annex/common/result.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/scanner.h"

namespace annex {

// Runs fn(0..count-1) on threads created once (the calling thread is not one of them,
// so it can scan meanwhile); `wait` blocks until every index is done.
class WorkerPool {
 public:
  explicit WorkerPool(int threads) {
    for (int w = 0; w < std::max(1, threads); ++w) workers_.emplace_back([this] { loop(); });
  }
  ~WorkerPool() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
  }
  void start(int count, std::function<void(int)> fn) {
    {
      std::lock_guard lock(mutex_);
      fn_ = std::move(fn);
      done_ = 0;
      count_ = count;
      next_ = 0;
      ++generation_;
    }
    wake_.notify_all();
  }
  void wait() {
    std::unique_lock lock(mutex_);
    finished_.wait(lock, [&] { return done_ >= count_.load(); });
  }

 private:
  void loop() {
    std::uint64_t seen = 0;
    for (;;) {
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
      }
      for (int i = next_++; i < count_.load(); i = next_++) {
        fn_(i);
        std::lock_guard lock(mutex_);
        if (++done_ == count_.load()) finished_.notify_all();
      }
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_, finished_;
  std::function<void(int)> fn_;
  std::atomic<int> next_{0}, count_{0};
  int done_ = 0;
  std::uint64_t generation_ = 0;
  bool stop_ = false;
  std::vector<std::thread> workers_;
};

// ScanMode::background: one thread that scans a copy of a frame while the session
// goes on tracking; the finished result waits for the next process().
class ScanWorker {
 public:
  // `nice`: the worker's niceness on Linux (0 to 19), so that on a busy machine the
  // threads of the render loop (the caller's and the trackers') come before the scan.
  ScanWorker(ScanParams params, int nice) : params_(std::move(params)) {
    // The worker is the scan's only thread: the scanner creates none per frame.
    params_.threads = 1;
    thread_ = std::thread([this, nice] {
#if defined(__linux__)
      // Linux applies PRIO_PROCESS with a thread id to that thread alone. Failure (a
      // sandbox forbidding it) only leaves the default priority.
      if (nice > 0) (void)setpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)), nice);
#else
      (void)nice;
#endif
      loop();
    });
  }
  ~ScanWorker() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  bool busy() const { return in_flight_ || staged_; }
  bool ready() const { return in_flight_ && done_.load(std::memory_order_acquire); }
  // Copies the frame (the caller's may be gone before the scan ends); the buffer is
  // reused, so a 640x480 copy allocates nothing after the first. The scan starts at
  // go(): the session calls it when the frame's tracking is done, so a scan never
  // competes with the tracking of the frame it was taken from.
  void stage(const Frame& frame, int frame_index) {
    frame_.width = frame.width;
    frame_.height = frame.height;
    frame_.timestamp_s = frame.timestamp_s;
    frame_.index = frame.index;
    frame_.points.assign(frame.points.begin(), frame.points.end());
    frame_index_ = frame_index;
    staged_ = true;
  }
  void go() {
    if (!staged_) return;
    staged_ = false;
    {
      std::lock_guard lock(mutex_);
      done_ = false;
      has_job_ = true;
    }
    in_flight_ = true;
    wake_.notify_one();
  }
  void wait() {
    if (!in_flight_) return;
    std::unique_lock lock(mutex_);
    finished_.wait(lock, [&] { return done_.load(); });
  }
  // Only when ready(): the result, the frame it was taken from and the scan's time.
  struct Done {
    Result<ScanResult> result;
    int frame_index;
    double ms;
  };
  Done take() {
    std::lock_guard lock(mutex_);
    in_flight_ = false;
    return Done{std::move(*result_), frame_index_, ms_};
  }

 private:
  void loop() {
    for (;;) {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || has_job_; });
      if (stop_) return;
      has_job_ = false;
      lock.unlock();
      // frame_ is not touched by the session while the job runs (busy() is true).
      const auto t0 = std::chrono::steady_clock::now();
      Result<ScanResult> r = scan_frame(frame_, params_);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      lock.lock();
      result_.emplace(std::move(r));
      ms_ = ms;
      done_.store(true, std::memory_order_release);
      finished_.notify_all();
    }
  }

  ScanParams params_;
  std::mutex mutex_;
  std::condition_variable wake_, finished_;
  Frame frame_;
  std::optional<Result<ScanResult>> result_;
  double ms_ = 0;
  int frame_index_ = 0;
  bool has_job_ = false, stop_ = false;
  std::atomic<bool> done_{false};
  bool in_flight_ = false, staged_ = false;  // session thread only
  std::thread thread_;
};

}  // namespace annex
