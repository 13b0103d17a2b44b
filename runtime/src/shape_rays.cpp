// Rays against the generators' primitive solids (shape_rays.h).
#include "shape_rays.h"

#include <cmath>
#include <limits>
#include <utility>

namespace annex::shape_rays {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMinT = 1e-6;  // ignore hits at the ray origin

// Smallest root above kMinT of a t^2 + 2 b t + c = 0 that `accept` takes.
template <typename Accept>
void quadratic_hits(double a, double b, double c, Accept accept) {
  if (std::abs(a) < 1e-15) {
    if (std::abs(b) > 1e-15) accept(-c / (2 * b));
    return;
  }
  const double disc = b * b - a * c;
  if (disc < 0) return;
  const double sq = std::sqrt(disc);
  double t0 = (-b - sq) / a, t1 = (-b + sq) / a;
  if (t0 > t1) std::swap(t0, t1);
  if (!accept(t0)) accept(t1);
}

void consider(LocalHit& best, double t, Vec3 normal) {
  if (t > kMinT && t < best.t) best = {t, normal};
}

double torus_sdf(Vec3 p, double major, double minor) {
  const double q = std::hypot(p.x, p.y) - major;
  return std::hypot(q, p.z) - minor;
}

}  // namespace

LocalHit hit_sphere(Vec3 o, Vec3 d, double r) {
  LocalHit h;
  quadratic_hits(dot(d, d), dot(o, d), dot(o, o) - r * r, [&](double t) {
    if (t <= kMinT) return false;
    consider(h, t, normalized(o + d * t));
    return true;
  });
  return h;
}

LocalHit hit_cylinder(Vec3 o, Vec3 d, double r, double height) {
  LocalHit h;
  const double hh = height * 0.5;
  quadratic_hits(d.x * d.x + d.y * d.y, o.x * d.x + o.y * d.y, o.x * o.x + o.y * o.y - r * r,
                 [&](double t) {
                   if (t <= kMinT) return false;
                   const Vec3 p = o + d * t;
                   if (std::abs(p.z) > hh) return false;
                   consider(h, t, normalized(Vec3{p.x, p.y, 0}));
                   return true;
                 });
  if (std::abs(d.z) > 1e-15) {
    for (double zc : {hh, -hh}) {
      const double t = (zc - o.z) / d.z;
      const Vec3 p = o + d * t;
      if (p.x * p.x + p.y * p.y <= r * r) consider(h, t, {0, 0, zc > 0 ? 1.0 : -1.0});
    }
  }
  return h;
}

// Cone with its base (radius r) at z = -height/2 narrowing towards z = +height/2: to
// its apex there, or to a top cap of radius `narrow` (a frustum).
LocalHit hit_cone(Vec3 o, Vec3 d, double r, double height, double narrow) {
  LocalHit h;
  const double hh = height * 0.5;
  const double k = (r - narrow) / height;  // radius lost per metre of height
  const double k2 = k * k;
  const double apex = narrow > 0 ? -hh + r / k : hh;  // z of the (virtual) apex
  const double w0 = apex - o.z;  // distance below the apex at t = 0
  quadratic_hits(d.x * d.x + d.y * d.y - k2 * d.z * d.z, o.x * d.x + o.y * d.y + k2 * w0 * d.z,
                 o.x * o.x + o.y * o.y - k2 * w0 * w0, [&](double t) {
                   if (t <= kMinT) return false;
                   const Vec3 p = o + d * t;
                   const double w = apex - p.z;
                   if (p.z < -hh || p.z > hh || w < 0) return false;
                   consider(h, t, normalized(Vec3{p.x, p.y, k2 * w}));
                   return true;
                 });
  if (std::abs(d.z) > 1e-15) {
    const double t = (-hh - o.z) / d.z;
    const Vec3 p = o + d * t;
    if (p.x * p.x + p.y * p.y <= r * r) consider(h, t, {0, 0, -1});
    if (narrow > 0) {
      const double t1 = (hh - o.z) / d.z;
      const Vec3 q = o + d * t1;
      if (q.x * q.x + q.y * q.y <= narrow * narrow) consider(h, t1, {0, 0, 1});
    }
  }
  return h;
}

// Sphere tracing on the exact signed distance (1-Lipschitz, so it never overshoots),
// started where the ray enters the bounding sphere.
LocalHit hit_torus(Vec3 o, Vec3 d, double major, double minor) {
  LocalHit h;
  const double len = norm(d);
  const Vec3 dn = d * (1.0 / len);
  const double bound = major + minor + 1e-4;
  const double b = dot(o, dn), c = dot(o, o) - bound * bound;
  const double disc = b * b - c;
  if (disc < 0) return h;
  const double s_exit = -b + std::sqrt(disc);
  double s = std::max(0.0, -b - std::sqrt(disc));
  for (int i = 0; i < 512 && s <= s_exit; ++i) {
    const Vec3 p = o + dn * s;
    const double f = torus_sdf(p, major, minor);
    if (f < 1e-7) {
      const double rho = std::max(1e-12, std::hypot(p.x, p.y));
      const double q = rho - major;
      consider(h, s / len, normalized(Vec3{q * p.x / rho, q * p.y / rho, p.z}));
      return h;
    }
    s += f;
  }
  return h;
}

LocalHit hit_box(Vec3 o, Vec3 d, Vec3 half) {
  LocalHit h;
  double t_near = -kInf, t_far = kInf;
  int axis = -1;
  double sign = 0;
  const double oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z}, hh[3] = {half.x, half.y, half.z};
  for (int i = 0; i < 3; ++i) {
    if (std::abs(dd[i]) < 1e-15) {
      if (std::abs(oo[i]) > hh[i]) return h;
      continue;
    }
    double t0 = (-hh[i] - oo[i]) / dd[i], t1 = (hh[i] - oo[i]) / dd[i];
    double s = -1;
    if (t0 > t1) std::swap(t0, t1), s = 1;
    if (t0 > t_near) t_near = t0, axis = i, sign = s;
    t_far = std::min(t_far, t1);
    if (t_near > t_far) return h;
  }
  if (axis < 0) return h;
  Vec3 n;
  (axis == 0 ? n.x : axis == 1 ? n.y : n.z) = sign;
  consider(h, t_near, n);
  return h;
}

}  // namespace annex::shape_rays
