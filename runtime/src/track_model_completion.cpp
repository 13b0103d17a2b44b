// Model completion: the faces of a box its match-time view did not show.
#include "annex/runtime/track_model_completion.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace annex {
namespace {

double coord(Vec3 p, int a) { return a == 0 ? p.x : (a == 1 ? p.y : p.z); }

Vec3 axis_point(int a, double along, int b, double u, int c, double v) {
  double xyz[3] = {0, 0, 0};
  xyz[a] = along;
  xyz[b] = u;
  xyz[c] = v;
  return {xyz[0], xyz[1], xyz[2]};
}

double quantile_abs(const std::vector<Vec3>& points, int a, double q) {
  std::vector<double> v;
  v.reserve(points.size());
  for (const Vec3& p : points) v.push_back(std::abs(coord(p, a)));
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

ModelCompletion complete_tracking_model(TrackingModel& model, const ModelCompletionParams& params) {
  ModelCompletion out;
  // Without normals the tracker cannot tell a face turned away from one in view, so a
  // complete surface would only add points that can never be paired.
  if (model.kind != ShapeKind::box || model.points.size() < 20 ||
      model.normals.size() != model.points.size() || params.surface_points <= 0)
    return out;
  double h[3];
  for (int a = 0; a < 3; ++a) h[a] = std::max(0.005, quantile_abs(model.points, a, params.extent_quantile));
  out.half_extents_m = {h[0], h[1], h[2]};
  const double area = 8 * (h[0] * h[1] + h[1] * h[2] + h[0] * h[2]);
  const double spacing = std::sqrt(area / params.surface_points);
  const double covered2 = std::pow(params.covered_spacings * spacing, 2);
  const std::vector<Vec3> seen = model.points;
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const int nu = std::max(1, static_cast<int>(std::round(2 * h[b] / spacing)));
    const int nv = std::max(1, static_cast<int>(std::round(2 * h[c] / spacing)));
    for (const double side : {-1.0, 1.0}) {
      const Vec3 normal = axis_point(a, side, b, 0, c, 0);
      for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
          // Cell centres: the face's edges are shared with its neighbours' cells.
          const double u = -h[b] + (i + 0.5) * 2 * h[b] / nu;
          const double v = -h[c] + (j + 0.5) * 2 * h[c] / nv;
          const Vec3 p = axis_point(a, side * h[a], b, u, c, v);
          const bool covered = std::any_of(seen.begin(), seen.end(), [&](Vec3 s) {
            const Vec3 d = s - p;
            return dot(d, d) < covered2;
          });
          if (covered) continue;
          model.points.push_back(p);
          model.normals.push_back(normal);
          ++out.added_points;
        }
    }
  }
  for (const Vec3& p : model.points) model.radius_m = std::max(model.radius_m, norm(p));
  return out;
}

}  // namespace annex
