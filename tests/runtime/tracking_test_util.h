#pragma once
// Shared by the tracking tests: synthetic sequences with ground-truth object poses.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "annex/runtime/icp_tracker.h"
#include "annex/runtime/synthetic_scene.h"

namespace annex::test {

// The object frame of synthetic object `i` at `frame` in camera coordinates: centre,
// +Z up along its axis, +X along its yawed local x (box size_x).
inline Pose truth_pose(const SyntheticScene& scene, int i, int frame) {
  const SyntheticScene s = scene_at_frame(scene, frame);
  const SyntheticObject& o = s.objects[static_cast<size_t>(i)];
  const double yaw = o.yaw_deg * std::numbers::pi / 180.0;
  const Vec3 x = table_to_camera_direction(s, {std::cos(yaw), std::sin(yaw), 0});
  const Vec3 z = table_to_camera_direction(s, {0, 0, 1});
  return {table_to_camera_point(s, o.center), quat_from_axes(x, cross(z, x), z)};
}

// Rotation error modulo the shape's symmetry: none for spheres, the axis angle for
// cylinders, cones and tori, the smallest angle over the box's four turns of 180
// degrees about its axes otherwise.
inline double rotation_error_deg(ShapeKind kind, Quat truth, Quat tracked) {
  switch (symmetry_of(kind)) {
    case Symmetry::spherical:
      return 0;
    case Symmetry::axial: {
      const Vec3 a = rotate(truth, {0, 0, 1}), b = rotate(tracked, {0, 0, 1});
      return std::acos(std::clamp(dot(a, b), -1.0, 1.0)) * 180.0 / std::numbers::pi;
    }
    case Symmetry::none:
      break;
  }
  double best = 360;
  const Quat flips[] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  for (const Quat& f : flips) best = std::min(best, rotation_angle_deg(truth * f, tracked));
  return best;
}

inline double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace annex::test
