#include "annex/common/assignment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

namespace annex {
namespace {

// Jonker-Volgenant (1987) for the n x m problem with n <= m, maximising total
// profit. Internally it minimises cost = -profit with column potentials v only:
// the invariant is that every assigned row sits on a column minimising
// cost(i, j) - v[j], which is dual feasibility with u[i] = that minimum.
// `profit` is row-major n x m and read row by row, so the access is contiguous.
// With n < m the unmatched columns must keep the largest potential (they face the
// implied zero-cost dummy rows); v starts at 0 and only ever decreases on matched
// columns, which stay matched, so that holds without explicit dummy rows.
class JonkerVolgenant {
 public:
  JonkerVolgenant(const double* profit, int n, int m)
      : profit_(profit), n_(n), m_(m), v_(m, 0.0), col4row_(n, -1), row4col_(m, -1) {}

  std::vector<int> solve() {
    std::vector<int> free_rows;
    if (n_ == m_) {
      free_rows = column_reduction();
    } else {
      free_rows.resize(n_);
      for (int i = 0; i < n_; ++i) free_rows[i] = i;
    }
    // Two passes, as in the paper: cheap, and it leaves few rows for augmentation.
    for (int pass = 0; pass < 2 && !free_rows.empty(); ++pass)
      free_rows = augmenting_row_reduction(std::move(free_rows));
    augment(free_rows);
    return std::move(col4row_);
  }

 private:
  const double* row(int i) const { return profit_ + static_cast<std::size_t>(i) * m_; }

  // Square case only: v[j] = column minimum of the cost, each column given to its
  // minimising row when that row is still free, then "reduction transfer" lowers the
  // potential of a row's only column so the row is indifferent to its second best.
  std::vector<int> column_reduction() {
    std::vector<int> argmin(m_, 0);
    const double* p0 = row(0);
    for (int j = 0; j < m_; ++j) v_[j] = -p0[j];
    for (int i = 1; i < n_; ++i) {  // row by row: contiguous reads of the input
      const double* p = row(i);
      for (int j = 0; j < m_; ++j) {
        if (-p[j] < v_[j]) {
          v_[j] = -p[j];
          argmin[j] = i;
        }
      }
    }
    std::vector<int> matches(n_, 0);
    for (int j = m_ - 1; j >= 0; --j) {
      const int i = argmin[j];
      if (matches[i]++ == 0) {
        col4row_[i] = j;
        row4col_[j] = i;
      }
    }
    std::vector<int> free_rows;
    for (int i = 0; i < n_; ++i) {
      if (matches[i] == 0) {
        free_rows.push_back(i);
      } else if (matches[i] == 1 && m_ > 1) {
        const int j1 = col4row_[i];
        const double* p = row(i);
        double min = std::numeric_limits<double>::infinity();
        for (int j = 0; j < m_; ++j)
          if (j != j1) min = std::min(min, -p[j] - v_[j]);
        v_[j1] -= min;
      }
    }
    return free_rows;
  }

  // Each free row takes its best column; if that column belonged to another row,
  // the column's potential drops so the row's second best ties, and the evicted row
  // is retried at once (or queued for the next pass on an exact tie).
  std::vector<int> augmenting_row_reduction(std::vector<int> free_rows) {
    std::vector<int> still_free;
    // Each retry lowers a potential by a positive amount; the cap only bounds the
    // pass on pathological floating-point inputs (leftovers go to augmentation).
    long retries_left = 4L * n_ + 16;
    std::size_t k = 0;
    while (k < free_rows.size()) {
      const int i = free_rows[k++];
      const double* p = row(i);
      double best = -p[0] - v_[0];
      double second = std::numeric_limits<double>::infinity();
      int j1 = 0;
      int j2 = -1;
      for (int j = 1; j < m_; ++j) {
        const double h = -p[j] - v_[j];
        if (h < second) {
          if (h >= best) {
            second = h;
            j2 = j;
          } else {
            second = best;
            j2 = j1;
            best = h;
            j1 = j;
          }
        }
      }
      int evicted = row4col_[j1];
      const bool strict = best < second;
      if (strict) {
        v_[j1] -= second - best;
      } else if (evicted >= 0) {
        // A tie: prefer the second column, which may be free.
        j1 = j2;
        evicted = row4col_[j1];
      }
      col4row_[i] = j1;
      row4col_[j1] = i;
      if (evicted >= 0) {
        col4row_[evicted] = -1;
        if (strict && retries_left-- > 0) {
          free_rows[--k] = evicted;
        } else {
          still_free.push_back(evicted);
        }
      }
    }
    return still_free;
  }

