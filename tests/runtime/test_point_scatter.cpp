// point_scatter and weighted_point_scatter (runtime/src/point_scatter.h), the plane fits'
// sums on plain doubles, against the Eigen expressions they replace: the same bits on
// random clouds of every size, so a fit's plane (and every scan) is what it was.
#include "point_scatter.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace annex {
namespace {

// A patch 0.5 to 3 m away, a few centimetres to a metre across.
std::vector<Vec3> random_cloud(std::mt19937_64& rng, size_t n) {
  std::uniform_real_distribution<double> centre(0.5, 3.0), spread(0.02, 1.0), unit(-1, 1);
  const double z = centre(rng), s = spread(rng);
  std::vector<Vec3> pts(n);
  for (Vec3& p : pts) p = {s * unit(rng), s * unit(rng), z + 0.1 * s * unit(rng)};
  return pts;
}

bool same_bits(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * 9) == 0;
}

bool same_bits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * 3) == 0;
}

TEST(PointScatter, SameBitsAsEigensOuterProducts) {
  std::mt19937_64 rng(11);
  for (size_t n : {1, 2, 3, 7, 50, 999, 25000}) {
    const std::vector<Vec3> pts = random_cloud(rng, n);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const Vec3& p : pts) mean += Eigen::Vector3d(p.x, p.y, p.z);
    mean /= static_cast<double>(pts.size());
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const Vec3& p : pts) {
      const Eigen::Vector3d q = Eigen::Vector3d(p.x, p.y, p.z) - mean;
      scatter += q * q.transpose();
    }
    const PointScatter got = point_scatter(pts);
    EXPECT_TRUE(same_bits(got.mean, mean)) << n << " points";
    EXPECT_TRUE(same_bits(got.scatter, scatter)) << n << " points:\n"
                                                 << got.scatter << "\n"
                                                 << scatter;
  }
}

TEST(PointScatter, WeightedSameBitsAsEigensOuterProducts) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> weight(50, 5e5);
  for (size_t n : {1, 2, 3, 7, 50, 999, 25000}) {
    const std::vector<Vec3> pts = random_cloud(rng, n);
    std::vector<double> w(n);
    for (double& x : w) x = weight(rng);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    double sum = 0;
    for (size_t k = 0; k < n; ++k) {
      mean += w[k] * Eigen::Vector3d(pts[k].x, pts[k].y, pts[k].z);
      sum += w[k];
    }
    mean /= sum;
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (size_t k = 0; k < n; ++k) {
      const Eigen::Vector3d o = Eigen::Vector3d(pts[k].x, pts[k].y, pts[k].z) - mean;
      scatter += w[k] * o * o.transpose();
    }
    const WeightedScatter got = weighted_point_scatter(pts, w);
    EXPECT_EQ(got.weight, sum);
    EXPECT_TRUE(same_bits(got.mean, mean)) << n << " points";
    EXPECT_TRUE(same_bits(got.scatter, scatter)) << n << " points:\n"
                                                 << got.scatter << "\n"
                                                 << scatter;
  }
}

}  // namespace
}  // namespace annex
