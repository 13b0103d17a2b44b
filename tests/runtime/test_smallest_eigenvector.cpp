// smallest_eigenvector (runtime/src/smallest_eigenvector.h), the MLS normal's solve,
// against Eigen's iterative SelfAdjointEigenSolver on random covariances: flat patches
// (one small eigenvalue), elongated ones, near-isotropic ones, and degenerate matrices.
#include "smallest_eigenvector.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace annex {
namespace {

// A random rotation times diag(l0, l1, l2) times its transpose, offset like a patch
// 1.5 m away (the covariance of points there: sums of squares minus the mean's square).
Eigen::Matrix3d covariance(std::mt19937_64& rng, double l0, double l1, double l2) {
  std::normal_distribution<double> g(0, 1);
  const Eigen::Matrix3d q = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
  return q * Eigen::Vector3d(l0, l1, l2).asDiagonal() * q.transpose();
}

void expect_matches_reference(const Eigen::Matrix3d& a, double tolerance) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> reference(a);
  const Eigen::Vector3d want = reference.eigenvectors().col(0);
  const Eigen::Vector3d got = smallest_eigenvector(a);
  EXPECT_NEAR(got.norm(), 1.0, 1e-12);
  // Same line (either sign): the cross product's length is the angle's sine.
  EXPECT_LT(got.cross(want).norm(), tolerance) << a;
  EXPECT_LT((a * got - reference.eigenvalues()(0) * got).norm(),
            tolerance * reference.eigenvalues()(2) + 1e-18) << a;
}

TEST(SmallestEigenvector, MatchesFullSolverOnPatchCovariances) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int t = 0; t < 2000; ++t) {
    const double spread = 1e-4 * (0.1 + u(rng));  // (1 cm)^2 across the patch
    const double noise = spread * std::pow(10.0, -6 * u(rng));  // down to a perfect plane
    expect_matches_reference(covariance(rng, noise, spread * (0.05 + u(rng)), spread), 1e-8);
  }
}

TEST(SmallestEigenvector, NearIsotropicAndElongated) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  for (int t = 0; t < 500; ++t) {
    // Smallest eigenvalue clearly apart (10 %) from two nearly equal others, and a line
    // (two small, one large) with the smallest 1 % under the middle one.
    expect_matches_reference(covariance(rng, 0.9e-4, 1e-4 * (1 + 1e-3 * u(rng)), 1e-4), 1e-8);
    expect_matches_reference(covariance(rng, 0.99e-6, 1e-6, 1e-4 * (1 + u(rng))), 1e-6);
  }
}

TEST(SmallestEigenvector, DegenerateMatricesGiveAUnitVector) {
  std::mt19937_64 rng(2);
  for (const Eigen::Matrix3d& a :
       {Eigen::Matrix3d(Eigen::Matrix3d::Zero()), Eigen::Matrix3d(Eigen::Matrix3d::Identity()),
        covariance(rng, 0, 0, 1e-4), covariance(rng, 1e-6, 1e-6, 1e-4)}) {
    const Eigen::Vector3d v = smallest_eigenvector(a);
    EXPECT_NEAR(v.norm(), 1.0, 1e-12) << a;
    // An eigenvector of the smallest eigenvalue, whichever of the equal ones.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> reference(a);
    EXPECT_LT((a * v - reference.eigenvalues()(0) * v).norm(), 1e-8 * reference.eigenvalues()(2) + 1e-15)
        << a;
  }
}

}  // namespace
}  // namespace annex
