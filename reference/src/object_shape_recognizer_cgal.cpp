// The paper's shape detector for comparison: CGAL 5.5 Efficient RANSAC (Schnabel,
// Wahl & Klein 2007) with plane, sphere, cylinder, cone and torus factories. The
// salient primitive is the detected shape with most assigned points, as in the paper;
// a plane maps to a box whose extents are the points' bounding box along the plane.
// The only CGAL translation unit (it costs ~25 s to compile).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Random.h>
#include <CGAL/Shape_detection/Efficient_RANSAC.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "annex/reference/object_shape_recognizer_cgal.h"

namespace annex {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using Vector3 = Kernel::Vector_3;
using Pwn = std::pair<Point3, Vector3>;
using PwnVector = std::vector<Pwn>;
using PointMap = CGAL::First_of_pair_property_map<Pwn>;
using NormalMap = CGAL::Second_of_pair_property_map<Pwn>;
using Traits =
    CGAL::Shape_detection::Efficient_RANSAC_traits<Kernel, PwnVector, PointMap, NormalMap>;
using Ransac = CGAL::Shape_detection::Efficient_RANSAC<Traits>;
using CPlane = CGAL::Shape_detection::Plane<Traits>;
using CSphere = CGAL::Shape_detection::Sphere<Traits>;
using CCylinder = CGAL::Shape_detection::Cylinder<Traits>;
using CCone = CGAL::Shape_detection::Cone<Traits>;
using CTorus = CGAL::Shape_detection::Torus<Traits>;

Vec3 vec(const Vector3& v) { return {v.x(), v.y(), v.z()}; }
Vec3 vec(const Point3& p) { return {p.x(), p.y(), p.z()}; }

// Extent of the assigned points along an axis through `origin`: (min, max).
std::pair<double, double> extent(const PwnVector& pts, const std::vector<std::size_t>& idx,
                                 Vec3 origin, Vec3 axis) {
  double lo = 1e18, hi = -1e18;
  for (std::size_t i : idx) {
    const double t = dot(vec(pts[i].first) - origin, axis);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  return {lo, hi};
}

}  // namespace

ObjectShape recognize_object_shape_cgal(const std::vector<Vec3>& points,
                                        const std::vector<Vec3>& normals,
                                        const CgalRansacParams& params) {
  ObjectShape out;
  if (points.size() < 20) return out;
  PwnVector pts;
  pts.reserve(points.size());
  const bool have_normals = normals.size() == points.size();
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec3 n = have_normals ? normals[i] : Vec3{0, 0, 1};
    pts.emplace_back(Point3(points[i].x, points[i].y, points[i].z), Vector3(n.x, n.y, n.z));
  }
  if (!have_normals)
    CGAL::jet_estimate_normals<CGAL::Sequential_tag>(
        pts, params.jet_neighbours,
        CGAL::parameters::point_map(PointMap()).normal_map(NormalMap()));

  // CGAL draws from its default generator: seed it so runs repeat.
  CGAL::get_default_random() = CGAL::Random(static_cast<unsigned int>(params.seed));
  Ransac ransac;
  ransac.set_input(pts);
  ransac.add_shape_factory<CPlane>();
  ransac.add_shape_factory<CSphere>();
  ransac.add_shape_factory<CCylinder>();
  ransac.add_shape_factory<CCone>();
  ransac.add_shape_factory<CTorus>();
  Ransac::Parameters rp;
  rp.probability = params.probability;
  rp.min_points = static_cast<std::size_t>(
      std::max<int>(params.min_points, static_cast<int>(points.size() / 20)));
  rp.epsilon = params.epsilon_m;
  rp.cluster_epsilon = params.cluster_epsilon_m;
  rp.normal_threshold = params.normal_threshold;
  ransac.detect(rp);

  struct Found {
    ShapeFit fit;
    std::size_t count = 0;
  };
  std::vector<Found> found;
  for (const auto& shape : ransac.shapes()) {
    const auto& idx = shape->indices_of_assigned_points();
    Found f;
    f.count = idx.size();
    PhysicalPrimitive& p = f.fit.primitive;
    if (const auto* s = dynamic_cast<const CSphere*>(shape.get())) {
      p.kind = ShapeKind::sphere;
      p.dimensions_m = {s->radius()};
      p.center = vec(s->center());
    } else if (const auto* c = dynamic_cast<const CCylinder*>(shape.get())) {
      const Vec3 axis = normalized(vec(c->axis().to_vector()));
      const Vec3 origin = vec(c->axis().point());
      const auto [lo, hi] = extent(pts, idx, origin, axis);
      p.kind = ShapeKind::cylinder;
      p.dimensions_m = {c->radius(), hi - lo};
      p.center = origin + axis * ((lo + hi) / 2);
      p.axis = axis;
    } else if (const auto* k = dynamic_cast<const CCone*>(shape.get())) {
      const Vec3 axis = normalized(vec(k->axis()));
      const Vec3 apex = vec(k->apex());
      const auto [lo, hi] = extent(pts, idx, apex, axis);
      p.kind = ShapeKind::cone;
      p.dimensions_m = {std::max(0.0, hi) * std::tan(k->angle()), std::max(0.0, hi)};
      p.center = apex + axis * (hi / 2);
      p.axis = axis * -1.0;  // ours points from the base to the apex
      (void)lo;
    } else if (const auto* t = dynamic_cast<const CTorus*>(shape.get())) {
      p.kind = ShapeKind::torus;
      p.dimensions_m = {t->major_radius(), t->minor_radius()};
      p.center = vec(t->center());
      p.axis = normalized(vec(t->axis()));
    } else if (const auto* pl = dynamic_cast<const CPlane*>(shape.get())) {
      const Vec3 n = normalized(vec(pl->plane_normal()));
      const Vec3 seed = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
      const Vec3 u = normalized(cross(n, seed)), v = cross(n, u);
      const Vec3 o = vec(pts[idx.front()].first);
      const auto [u0, u1] = extent(pts, idx, o, u);
      const auto [v0, v1] = extent(pts, idx, o, v);
      p.kind = ShapeKind::box;
      p.dimensions_m = {u1 - u0, v1 - v0, 0.0};
      p.center = o + u * ((u0 + u1) / 2) + v * ((v0 + v1) / 2);
      p.axis = n;
      f.fit.x_axis = u;
    } else {
      continue;
    }
    f.fit.coverage = static_cast<double>(f.count) / static_cast<double>(points.size());
    p.fit = f.fit.coverage;
    found.push_back(std::move(f));
  }
  std::stable_sort(found.begin(), found.end(),
                   [](const Found& a, const Found& b) { return a.count > b.count; });
  for (const Found& f : found) {
    out.candidates.push_back(f.fit);
    out.primitives.push_back(f.fit);
  }
  if (!out.primitives.empty()) out.fit = out.primitives.front().coverage;
  return out;
}

}  // namespace annex
