#pragma once
// Small value types for poses in the core library. Eigen stays out of the public
// headers of common/ so formats and the editor compile fast; runtime converts.

#include <cmath>

namespace annex {

struct Vec3 {
  double x = 0, y = 0, z = 0;
  bool operator==(const Vec3&) const = default;
};

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(Vec3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalized(Vec3 a) {
  const double n = norm(a);
  return n > 0 ? a * (1.0 / n) : Vec3{0, 0, 1};
}

// Unit quaternion, w first (the order the .haptic format writes).
struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
  bool operator==(const Quat&) const = default;
};

inline Quat operator*(Quat a, Quat b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
          a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
          a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
inline Quat normalized(Quat q) {
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return n > 0 ? Quat{q.w / n, q.x / n, q.y / n, q.z / n} : Quat{};
}
inline Vec3 rotate(Quat q, Vec3 v) {
  const Vec3 u{q.x, q.y, q.z};
  const Vec3 t = cross(u, v) * 2.0;
  return v + t * q.w + cross(u, t);
}
// Rotation taking +Z onto `axis` (the axis convention of every primitive).
Quat rotation_from_z(Vec3 axis);
// Rotation whose columns are the right-handed orthonormal axes x, y, z.
Quat rotation_from_axes(Vec3 x, Vec3 y, Vec3 z);

// Rigid pose of a primitive relative to its virtual object, or of a physical
// primitive in the sensor frame. A primitive's own axis is its local +Z.
struct Pose {
  Vec3 position;
  Quat rotation;
  bool operator==(const Pose&) const = default;
  Vec3 axis() const { return rotate(rotation, {0, 0, 1}); }
};

}  // namespace annex
