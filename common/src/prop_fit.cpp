#include "annex/common/prop_fit.h"

#include <algorithm>
#include <numeric>

namespace annex {

Affine operator*(const Affine& a, const Affine& b) {
  Affine r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      double s = j == 3 ? a.m[i * 4 + 3] : 0.0;
      for (int k = 0; k < 3; ++k) s += a.m[i * 4 + k] * b.m[k * 4 + j];
      r.m[i * 4 + j] = s;
    }
  }
  return r;
}

Affine affine_from_pose(const Pose& pose) {
  const Vec3 c0 = rotate(pose.rotation, {1, 0, 0});
  const Vec3 c1 = rotate(pose.rotation, {0, 1, 0});
  const Vec3 c2 = rotate(pose.rotation, {0, 0, 1});
  return {{c0.x, c1.x, c2.x, pose.position.x, c0.y, c1.y, c2.y, pose.position.y, c0.z, c1.z,
           c2.z, pose.position.z}};
}

Affine inverse_rigid(const Pose& pose) {
  const Affine f = affine_from_pose(pose);
  Affine r;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) r.m[i * 4 + k] = f.m[k * 4 + i];
  for (int i = 0; i < 3; ++i)
    r.m[i * 4 + 3] = -(r.m[i * 4] * f.m[3] + r.m[i * 4 + 1] * f.m[7] + r.m[i * 4 + 2] * f.m[11]);
  return r;
}

Affine model_from_mesh(const VirtualObject& object) {
  Affine a;
  a.m[0] = a.m[5] = a.m[10] = object.model_scale;
  return a;
}

Quat plane_frame(const PhysicalPrimitive& p, bool swap_sides) {
  const Vec3 z = normalized(p.axis);
  Vec3 x = p.x_axis - z * dot(p.x_axis, z);
  if (norm(x) < 1e-9) x = rotate(rotation_from_z(z), {1, 0, 0});
  x = normalized(x);
  Vec3 y = cross(z, x);
  // The virtual size_x lies along the physical size_y side: turn the frame a quarter.
  if (swap_sides) {
    const Vec3 old_x = x;
    x = y;
    y = old_x * -1.0;
  }
  return rotation_from_axes(x, y, z);
}

Vec3 local_scale_for(const Primitive& p, const std::vector<double>& f) {
  auto at = [&](size_t i) { return i < f.size() ? f[i] : 1.0; };
  switch (p.kind) {
    case ShapeKind::sphere: return {at(0), at(0), at(0)};
    case ShapeKind::cylinder:
    case ShapeKind::cone:
      return {at(0), at(0), at(1)};
    // A torus's tube thickness shows along its axis; the ring spans x and y.
    case ShapeKind::torus: return {at(0), at(0), at(1)};
    case ShapeKind::box: return {at(0), at(1), at(2)};
    // A flat panel scales in its plane; its thickness (none) stays.
    case ShapeKind::plane: return {at(0), at(1), 1};
  }
  return {1, 1, 1};
}

PropFit fit_to_prop(const Primitive& v, const PhysicalPrimitive& p) {
  const size_t n = std::min(v.dimensions.size(), p.dimensions_m.size());
  // Which physical size each virtual dimension takes: the same index, except for
  // boxes and planes, whose sides pair up by size rank (as in the Voter).
  std::vector<size_t> partner(n);
  std::iota(partner.begin(), partner.end(), 0);
  if (v.kind == ShapeKind::box || v.kind == ShapeKind::plane) {
    std::vector<size_t> vi(n), pi(n);
    std::iota(vi.begin(), vi.end(), 0);
    std::iota(pi.begin(), pi.end(), 0);
    std::stable_sort(vi.begin(), vi.end(), [&](size_t a, size_t b) {
      return v.dimensions[a].value_m > v.dimensions[b].value_m;
    });
    std::stable_sort(pi.begin(), pi.end(), [&](size_t a, size_t b) {
      return p.dimensions_m[a] > p.dimensions_m[b];
    });
    for (size_t r = 0; r < n; ++r) partner[vi[r]] = pi[r];
  }
  std::vector<double> wanted(n, 1.0), clamped(n, 1.0);
  PropFit fit;
  for (size_t i = 0; i < n; ++i) {
    const Dimension& d = v.dimensions[i];
    wanted[i] = d.value_m > 0 ? p.dimensions_m[partner[i]] / d.value_m : 1.0;
    clamped[i] = std::clamp(wanted[i], d.min_scale, d.max_scale);
    fit.clamped = fit.clamped || clamped[i] != wanted[i];
  }
  fit.scale = local_scale_for(v, clamped);
  fit.wanted_scale = local_scale_for(v, wanted);

  Pose world_from_local{p.center, rotation_from_z(p.axis)};
  if (v.kind == ShapeKind::plane && p.kind == ShapeKind::plane && n == 2)
    world_from_local.rotation = plane_frame(p, partner[0] == 1);
  Affine scale;
  scale.m[0] = fit.scale.x;
  scale.m[5] = fit.scale.y;
  scale.m[10] = fit.scale.z;
  fit.world_from_model = affine_from_pose(world_from_local) * scale * inverse_rigid(v.pose);
  return fit;
}

}  // namespace annex
