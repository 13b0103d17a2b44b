// The unit eigenvector of a symmetric positive semi-definite 3x3 matrix (a covariance)
// for its smallest eigenvalue: a surface patch's normal. The eigenvalue is the smallest
// root of the characteristic polynomial by Newton's method from below (monotone there:
// the cubic's inflection, the mean of the roots, lies above its smallest root), the
// vector the largest cross product of two rows of (A - lambda I), whose null space it
// spans. No trig, unlike the closed-form solve of all three eigenvalues. Falls back to
// Eigen's solver when the null space is not a line (two smallest eigenvalues equal).
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace annex {

inline Eigen::Vector3d smallest_eigenvector(const Eigen::Matrix3d& a) {
  const double a00 = a(0, 0), a11 = a(1, 1), a22 = a(2, 2);
  const double a01 = a(0, 1), a02 = a(0, 2), a12 = a(1, 2);
  // det(A - lambda I) = -lambda^3 + c2 lambda^2 - c1 lambda + c0.
  const double c2 = a00 + a11 + a22;
  const double c1 = a00 * a11 + a00 * a22 + a11 * a22 - a01 * a01 - a02 * a02 - a12 * a12;
  const double c0 = a00 * (a11 * a22 - a12 * a12) - a01 * (a01 * a22 - a12 * a02) +
                    a02 * (a01 * a12 - a11 * a02);
  const double scale = std::abs(a00) + std::abs(a11) + std::abs(a22) + std::abs(a01) +
                       std::abs(a02) + std::abs(a12);
  auto full_solve = [&] {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(a);
    return Eigen::Vector3d(es.eigenvectors().col(0));
  };
  if (!(scale > 0) || !std::isfinite(scale)) return full_solve();
  // Start below every root (a PSD matrix's are >= 0; rounding may leave one a little under).
  double lambda = -1e-12 * scale;
  for (int it = 0; it < 60; ++it) {
    const double p = ((-lambda + c2) * lambda - c1) * lambda + c0;
    const double dp = (-3 * lambda + 2 * c2) * lambda - c1;
    if (!(dp < 0)) break;  // at or past a double root: leave it to the full solve's check
    const double step = -p / dp;
    lambda += step;
    if (!(std::abs(step) > 1e-15 * scale)) break;
  }
  const Eigen::Vector3d r0(a00 - lambda, a01, a02), r1(a01, a11 - lambda, a12),
      r2(a02, a12, a22 - lambda);
  const Eigen::Vector3d x01 = r0.cross(r1), x02 = r0.cross(r2), x12 = r1.cross(r2);
  const double n01 = x01.squaredNorm(), n02 = x02.squaredNorm(), n12 = x12.squaredNorm();
  const double best = std::max({n01, n02, n12});
  // The cross product's length is (lambda1 - lambda) (lambda2 - lambda): the rows span a
  // plane, and their cross product is accurate, only when both stand clear of lambda.
  if (!(best > 1e-12 * scale * scale * scale * scale)) return full_solve();
  const Eigen::Vector3d& v = best == n01 ? x01 : best == n02 ? x02 : x12;
  return v / std::sqrt(best);
}

}  // namespace annex
