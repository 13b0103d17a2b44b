#pragma once
// The worker threads of one scan (scanner.cpp): created when scan_frame starts, awake
// for its few milliseconds, joined when it returns. Spawning threads per parallel pass
// (a scan has a dozen) costs a thread start each time, and a thread woken from sleep
// under load starts late; a helper that is already spinning picks a pass up within a
// microsecond. Private to the runtime.
//
// Every pass hands out items through one atomic counter, so which thread runs an item
// never matters to the result: callers keep results per item (or per band of items) and
// combine them in item order, as one thread would.

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace annex {

class ScanPool {
 public:
  // `threads` counts the calling thread: 1 runs everything on the caller.
  explicit ScanPool(int threads) {
    for (int w = 1; w < threads; ++w) helpers_.emplace_back([this] { loop(); });
  }
  ~ScanPool() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
      generation_.fetch_add(1, std::memory_order_release);
    }
    wake_.notify_all();
    for (std::thread& t : helpers_) t.join();
  }
  ScanPool(const ScanPool&) = delete;
  ScanPool& operator=(const ScanPool&) = delete;

  int threads() const { return static_cast<int>(helpers_.size()) + 1; }

  // body(order[k]) for k in 0..n-1 (body(k) without `order`), items taken in that order
  // by whichever thread is free; returns when all are done.
  // Only the thread that created the pool calls it (the helpers see no pool); a pass
  // started from inside a pass's item runs on the calling thread.
  template <typename F>
  void run(size_t n, F&& body, const std::vector<size_t>* order = nullptr) {
    if (helpers_.empty() || n <= 1 || running_) {
      for (size_t k = 0; k < n; ++k) body(order ? (*order)[k] : k);
      return;
    }
    running_ = true;
    using Body = std::remove_reference_t<F>;
    struct Ctx {
      Body* body;
      const std::vector<size_t>* order;
    } ctx{&body, order};
    job_.call = [](void* c, size_t k) {
      const Ctx& x = *static_cast<Ctx*>(c);
      (*x.body)(x.order ? (*x.order)[k] : k);
    };
    job_.ctx = &ctx;
    job_.n = n;
    next_.store(0, std::memory_order_relaxed);
    done_.store(0, std::memory_order_relaxed);
    const int helpers = static_cast<int>(std::min(helpers_.size(), n - 1));
    slots_.store(helpers, std::memory_order_release);
    {
      std::lock_guard lock(mutex_);
      generation_.fetch_add(1, std::memory_order_release);
    }
    if (sleeping_.load(std::memory_order_acquire) > 0) wake_.notify_all();
    work();
    // Helpers that have not taken the pass by now are not waited for: the caller did
    // its items (a helper woken late under load would otherwise hold the scan up).
    const int unclaimed = std::max(0, slots_.exchange(0, std::memory_order_acq_rel));
    const int entered = helpers - unclaimed;
    // A helper's last item may take milliseconds (a big cluster's fits): after a short
    // spin the caller sleeps until a helper finishes instead of burning its core.
    for (int spin = 0; spin < kCallerSpin && done_.load(std::memory_order_acquire) < entered; ++spin)
      pause();
    for (int d = done_.load(std::memory_order_acquire); d < entered; d = done_.load(std::memory_order_acquire))
      done_.wait(d, std::memory_order_acquire);
    running_ = false;
  }

  // Splits 0..n-1 into contiguous bands of at least `min_band` items, at most one per
  // thread, and runs body(band, begin, end) for each; returns the number of bands.
  // A pass too small to be worth a second thread stays one band on the caller.
  template <typename F>
  size_t bands(size_t n, size_t min_band, F&& body) {
    const size_t count =
        std::max<size_t>(1, std::min<size_t>(static_cast<size_t>(threads()), n / std::max<size_t>(1, min_band)));
    run(count, [&](size_t b) { body(b, n * b / count, n * (b + 1) / count); });
    return count;
  }

 private:
  struct Job {
    void (*call)(void*, size_t) = nullptr;
    void* ctx = nullptr;
    size_t n = 0;
  };

  static void pause() {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#else
    std::this_thread::yield();
#endif
  }

  void work() {
    for (size_t k = next_.fetch_add(1, std::memory_order_relaxed); k < job_.n;
         k = next_.fetch_add(1, std::memory_order_relaxed))
      job_.call(job_.ctx, k);
  }

  void loop() {
    uint64_t seen = 0;
    for (;;) {
      // Spin a little (passes follow each other within microseconds), then sleep.
      for (int spin = 0; spin < kHelperSpin && generation_.load(std::memory_order_acquire) == seen; ++spin)
        pause();
      if (generation_.load(std::memory_order_acquire) == seen) {
        std::unique_lock lock(mutex_);
        sleeping_.fetch_add(1, std::memory_order_acq_rel);
        wake_.wait(lock, [&] { return generation_.load(std::memory_order_acquire) != seen; });
        sleeping_.fetch_sub(1, std::memory_order_acq_rel);
      }
      seen = generation_.load(std::memory_order_acquire);
      {
        std::lock_guard lock(mutex_);
        if (stop_) return;
      }
      // A slot taken means the caller counts this helper in and waits for it.
      if (slots_.fetch_sub(1, std::memory_order_acq_rel) <= 0) continue;
      work();
      done_.fetch_add(1, std::memory_order_release);
      done_.notify_all();
    }
  }

  // How long a helper spins for the next pass before it sleeps, in pauses (some 10 ns
  // each on the project's Xeon, 20000 measured at 200 us; 15 to 40 ns on other x86
  // cores): about 50 us, the gaps between a scan's back-to-back passes (clusters to
  // MLS to shapes) are shorter, while its serial stretches (the plane stage, the
  // clustering) are milliseconds long, where spinning on would only burn a core that a
  // loaded machine gives someone else (a 0.2 ms spin, with the caller yielding instead
  // of sleeping, cost about 2 to 6 ms more CPU per scan at load 10).
  static constexpr int kHelperSpin = 5000;
  // The caller's spin for helpers still on their last item, before it sleeps.
  static constexpr int kCallerSpin = 2000;

  std::vector<std::thread> helpers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::atomic<uint64_t> generation_{0};
  std::atomic<int> sleeping_{0};
  std::atomic<int> slots_{0};
  std::atomic<int> done_{0};
  std::atomic<size_t> next_{0};
  Job job_;
  bool running_ = false;  // a pass is on; read and written by the calling thread only
  bool stop_ = false;
};

}  // namespace annex
