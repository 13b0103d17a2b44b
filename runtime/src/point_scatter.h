// The mean of points and their scatter about it (the sum of the offsets' outer
// products): a least-squares plane passes through the mean, its normal the scatter's
// eigenvector of the smallest eigenvalue. Private to the runtime library.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "annex/common/geometry.h"

namespace annex {

struct PointScatter {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
};

// The sums run on plain doubles, each entry the same products added in the same order as
// Eigen's `scatter += q * q.transpose()` (so the same bits), some five times faster: the
// plane fits of the serial plane stage sum tens of thousands of points.
// `pts` must not be empty.
inline PointScatter point_scatter(const std::vector<Vec3>& pts) {
  double mx = 0, my = 0, mz = 0;
  for (const Vec3& p : pts) mx += p.x, my += p.y, mz += p.z;
  const double n = static_cast<double>(pts.size());
  mx /= n, my /= n, mz /= n;
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  for (const Vec3& p : pts) {
    const double x = p.x - mx, y = p.y - my, z = p.z - mz;
    xx += x * x, xy += x * y, xz += x * z, yy += y * y, yz += y * z, zz += z * z;
  }
  PointScatter s;
  s.mean = {mx, my, mz};
  s.scatter << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  return s;
}

// The same with a weight per point: the weighted mean and the sum of each offset's
// outer product times its weight (the entries (w q_i) q_j, as Eigen's
// `w * q * q.transpose()` forms them), and the weights' sum.
struct WeightedScatter {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  double weight = 0;
};

// `pts` and `w` of one size, not empty, the weights' sum positive.
inline WeightedScatter weighted_point_scatter(const std::vector<Vec3>& pts,
                                              const std::vector<double>& w) {
  WeightedScatter s;
  double mx = 0, my = 0, mz = 0;
  for (size_t k = 0; k < pts.size(); ++k) {
    mx += w[k] * pts[k].x, my += w[k] * pts[k].y, mz += w[k] * pts[k].z;
    s.weight += w[k];
  }
  mx /= s.weight, my /= s.weight, mz /= s.weight;
  double m[3][3] = {};
  for (size_t k = 0; k < pts.size(); ++k) {
    const double o[3] = {pts[k].x - mx, pts[k].y - my, pts[k].z - mz};
    for (int i = 0; i < 3; ++i) {
      const double wo = w[k] * o[i];
      for (int j = 0; j < 3; ++j) m[i][j] += wo * o[j];
    }
  }
  s.mean = {mx, my, mz};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s.scatter(i, j) = m[i][j];
  return s;
}

}  // namespace annex
