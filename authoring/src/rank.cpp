#include "annex/authoring/rank.h"

#include <algorithm>
#include <numeric>

namespace annex::authoring {

std::vector<double> rank_weights(int n) {
  std::vector<double> w;
  for (int r = 0; r < n; ++r) w.push_back(static_cast<double>(n - r) / n);
  return w;
}

std::vector<int> order_by_weight(const std::vector<double>& weights) {
  std::vector<int> order(weights.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return weights[a] > weights[b]; });
  return order;
}

bool is_permutation_of_n(const std::vector<int>& order, int n) {
  if (static_cast<int>(order.size()) != n) return false;
  std::vector<bool> seen(static_cast<std::size_t>(n), false);
  for (int i : order) {
    if (i < 0 || i >= n || seen[i]) return false;
    seen[i] = true;
  }
  return true;
}

std::vector<double> weights_from_order(const std::vector<int>& order) {
  const int n = static_cast<int>(order.size());
  const std::vector<double> by_rank = rank_weights(n);
  std::vector<double> w(order.size(), 0.0);
  for (int r = 0; r < n; ++r) w[order[r]] = by_rank[r];
  return w;
}

}  // namespace annex::authoring
