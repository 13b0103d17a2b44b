#include "annex/common/geometry.h"

namespace annex {

Quat rotation_from_z(Vec3 axis) {
  const Vec3 a = normalized(axis);
  const Vec3 z{0, 0, 1};
  const double c = dot(z, a);
  if (c < -1.0 + 1e-12) return {0, 1, 0, 0};  // 180 degrees about X
  const Vec3 v = cross(z, a);
  return normalized(Quat{1.0 + c, v.x, v.y, v.z});
}

}  // namespace annex
