#include "annex/runtime/scan_workers.h"

#include "scan_pool.h"

namespace annex {

ScanWorkers::ScanWorkers() = default;
ScanWorkers::~ScanWorkers() = default;

int ScanWorkers::threads() const { return pool_ ? pool_->threads() : 0; }

ScanPool& ScanWorkers::pool(int threads) {
  if (!pool_ || pool_->threads() != threads) {
    pool_.reset();  // the old helpers are joined before new ones start
    pool_ = std::make_unique<ScanPool>(threads);
  }
  return *pool_;
}

}  // namespace annex
