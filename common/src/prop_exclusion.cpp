#include "annex/common/prop_exclusion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace annex {
namespace {

// Half the extent of a primitive's bounds along the unit direction u.
double half_extent(const PhysicalPrimitive& p, Vec3 u) {
  const auto dim = [&](size_t i) { return i < p.dimensions_m.size() ? p.dimensions_m[i] : 0.0; };
  const Vec3 axis = norm(p.axis) > 0 ? normalized(p.axis) : Vec3{0, 0, 1};
  const double c = std::min(1.0, std::abs(dot(axis, u)));
  const double s = std::sqrt(std::max(0.0, 1 - c * c));
  switch (p.kind) {
    case ShapeKind::sphere:
      return dim(0);
    case ShapeKind::cylinder:
    case ShapeKind::cone:
      return c * dim(1) / 2 + s * dim(0);
    case ShapeKind::torus:
      return c * dim(1) + s * (dim(0) + dim(1));
    case ShapeKind::box:
      return c * dim(2) / 2 + s * std::hypot(dim(0), dim(1)) / 2;
    case ShapeKind::plane:  // no thickness: only its tilt raises it
      return s * std::hypot(dim(0), dim(1)) / 2;
  }
  return 0;
}

bool in_range(double v, const SizeRange& r) {
  return (!r.min_m || v >= *r.min_m) && (!r.max_m || v <= *r.max_m);
}

std::string metres(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

std::string describe_exclude_rule(const ExcludeRule& rule) {
  std::string out = "shape " + (rule.shape ? std::string(shape_name(*rule.shape)) : "any");
  for (const SizeRange& r : rule.ranges) {
    out += ", " + r.dimension;
    if (r.min_m) out += " min " + metres(*r.min_m);
    if (r.max_m) out += " max " + metres(*r.max_m);
  }
  return out;
}

double prop_height_m(const PhysicalObject& object, const std::optional<Plane>& support) {
  if (object.primitives.empty()) return 0;
  if (support) {
    const Vec3 n = normalized(support->normal);
    double top = -1e300;
    for (const PhysicalPrimitive& p : object.primitives)
      top = std::max(top, dot(n, p.center) + support->d + half_extent(p, n));
    return std::max(0.0, top);
  }
  const Vec3 up =
      norm(object.primitives[0].axis) > 0 ? normalized(object.primitives[0].axis) : Vec3{0, 0, 1};
  double lo = 1e300, hi = -1e300;
  for (const PhysicalPrimitive& p : object.primitives) {
    const double c = dot(up, p.center), h = half_extent(p, up);
    lo = std::min(lo, c - h);
    hi = std::max(hi, c + h);
  }
  return hi - lo;
}

std::optional<int> excluding_rule(const HapticSpec& spec, const PhysicalObject& object,
                                  const std::optional<Plane>& support) {
  std::optional<double> height;  // computed once, when a rule asks for it
  for (size_t r = 0; r < spec.exclude.size(); ++r) {
    const ExcludeRule& rule = spec.exclude[r];
    for (const PhysicalPrimitive& p : object.primitives) {
      if (rule.shape && *rule.shape != p.kind) continue;
      bool all = true;
      for (const SizeRange& range : rule.ranges) {
        double value = 0;
        if (range.dimension == kPropHeight) {
          if (!height) height = prop_height_m(object, support);
          value = *height;
        } else {
          const int d = dimension_index(p.kind, range.dimension);
          if (d < 0 || static_cast<size_t>(d) >= p.dimensions_m.size()) {
            all = false;
            break;
          }
          value = p.dimensions_m[static_cast<size_t>(d)];
        }
        if (!in_range(value, range)) {
          all = false;
          break;
        }
      }
      if (all) return static_cast<int>(r);
    }
  }
  return std::nullopt;
}

}  // namespace annex
