#pragma once
// The q-quantile of a sample (the element at floor(q (n - 1)) once sorted; 0 when empty).
// Private to the runtime.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace annex {

inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const std::size_t k =
      std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace annex