  // Shortest augmenting path (Dijkstra on reduced costs) from each free row. All
  // columns at the current minimum distance are collected at once, and only the
  // columns actually reached get their potentials updated.
  void augment(const std::vector<int>& free_rows) {
    std::vector<double> d(m_);
    std::vector<int> pred(m_);
    std::vector<int> cols(m_);
    for (const int f : free_rows) {
      const double* pf = row(f);
      for (int j = 0; j < m_; ++j) {
        d[j] = -pf[j] - v_[j];
        pred[j] = f;
        cols[j] = j;
      }
      // cols[0, low): scanned; cols[low, up): at distance `min`, to scan; rest: todo.
      int low = 0;
      int up = 0;
      int last = 0;  // cols[0, last): scanned before the latest minimum was found
      int sink = -1;
      double min = 0;
      while (sink < 0) {
        if (up == low) {
          last = low;
          min = d[cols[up++]];
          for (int k = up; k < m_; ++k) {
            const int j = cols[k];
            const double h = d[j];
            if (h <= min) {
              if (h < min) {
                up = low;
                min = h;
              }
              cols[k] = cols[up];
              cols[up++] = j;
            }
          }
          for (int k = low; k < up; ++k) {
            if (row4col_[cols[k]] < 0) {
              sink = cols[k];
              break;
            }
          }
          if (sink >= 0) break;
        }
        const int j1 = cols[low++];
        const int i = row4col_[j1];
        const double* p = row(i);
        const double h = -p[j1] - v_[j1] - min;
        for (int k = up; k < m_; ++k) {
          const int j = cols[k];
          const double dj = -p[j] - v_[j] - h;
          if (dj < d[j]) {
            pred[j] = i;
            if (dj == min) {
              if (row4col_[j] < 0) {
                sink = j;
                break;
              }
              cols[k] = cols[up];
              cols[up++] = j;
            }
            d[j] = dj;
          }
        }
      }
      for (int k = 0; k < last; ++k) {
        const int j = cols[k];
        v_[j] += d[j] - min;
      }
      for (int j = sink;;) {
        const int i = pred[j];
        row4col_[j] = i;
        std::swap(j, col4row_[i]);
        if (i == f) break;
      }
    }
  }

  const double* profit_;
  int n_;
  int m_;
  std::vector<double> v_;
  std::vector<int> col4row_;
  std::vector<int> row4col_;
};

}  // namespace

Assignment max_weight_assignment(const WeightMatrix& w) {
  if (w.rows < 0 || w.cols < 0 ||
      w.values.size() != static_cast<std::size_t>(w.rows) * static_cast<std::size_t>(w.cols))
    throw std::invalid_argument("max_weight_assignment: matrix size does not match rows x cols");
  for (double x : w.values)
    if (!std::isfinite(x)) throw std::invalid_argument("max_weight_assignment: non-finite weight");
  Assignment result;
  result.row_to_col.assign(static_cast<std::size_t>(w.rows), -1);
  if (w.rows == 0 || w.cols == 0) return result;

  // The solver assigns every row of the short side; missing rows or columns are the
  // paper's zero-weight dummies. It reads rows contiguously, so a tall matrix is
  // transposed once (O(rows * cols), small next to the solve).
  if (w.rows <= w.cols) {
    result.row_to_col = JonkerVolgenant(w.values.data(), w.rows, w.cols).solve();
  } else {
    // In tiles, so both the reads and the writes stay within a few cache lines.
    constexpr int kTile = 32;
    // Left uninitialised: every element is written below.
    const std::unique_ptr<double[]> transposed(new double[w.values.size()]);
    for (int r0 = 0; r0 < w.rows; r0 += kTile) {
      for (int c0 = 0; c0 < w.cols; c0 += kTile) {
        const int r1 = std::min(r0 + kTile, w.rows);
        const int c1 = std::min(c0 + kTile, w.cols);
        for (int r = r0; r < r1; ++r)
          for (int c = c0; c < c1; ++c)
            transposed[static_cast<std::size_t>(c) * w.rows + r] = w.at(r, c);
      }
    }
    const std::vector<int> col_to_row =
        JonkerVolgenant(transposed.get(), w.cols, w.rows).solve();
    for (int c = 0; c < w.cols; ++c) result.row_to_col[col_to_row[c]] = c;
  }
  for (int r = 0; r < w.rows; ++r)
    if (result.row_to_col[r] >= 0) result.total += w.at(r, result.row_to_col[r]);
  return result;
}

}  // namespace annex
