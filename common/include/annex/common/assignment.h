#pragma once
// Maximum-weight assignment on a rectangular matrix (the matching step of the
// ObjectFinder). Rows are virtual objects, columns physical objects; the solver
// pads with zero-weight dummies, as the paper does, so every row and column is
// matched to something, a dummy included.

#include <cstddef>
#include <vector>

namespace annex {

// Row-major dense matrix of weights.
struct WeightMatrix {
  int rows = 0;
  int cols = 0;
  std::vector<double> values;  // rows * cols
  double at(int r, int c) const { return values[static_cast<std::size_t>(r) * cols + c]; }
  double& at(int r, int c) { return values[static_cast<std::size_t>(r) * cols + c]; }
};

struct Assignment {
  std::vector<int> row_to_col;  // -1: the row went to a dummy column
  double total = 0;             // sum of the weights of the real pairs
};

// Shortest-augmenting-path Hungarian method (Jonker-Volgenant style), O(n^3).
// As with the paper's square padding, exactly min(rows, cols) rows get a real
// column, even when its weight is negative (votes never are).
// Weights must be finite and values.size() == rows * cols; throws
// std::invalid_argument otherwise (a programmer error: votes are always finite).
Assignment max_weight_assignment(const WeightMatrix& weights);

}  // namespace annex
