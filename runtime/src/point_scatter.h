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

// `pts` must not be empty.
inline PointScatter point_scatter(const std::vector<Vec3>& pts) {
  PointScatter s;
  for (const Vec3& p : pts) s.mean += Eigen::Vector3d(p.x, p.y, p.z);
  s.mean /= static_cast<double>(pts.size());
  for (const Vec3& p : pts) {
    const Eigen::Vector3d q = Eigen::Vector3d(p.x, p.y, p.z) - s.mean;
    s.scatter += q * q.transpose();
  }
  return s;
}

}  // namespace annex
