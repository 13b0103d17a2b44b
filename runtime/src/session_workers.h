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
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include "annex/common/result.h"
#include "annex/runtime/annex_session.h"
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
// goes on tracking; the finished result waits for the next process(). The session and
// the worker share no mutex: the hand-over is three atomics (C++20 wait/notify, a futex
// on Linux), so a worker at idle priority, preempted at any instruction, can never hold
// a lock the render loop waits for (no priority inversion).
class ScanWorker {
 public:
  // `late_after`: pushes a scan may run at idle priority before it is promoted.
  ScanWorker(ScanParams params, ScanPriority priority, int nice, int late_after)
      : params_(std::move(params)), priority_(priority), nice_(nice), late_after_(late_after) {
    // The worker is the scan's only thread: the scanner creates none per frame.
    params_.threads = 1;
    thread_ = std::thread([this] {
#if defined(__linux__)
      tid_.store(static_cast<int>(::syscall(SYS_gettid)), std::memory_order_release);
#endif
      loop();
    });
  }
  ~ScanWorker() {
    stop_.store(true, std::memory_order_release);
    jobs_.fetch_add(1, std::memory_order_release);
    jobs_.notify_one();
    thread_.join();
  }
  bool busy() const { return in_flight_ || staged_; }
  bool ready() const { return in_flight_ && done_.load(std::memory_order_acquire); }
  // Copies the frame (the caller's may be gone before the scan ends); the buffer is
  // reused, so a 640x480 copy allocates nothing after the first. The scan starts at
  // go(): the session calls it as the push returns, so a scan never competes with the
  // tracking of the frame it was taken from and starts in the render loop's idle time.
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
    done_.store(false, std::memory_order_relaxed);
    in_flight_ = true;
    pushes_in_flight_ = 0;
    jobs_.fetch_add(1, std::memory_order_release);  // publishes frame_ to the worker
    jobs_.notify_one();
  }
  void wait() {
    if (in_flight_) done_.wait(false, std::memory_order_acquire);
  }
  // Only when ready(): the result, the frame it was taken from and the scan's time.
  struct Done {
    Result<ScanResult> result;
    int frame_index;
    double ms;
  };
  Done take() {
    in_flight_ = false;
    return Done{std::move(*result_), frame_index_, ms_};
  }
  // Called once a push. Under SCHED_IDLE a scan gets next to no CPU while every core is
  // busy (a game whose threads spin, other programs), so props would not be annexed: a
  // scan still running `late_after` pushes after it started is promoted to SCHED_OTHER
  // at niceness `nice` until it ends; the next scan starts idle again. The session
  // thread changes the worker's policy by its thread id, so the promotion does not wait
  // for the starved worker to run. Returns true on promotion.
  bool tick() {
    if (!in_flight_ || ++pushes_in_flight_ != late_after_ || !idle_.load(std::memory_order_acquire))
      return false;
#if defined(__linux__)
    const int tid = tid_.load(std::memory_order_acquire);
    if (tid <= 0 || done_.load(std::memory_order_acquire)) return false;
    sched_param none{};  // SCHED_OTHER keeps the worker's niceness, `nice`
    if (::sched_setscheduler(tid, SCHED_OTHER, &none) != 0) return false;
    promoted_.store(true, std::memory_order_release);
    return true;
#else
    return false;
#endif
  }

 private:
  // SCHED_IDLE: the scheduler runs the worker only when a core has nothing else to run
  // and preempts it as soon as any other thread wakes (a tracker, the render loop, another
  // process), so the scan uses the frame's idle time and does not delay a push. Linux
  // applies these calls to the calling thread alone. The worker first takes niceness
  // `nice` (raising one's niceness is always allowed), then SCHED_IDLE only if it may
  // leave it again for tick()'s promotion: that needs CAP_SYS_NICE (root) or RLIMIT_NICE
  // >= 20 - nice (Linux's rule for leaving SCHED_IDLE; Debian's default limit is 0).
  // Otherwise it stays at niceness `nice`, a smaller share of a busy core, as with
  // ScanPriority::nice. A failure (a sandbox forbidding it) leaves the default priority.
  void lower_priority() {
#if defined(__linux__)
    const id_t self = static_cast<id_t>(::syscall(SYS_gettid));
    if (nice_ > 0) (void)::setpriority(PRIO_PROCESS, self, nice_);
    if (priority_ != ScanPriority::idle) return;
    rlimit limit{};
    const bool may_leave =
        ::geteuid() == 0 || (::getrlimit(RLIMIT_NICE, &limit) == 0 &&
                             limit.rlim_cur >= static_cast<rlim_t>(20 - nice_));
    sched_param none{};
    if (may_leave && ::sched_setscheduler(0, SCHED_IDLE, &none) == 0)
      idle_.store(true, std::memory_order_release);
#endif
  }

  void loop() {
    lower_priority();
    std::uint32_t seen = 0;
    for (;;) {
      jobs_.wait(seen, std::memory_order_acquire);
      seen = jobs_.load(std::memory_order_acquire);
      if (stop_.load(std::memory_order_acquire)) return;
#if defined(__linux__)
      if (promoted_.exchange(false, std::memory_order_acq_rel)) {
        sched_param none{};
        (void)::sched_setscheduler(0, SCHED_IDLE, &none);  // entering it is always allowed
      }
#endif
      // frame_ is not touched by the session while the job runs (busy() is true).
      const auto t0 = std::chrono::steady_clock::now();
      Result<ScanResult> r = scan_frame(frame_, params_);
      ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      result_.emplace(std::move(r));
      done_.store(true, std::memory_order_release);  // publishes result_ and ms_
      done_.notify_all();
    }
  }

  ScanParams params_;
  const ScanPriority priority_;
  const int nice_, late_after_;
  int pushes_in_flight_ = 0;  // session thread only
  std::atomic<int> tid_{0};
  // idle_: the worker runs under SCHED_IDLE; promoted_: tick() lifted this scan out of it.
  std::atomic<bool> idle_{false}, promoted_{false};
  Frame frame_;
  std::optional<Result<ScanResult>> result_;
  double ms_ = 0;
  int frame_index_ = 0;
  std::atomic<std::uint32_t> jobs_{0};
  std::atomic<bool> stop_{false}, done_{false};
  bool in_flight_ = false, staged_ = false;  // session thread only
  std::thread thread_;
};

}  // namespace annex
