#include "annex/common/geometry.h"

#include <cmath>

namespace annex {

Quat rotation_from_z(Vec3 axis) {
  const Vec3 a = normalized(axis);
  const Vec3 z{0, 0, 1};
  const double c = dot(z, a);
  if (c < -1.0 + 1e-12) return {0, 1, 0, 0};  // 180 degrees about X
  const Vec3 v = cross(z, a);
  return normalized(Quat{1.0 + c, v.x, v.y, v.z});
}

Quat rotation_from_axes(Vec3 x, Vec3 y, Vec3 z) {
  // Shepperd's method: divide by the largest of the four diagonal sums.
  const double t = x.x + y.y + z.z;
  Quat q;
  if (t > 0) {
    const double s = std::sqrt(t + 1.0) * 2;
    q = {0.25 * s, (y.z - z.y) / s, (z.x - x.z) / s, (x.y - y.x) / s};
  } else if (x.x > y.y && x.x > z.z) {
    const double s = std::sqrt(1.0 + x.x - y.y - z.z) * 2;
    q = {(y.z - z.y) / s, 0.25 * s, (y.x + x.y) / s, (z.x + x.z) / s};
  } else if (y.y > z.z) {
    const double s = std::sqrt(1.0 + y.y - x.x - z.z) * 2;
    q = {(z.x - x.z) / s, (y.x + x.y) / s, 0.25 * s, (z.y + y.z) / s};
  } else {
    const double s = std::sqrt(1.0 + z.z - x.x - y.y) * 2;
    q = {(x.y - y.x) / s, (z.x + x.z) / s, (z.y + y.z) / s, 0.25 * s};
  }
  if (q.w < 0) q = {-q.w, -q.x, -q.y, -q.z};  // one of the two equal quaternions
  return normalized(q);
}

}  // namespace annex
