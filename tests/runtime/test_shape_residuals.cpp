// The shape recognizer's refinement residuals (runtime/src/shape_residuals.h): each
// analytic gradient against a central difference of the residual itself, at random
// parameters and points, and each residual against its geometric definition.
#include "shape_residuals.h"

#include <gtest/gtest.h>

#include <functional>
#include <random>

namespace annex {
namespace {

using namespace shape_residuals;

// Central difference of f at p along each parameter (an independent reference: only
// the residual's value is used).
template <int N, typename F>
Gradient<N> central_difference(const std::array<double, N>& p, F f) {
  Gradient<N> g;
  for (int j = 0; j < N; ++j) {
    const double step = 1e-6 * std::max(1.0, std::abs(p[j]));
    std::array<double, N> hi = p, lo = p;
    hi[j] += step;
    lo[j] -= step;
    g[j] = (f(hi) - f(lo)) / (2 * step);
  }
  return g;
}

// Checks `residual(p, g)` at `trials` random parameter sets from `draw`: the gradient
// matches the central difference to 1e-6 relative to its size, and asking for the
// gradient does not change the value.
template <int N, typename Draw, typename Residual>
void expect_gradient_matches(Draw draw, Residual residual, int trials = 200) {
  std::mt19937_64 rng(7);
  for (int t = 0; t < trials; ++t) {
    const std::array<double, N> p = draw(rng);
    Gradient<N> analytic;
    const double with = residual(p, &analytic);
    const double without = residual(p, static_cast<Gradient<N>*>(nullptr));
    EXPECT_EQ(with, without);
    const Gradient<N> numeric =
        central_difference<N>(p, [&](const std::array<double, N>& q) { return residual(q, nullptr); });
    const double scale = std::max(1.0, numeric.norm());
    EXPECT_LT((analytic - numeric).norm(), 1e-6 * scale)
        << "trial " << t << ": analytic " << analytic.transpose() << " numeric " << numeric.transpose();
  }
}

std::uniform_real_distribution<double> unit(-1.0, 1.0);

TEST(ShapeResiduals, CircleGradientMatchesCentralDifference) {
  const double qa = 0.031, qb = -0.047;
  expect_gradient_matches<3>(
      [](std::mt19937_64& rng) { return std::array<double, 3>{0.1 * unit(rng), 0.1 * unit(rng), 0.02 + 0.1 * std::abs(unit(rng))}; },
      [&](const std::array<double, 3>& p, Gradient<3>* g) { return circle(p, qa, qb, g); });
}

TEST(ShapeResiduals, ConeGradientMatchesCentralDifference) {
  std::mt19937_64 pts(11);
  const double qa = 0.05 * unit(pts), qb = 0.05 * unit(pts), t = 0.5 + 0.5 * unit(pts), span = 0.18;
  expect_gradient_matches<4>(
      [](std::mt19937_64& rng) {
        return std::array<double, 4>{0.02 * unit(rng), 0.02 * unit(rng), 0.05 + 0.04 * unit(rng),
                                     0.05 + 0.04 * unit(rng)};
      },
      [&](const std::array<double, 4>& p, Gradient<4>* g) { return cone(p, qa, qb, t, span, g); });
}

TEST(ShapeResiduals, SphereGradientsMatchCentralDifference) {
  const double qa = 0.02, qb = -0.03, qh = 0.05;
  expect_gradient_matches<4>(
      [](std::mt19937_64& rng) {
        return std::array<double, 4>{0.05 * unit(rng), 0.05 * unit(rng), 0.05 * unit(rng), 0.05 + 0.04 * unit(rng)};
      },
      [&](const std::array<double, 4>& p, Gradient<4>* g) { return sphere(p, qa, qb, qh, g); });
  // Resting: the radius parameter on either side of 0 (its absolute value is the radius).
  expect_gradient_matches<3>(
      [](std::mt19937_64& rng) {
        const double r = 0.02 + 0.06 * std::abs(unit(rng));
        return std::array<double, 3>{0.05 * unit(rng), 0.05 * unit(rng), unit(rng) < 0 ? -r : r};
      },
      [&](const std::array<double, 3>& p, Gradient<3>* g) { return resting_sphere(p, qa, qb, qh, g); });
}

TEST(ShapeResiduals, TorusGradientMatchesCentralDifference) {
  const double qa = 0.07, qb = 0.01, qh = 0.012;
  expect_gradient_matches<4>(
      [](std::mt19937_64& rng) {
        const double minor = 0.006 + 0.01 * std::abs(unit(rng));
        return std::array<double, 4>{0.02 * unit(rng), 0.02 * unit(rng), 0.04 + 0.02 * unit(rng),
                                     unit(rng) < 0 ? -minor : minor};
      },
      [&](const std::array<double, 4>& p, Gradient<4>* g) { return torus(p, qa, qb, qh, g); });
}

TEST(ShapeResiduals, LyingCircleGradientMatchesCentralDifference) {
  const double w = 0.013, h = 0.041;
  expect_gradient_matches<2>(
      [](std::mt19937_64& rng) {
        const double r = 0.02 + 0.04 * std::abs(unit(rng));
        return std::array<double, 2>{0.03 * unit(rng), unit(rng) < 0 ? -r : r};
      },
      [&](const std::array<double, 2>& p, Gradient<2>* g) { return lying_circle(p, w, h, g); });
}

// The box outline's rectangle, at points inside, outside across a side and beyond a
// corner (random centres, azimuths and sides, points away from the kinks: the diagonals
// inside, the side lines' extensions outside, where no single gradient exists).
TEST(ShapeResiduals, RectangleGradientMatchesCentralDifference) {
  for (const auto& q : {std::array<double, 2>{0.011, -0.004}, std::array<double, 2>{0.09, 0.013},
                        std::array<double, 2>{-0.11, 0.083}}) {
    expect_gradient_matches<5>(
        [](std::mt19937_64& rng) {
          return std::array<double, 5>{0.005 * unit(rng), 0.005 * unit(rng), 0.3 * unit(rng),
                                       0.05 + 0.004 * unit(rng), 0.03 + 0.004 * unit(rng)};
        },
        [&](const std::array<double, 5>& p, Gradient<5>* g) { return rectangle(p, q[0], q[1], g); });
  }
}

// The values are the geometric distances they stand for.
TEST(ShapeResiduals, ValuesAreTheShapesDistances) {
  // A point 3 cm outside a 5 cm circle.
  EXPECT_NEAR(circle({0.01, 0.02, 0.05}, 0.01 + 0.08, 0.02, nullptr), 0.03, 1e-12);
  // A cylinder (equal radii) is its circle at every height.
  EXPECT_NEAR(cone({0, 0, 0.04, 0.04}, 0.0, 0.05, 0.7, 0.2, nullptr), 0.01, 1e-12);
  // A 45-degree cone: radius 0.1 at t = 0, 0 at t = 1 over a 0.1 m span; the point on
  // the axis at the base is 0.1 m in from the side radially, 0.1 / sqrt(2) across it.
  EXPECT_NEAR(cone({0, 0, 0.1, 0.0}, 0.0, 0.0, 0.0, 0.1, nullptr), -0.1 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(sphere({0, 0, 0.05, 0.05}, 0.0, 0.0, 0.0, nullptr), 0.0, 1e-12);
  // Resting sphere of radius 4 cm: its top at 8 cm.
  EXPECT_NEAR(resting_sphere({0, 0, -0.04}, 0.0, 0.0, 0.09, nullptr), 0.01, 1e-12);
  // Torus major 5 cm, minor 1 cm: its outer equator at 6 cm, 1 cm up.
  EXPECT_NEAR(torus({0, 0, 0.05, 0.01}, 0.06, 0.0, 0.01, nullptr), 0.0, 1e-12);
  // Lying cylinder of radius 3 cm: its top at 6 cm.
  EXPECT_NEAR(lying_circle({0.0, 0.03}, 0.0, 0.065, nullptr), 0.005, 1e-12);
  // Rectangle 10 x 6 cm turned 90 degrees: its x side along b. A point 1 cm inside its
  // long side, one 2 cm out across its short side, one 3-4-5 beyond a corner.
  const double quarter = std::acos(0.0);
  EXPECT_NEAR(rectangle({0, 0, quarter, 0.05, 0.03}, 0.02, 0.0, nullptr), -0.01, 1e-12);
  EXPECT_NEAR(rectangle({0, 0, quarter, 0.05, 0.03}, 0.0, 0.07, nullptr), 0.02, 1e-12);
  EXPECT_NEAR(rectangle({0, 0, quarter, 0.05, 0.03}, 0.07, 0.08, nullptr), 0.05, 1e-12);
}

// The 4x-angle moments without trig against cos and sin of 4 atan2, any length, every quadrant.
TEST(ShapeResiduals, FourfoldMatchesTrig) {
  std::mt19937_64 rng(3);
  for (int t = 0; t < 1000; ++t) {
    const double x = unit(rng) * (t % 3 + 0.5), y = unit(rng) * (t % 5 + 0.5);
    const double phi = std::atan2(y, x);
    const auto [c4, s4] = fourfold(x, y);
    EXPECT_NEAR(c4, std::cos(4 * phi), 1e-12);
    EXPECT_NEAR(s4, std::sin(4 * phi), 1e-12);
  }
  const auto [c0, s0] = fourfold(0, 0);
  EXPECT_EQ(c0, 1.0);
  EXPECT_EQ(s0, 0.0);
}

}  // namespace
}  // namespace annex
