#pragma once
// Paces a recorded source: sleeps until each frame's recorded time relative to the
// first delivered frame (Pacing::recorded_rate).

#include <chrono>
#include <thread>

namespace annex {

class Pacer {
 public:
  void wait_for(double timestamp_s) {
    const auto now = std::chrono::steady_clock::now();
    if (!started_) {
      started_ = true;
      start_ = now;
      first_timestamp_s_ = timestamp_s;
      return;
    }
    const auto due = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                  std::chrono::duration<double>(timestamp_s - first_timestamp_s_));
    if (due > now) std::this_thread::sleep_until(due);
  }

 private:
  bool started_ = false;
  std::chrono::steady_clock::time_point start_;
  double first_timestamp_s_ = 0;
};

}  // namespace annex
