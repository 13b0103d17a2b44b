#pragma once
// Our quaternions to and from Eigen's rotation matrices, for the Eigen-based solvers
// (IcpTracker, camera motion). The quaternion comes back with w >= 0.

#include <Eigen/Dense>

#include "annex/common/geometry.h"

namespace annex {

inline Eigen::Matrix3d to_matrix(Quat q) {
  return Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized().toRotationMatrix();
}

inline Quat to_quat(const Eigen::Matrix3d& r) {
  Eigen::Quaterniond q(r);
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1;
  return {q.w(), q.x(), q.y(), q.z()};
}

}  // namespace annex
