// Maximum-weight assignment on dense random matrices, uniform [0, 100), the same
// distribution and sizes as bench/scipy_assignment.py so the two can be compared.

#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>

#include "annex/common/assignment.h"

namespace {

annex::WeightMatrix random_matrix(int rows, int cols, std::uint64_t seed) {
  annex::WeightMatrix w;
  w.rows = rows;
  w.cols = cols;
  w.values.resize(static_cast<size_t>(rows) * cols);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> dist(0.0, 100.0);
  for (double& x : w.values) x = dist(rng);
  return w;
}

// Args: rows, cols. A fresh matrix per size, fixed seed, so every run solves the
// same instance; the solver copies what it needs, the input is never modified.
void BM_MaxWeightAssignment(benchmark::State& state) {
  const int rows = static_cast<int>(state.range(0));
  const int cols = static_cast<int>(state.range(1));
  const annex::WeightMatrix w = random_matrix(rows, cols, 42);
  for (auto _ : state) {
    annex::Assignment a = annex::max_weight_assignment(w);
    benchmark::DoNotOptimize(a.total);
  }
}

BENCHMARK(BM_MaxWeightAssignment)
    ->ArgNames({"rows", "cols"})
    ->Args({10, 10})
    ->Args({100, 100})
    ->Args({1000, 1000})
    ->Args({2000, 2000})
    ->Args({500, 2000})
    ->Args({2000, 500})
    ->Unit(benchmark::kMillisecond);

}  // namespace
