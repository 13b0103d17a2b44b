// max_weight_assignment: the paper's worked example, edge cases, brute force on
// small random matrices and SciPy's linear_sum_assignment on larger ones.

#include "annex/common/assignment.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "../unique_temp_dir.h"

namespace annex {
namespace {

WeightMatrix make_matrix(int rows, int cols, std::vector<double> values) {
  WeightMatrix w;
  w.rows = rows;
  w.cols = cols;
  w.values = std::move(values);
  return w;
}

// Uniform weights from [lo, hi); integral ones when `integers` is set.
WeightMatrix random_matrix(int rows, int cols, double lo, double hi, bool integers,
                           std::mt19937_64& rng) {
  WeightMatrix w = make_matrix(rows, cols, std::vector<double>(static_cast<size_t>(rows) * cols));
  std::uniform_real_distribution<double> real(lo, hi);
  std::uniform_int_distribution<int> whole(static_cast<int>(lo), static_cast<int>(hi) - 1);
  for (double& x : w.values) x = integers ? whole(rng) : real(rng);
  return w;
}

// A valid result under square padding: each real column used at most once, and
// exactly min(rows, cols) rows on real columns (the rest sit on dummies). The
// reported total must be the sum of the chosen weights.
void expect_valid(const WeightMatrix& w, const Assignment& a) {
  ASSERT_EQ(a.row_to_col.size(), static_cast<size_t>(w.rows));
  std::vector<char> used(static_cast<size_t>(w.cols), 0);
  int matched = 0;
  double sum = 0;
  for (int r = 0; r < w.rows; ++r) {
    const int c = a.row_to_col[r];
    if (c == -1) continue;
    ASSERT_GE(c, 0) << "row " << r;
    ASSERT_LT(c, w.cols) << "row " << r;
    ASSERT_FALSE(used[c]) << "column " << c << " used twice";
    used[c] = 1;
    ++matched;
    sum += w.at(r, c);
  }
  EXPECT_EQ(matched, std::min(w.rows, w.cols));
  EXPECT_DOUBLE_EQ(a.total, sum);
}

// Best total over all injective maps from the shorter side into the longer one.
double brute_force_total(const WeightMatrix& w) {
  const bool transpose = w.rows > w.cols;
  const int n = transpose ? w.cols : w.rows;
  const int m = transpose ? w.rows : w.cols;
  auto weight = [&](int i, int j) { return transpose ? w.at(j, i) : w.at(i, j); };
  std::vector<char> used(static_cast<size_t>(m), 0);
  double best = -std::numeric_limits<double>::infinity();
  auto recurse = [&](auto& self, int i, double sum) -> void {
    if (i == n) {
      best = std::max(best, sum);
      return;
    }
    for (int j = 0; j < m; ++j) {
      if (used[j]) continue;
      used[j] = 1;
      self(self, i + 1, sum + weight(i, j));
      used[j] = 0;
    }
  };
  recurse(recurse, 0, 0.0);
  return n == 0 ? 0.0 : best;
}

TEST(Assignment, PaperFigure3PrefersTheGlobalOptimum) {
  // Rows v1..v3, columns p1..p3. v1 prefers p1 (55 %), but giving it p2 (34 %)
  // lets v3 take p1 (48 %): 34 + 65 + 48 = 147 beats 55 + 65 + 0 = 120.
  const WeightMatrix w = make_matrix(3, 3, {55, 34, 0,  //
                                            0, 0, 65,   //
                                            48, 0, 0});
  const Assignment a = max_weight_assignment(w);
  expect_valid(w, a);
  EXPECT_EQ(a.row_to_col, (std::vector<int>{1, 2, 0}));
  EXPECT_EQ(a.total, 147);
}

TEST(Assignment, EmptyMatricesGiveEmptyOrDummyAssignments) {
  for (const auto& [rows, cols] : {std::pair{0, 0}, std::pair{0, 3}, std::pair{3, 0}}) {
    const WeightMatrix w = make_matrix(rows, cols, {});
    const Assignment a = max_weight_assignment(w);
    EXPECT_EQ(a.row_to_col, std::vector<int>(static_cast<size_t>(rows), -1));
    EXPECT_EQ(a.total, 0);
  }
}

TEST(Assignment, SingleRowTakesItsBestColumn) {
  const WeightMatrix w = make_matrix(1, 5, {3, 9, 1, 9.5, 2});
  const Assignment a = max_weight_assignment(w);
  EXPECT_EQ(a.row_to_col, (std::vector<int>{3}));
  EXPECT_EQ(a.total, 9.5);
}

TEST(Assignment, SingleColumnGoesToItsBestRow) {
  const WeightMatrix w = make_matrix(4, 1, {3, 7, 1, 2});
  const Assignment a = max_weight_assignment(w);
  EXPECT_EQ(a.row_to_col, (std::vector<int>{-1, 0, -1, -1}));
  EXPECT_EQ(a.total, 7);
}

TEST(Assignment, AllZeroWeightsStillGiveAValidAssignment) {
  for (const auto& [rows, cols] : {std::pair{4, 4}, std::pair{2, 5}, std::pair{5, 2}}) {
    const WeightMatrix w =
        make_matrix(rows, cols, std::vector<double>(static_cast<size_t>(rows) * cols, 0.0));
    const Assignment a = max_weight_assignment(w);
    expect_valid(w, a);
    EXPECT_EQ(a.total, 0);
  }
}

TEST(Assignment, TiesGiveAValidOptimum) {
  const WeightMatrix equal = make_matrix(3, 3, std::vector<double>(9, 5.0));
  const Assignment a = max_weight_assignment(equal);
  expect_valid(equal, a);
  EXPECT_EQ(a.total, 15);

  // Two optimal assignments of total 10; either is fine.
  const WeightMatrix two_ways = make_matrix(2, 2, {5, 5,  //
                                                   5, 5});
  const Assignment b = max_weight_assignment(two_ways);
  expect_valid(two_ways, b);
  EXPECT_EQ(b.total, 10);
}

TEST(Assignment, NegativeWeightsAreSolvedExactly) {
  // Square padding: both rows must take a real column, so the best is -1 + -2.
  const WeightMatrix w = make_matrix(2, 2, {-1, -5,  //
                                            -3, -2});
  const Assignment a = max_weight_assignment(w);
  expect_valid(w, a);
  EXPECT_EQ(a.row_to_col, (std::vector<int>{0, 1}));
  EXPECT_EQ(a.total, -3);

  // Mixed signs, rectangular both ways.
  const WeightMatrix wide = make_matrix(2, 3, {-4, 2, -1,  //
                                               -2, 3, -9});
  const Assignment b = max_weight_assignment(wide);
  expect_valid(wide, b);
  EXPECT_EQ(b.row_to_col, (std::vector<int>{2, 1}));
  EXPECT_EQ(b.total, 2);

  const WeightMatrix tall = make_matrix(3, 1, {-7, -3, -5});
  const Assignment c = max_weight_assignment(tall);
  EXPECT_EQ(c.row_to_col, (std::vector<int>{-1, 0, -1}));
  EXPECT_EQ(c.total, -3);
}

TEST(Assignment, NonFiniteWeightsAreRejected) {
  for (double bad : {std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()}) {
    const WeightMatrix w = make_matrix(2, 2, {1, 2, bad, 4});
    EXPECT_THROW(max_weight_assignment(w), std::invalid_argument) << bad;
  }
}

TEST(Assignment, SizeMismatchIsRejected) {
  EXPECT_THROW(max_weight_assignment(make_matrix(2, 2, {1, 2, 3})), std::invalid_argument);
  EXPECT_THROW(max_weight_assignment(make_matrix(2, 2, {1, 2, 3, 4, 5})), std::invalid_argument);
  EXPECT_THROW(max_weight_assignment(make_matrix(0, 3, {1})), std::invalid_argument);
  EXPECT_THROW(max_weight_assignment(make_matrix(-1, 2, {})), std::invalid_argument);
  EXPECT_THROW(max_weight_assignment(make_matrix(2, -1, {})), std::invalid_argument);
}

TEST(Assignment, SmallIntegerMatricesMatchBruteForce) {
  std::mt19937_64 rng(20161);
  for (int rows = 1; rows <= 8; ++rows) {
    for (int cols = 1; cols <= 8; ++cols) {
      for (int trial = 0; trial < 6; ++trial) {
        // Narrow ranges make many ties; the negative range checks signs.
        const double lo = trial % 3 == 2 ? -50 : 0;
        const double hi = trial % 3 == 0 ? 4 : 100;
        const WeightMatrix w = random_matrix(rows, cols, lo, hi, true, rng);
        const Assignment a = max_weight_assignment(w);
        SCOPED_TRACE(testing::Message() << rows << "x" << cols << " trial " << trial);
        expect_valid(w, a);
        EXPECT_EQ(a.total, brute_force_total(w));
      }
    }
  }
}

TEST(Assignment, SmallRealMatricesMatchBruteForce) {
  std::mt19937_64 rng(2016);
  for (int rows = 1; rows <= 8; ++rows) {
    for (int cols = 1; cols <= 8; ++cols) {
      for (int trial = 0; trial < 4; ++trial) {
        const double lo = trial % 2 == 1 ? -1e3 : 0;
        const WeightMatrix w = random_matrix(rows, cols, lo, 1e3, false, rng);
        const Assignment a = max_weight_assignment(w);
        SCOPED_TRACE(testing::Message() << rows << "x" << cols << " trial " << trial);
        expect_valid(w, a);
        const double expected = brute_force_total(w);
        EXPECT_NEAR(a.total, expected, 1e-9 * std::max(1.0, std::abs(expected)));
      }
    }
  }
}

// Independent reference for medium sizes, where enumeration is too slow: the
// textbook O(n^2 m) Hungarian method with row and column potentials, rescanning
// every column at each step (no initialisation heuristics, no shortcuts).
double reference_total(const WeightMatrix& w) {
  const bool transpose = w.rows > w.cols;
  const int n = transpose ? w.cols : w.rows;
  const int m = transpose ? w.rows : w.cols;
  auto cost = [&](int i, int j) { return transpose ? -w.at(j, i) : -w.at(i, j); };
  const double inf = std::numeric_limits<double>::infinity();
  // 1-based; column 0 is the virtual start of each augmenting path.
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0), dist(m + 1);
  std::vector<int> row_of(m + 1, 0), prev(m + 1, 0);
  std::vector<char> done(m + 1);
  for (int i = 1; i <= n; ++i) {
    row_of[0] = i;
    int j0 = 0;
    std::fill(dist.begin(), dist.end(), inf);
    std::fill(done.begin(), done.end(), 0);
    while (row_of[j0] != 0) {
      done[j0] = 1;
      const int i0 = row_of[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (done[j]) continue;
        const double reduced = cost(i0 - 1, j - 1) - u[i0] - v[j];
        if (reduced < dist[j]) {
          dist[j] = reduced;
          prev[j] = j0;
        }
        if (dist[j] < delta) {
          delta = dist[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (done[j]) {
          u[row_of[j]] += delta;
          v[j] -= delta;
        } else {
          dist[j] -= delta;
        }
      }
      j0 = j1;
    }
    while (j0 != 0) {
      const int j1 = prev[j0];
      row_of[j0] = row_of[j1];
      j0 = j1;
    }
  }
  double total = 0;
  for (int j = 1; j <= m; ++j)
    if (row_of[j] != 0) total -= cost(row_of[j] - 1, j - 1);
  return total;
}

TEST(Assignment, MediumMatricesMatchReferenceHungarian) {
  std::mt19937_64 rng(1987);
  for (int trial = 0; trial < 60; ++trial) {
    const int rows = 10 + static_cast<int>(rng() % 200);
    const int cols = trial % 3 == 0 ? rows : 10 + static_cast<int>(rng() % 200);
    // Integers (exact totals): wide, narrow (many ties) and signed ranges.
    const double lo = trial % 4 == 3 ? -20 : 0;
    const double hi = trial % 4 == 1 ? 3 : 1000;
    const WeightMatrix w = random_matrix(rows, cols, lo, hi, true, rng);
    const Assignment a = max_weight_assignment(w);
    SCOPED_TRACE(testing::Message() << rows << "x" << cols << " [" << lo << ", " << hi << ")");
    expect_valid(w, a);
    EXPECT_EQ(a.total, reference_total(w));
  }
}

// SciPy's linear_sum_assignment(maximize=True) through Debian's interpreter (the
// python3 first on PATH may be another one without SciPy).
constexpr const char* kPython = "/usr/bin/python3";

bool scipy_available() {
  if (!std::filesystem::exists(kPython)) return false;
  const std::string cmd = std::string(kPython) + " -c 'import scipy.optimize' 2>/dev/null";
  return std::system(cmd.c_str()) == 0;
}

// Writes the matrix as text, runs SciPy on it and returns its best total.
double scipy_total(const WeightMatrix& w, const std::string& name) {
  const std::filesystem::path file = test::process_temp_dir() / ("assignment_" + name + ".txt");
  {
    std::ofstream out(file);
    out.precision(17);
    out << w.rows << ' ' << w.cols << '\n';
    for (int r = 0; r < w.rows; ++r) {
      for (int c = 0; c < w.cols; ++c) out << w.at(r, c) << (c + 1 < w.cols ? ' ' : '\n');
    }
  }
  const std::string script =
      "import sys, numpy as np\n"
      "from scipy.optimize import linear_sum_assignment\n"
      "f = open(sys.argv[1]); rows, cols = map(int, f.readline().split())\n"
      "w = np.loadtxt(f, ndmin=2).reshape(rows, cols)\n"
      "r, c = linear_sum_assignment(w, maximize=True)\n"
      "print(repr(float(w[r, c].sum())))\n";
  const std::string cmd =
      std::string(kPython) + " -c '" + script + "' " + file.string();
  std::FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("popen failed");
  std::string output;
  char buffer[256];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  const int status = pclose(pipe);
  std::filesystem::remove(file);
  if (status != 0 || output.empty()) throw std::runtime_error("scipy failed: " + output);
  return std::stod(output);
}

TEST(Assignment, LargeMatricesMatchScipy) {
  if (!scipy_available())
    GTEST_SKIP() << kPython << " with scipy.optimize not found (apt install python3-scipy)";
  struct Case {
    int rows, cols;
    double lo, hi;
    bool integers;
  };
  const Case cases[] = {
      {50, 50, 0, 100, false},    {50, 50, 0, 10, true},      {200, 200, 0, 100, false},
      {200, 200, -100, 100, true}, {300, 120, 0, 100, false}, {120, 300, 0, 100, false},
      {300, 120, -50, 50, false},  {150, 400, 0, 5, true},
  };
  std::mt19937_64 rng(1603);
  int index = 0;
  for (const Case& k : cases) {
    const WeightMatrix w = random_matrix(k.rows, k.cols, k.lo, k.hi, k.integers, rng);
    const Assignment a = max_weight_assignment(w);
    SCOPED_TRACE(testing::Message() << k.rows << "x" << k.cols << " [" << k.lo << ", " << k.hi
                                    << ")" << (k.integers ? " integers" : ""));
    expect_valid(w, a);
    const double expected = scipy_total(w, std::to_string(index++));
    if (k.integers) {
      EXPECT_EQ(a.total, expected);
    } else {
      EXPECT_NEAR(a.total, expected, 1e-9 * std::max(1.0, std::abs(expected)));
    }
  }
}

}  // namespace
}  // namespace annex
