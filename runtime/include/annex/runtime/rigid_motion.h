#pragma once
// Rigid motions for prediction and camera motion: composing poses, rotation vectors
// (axis times angle) to scale and blend turns, moving planes and points with the camera.

#include <cmath>

#include "annex/common/geometry.h"
#include "annex/common/physical_scene.h"

namespace annex {

inline Quat conjugate_quat(Quat q) { return {q.w, -q.x, -q.y, -q.z}; }

// a then b: (a * b)(p) = a(b(p)).
inline Pose compose(const Pose& a, const Pose& b) {
  return {a.position + rotate(a.rotation, b.position), normalized(a.rotation * b.rotation)};
}

inline Pose inverse(const Pose& a) {
  const Quat r = conjugate_quat(a.rotation);
  return {rotate(r, a.position * -1.0), r};
}

// Axis times angle (radians) of a unit quaternion, the short way round.
inline Vec3 rotation_vector(Quat q) {
  if (q.w < 0) q = {-q.w, -q.x, -q.y, -q.z};
  const double s = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
  if (s < 1e-12) return {2 * q.x, 2 * q.y, 2 * q.z};
  const double angle = 2 * std::atan2(s, q.w);
  return Vec3{q.x, q.y, q.z} * (angle / s);
}

inline Quat from_rotation_vector(Vec3 v) {
  const double angle = norm(v);
  if (angle < 1e-12) return normalized(Quat{1, v.x / 2, v.y / 2, v.z / 2});
  const double s = std::sin(angle / 2) / angle;
  return {std::cos(angle / 2), v.x * s, v.y * s, v.z * s};
}

// The turn q taken `times` times (fractions allowed).
inline Quat scaled_turn(Quat q, double times) {
  return from_rotation_vector(rotation_vector(q) * times);
}

// A plane n.p + d = 0 after the motion p -> motion(p).
inline Plane transform_plane(const Plane& plane, const Pose& motion) {
  Plane out;
  out.normal = rotate(motion.rotation, plane.normal);
  out.d = plane.d - dot(out.normal, motion.position);
  return out;
}

inline Vec3 transform_point(const Pose& motion, Vec3 p) {
  return motion.position + rotate(motion.rotation, p);
}

}  // namespace annex
