#pragma once
// Forced-rank mode (the paper's future work: developers found continuous weights
// hard to predict). The developer orders items; weights follow the rank linearly:
// rank r of n (0 = most important) gets weight (n - r) / n, so 3 items get 1, 2/3, 1/3.
// Every weight stays above 0 (a zero w_o or w_s would silence a vote) and the steps
// between neighbours are equal and never tie.

#include <vector>

namespace annex::authoring {

std::vector<double> rank_weights(int n);

// Item indices most important first: weight descending, ties in authored order
// (the order the Voter uses, see primitive_priority_order).
std::vector<int> order_by_weight(const std::vector<double>& weights);

// weights[order[r]] = rank_weights(n)[r]; `order` must be a permutation of 0..n-1.
std::vector<double> weights_from_order(const std::vector<int>& order);

bool is_permutation_of_n(const std::vector<int>& order, int n);

}  // namespace annex::authoring
