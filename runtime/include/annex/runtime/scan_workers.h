#pragma once
// Worker threads kept across scans, for a caller that scans frame after frame (a
// session's scan worker, a benchmark, `annex-runtime scan --repeat`). scan_frame without
// them starts its helper threads when it begins and joins them when it returns; with
// them the helpers are started by the first scan and wait, spinning briefly and then
// asleep, for the next one. Results are the same either way, bit for bit.
#include <memory>

#include "annex/common/result.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/scanner.h"

namespace annex {

class ScanPool;  // runtime/src/scan_pool.h
class ScanWorkers;

// scan_frame(frame, params) on `workers`' threads (params.threads of them, the calling
// thread included; a change of params.threads restarts them). One scan at a time per
// ScanWorkers: the caller does not share one between threads that scan concurrently.
Result<ScanResult> scan_frame(const Frame& frame, const ScanParams& params, ScanWorkers& workers);

class ScanWorkers {
 public:
  ScanWorkers();
  ~ScanWorkers();
  ScanWorkers(const ScanWorkers&) = delete;
  ScanWorkers& operator=(const ScanWorkers&) = delete;

  // Threads the workers run now, the calling thread included (0 before the first scan).
  int threads() const;

 private:
  friend Result<ScanResult> scan_frame(const Frame&, const ScanParams&, ScanWorkers&);
  // The pool of `threads` threads, started (or restarted) on first use.
  ScanPool& pool(int threads);
  std::unique_ptr<ScanPool> pool_;
};

}  // namespace annex
