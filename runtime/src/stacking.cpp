// Objects standing on objects (stacking.h).
#include "stacking.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "quantile.h"

namespace annex {

void fit_stacked_objects(std::vector<StackedObject>& objects, const Plane& support,
                         const ShapeRecognizerParams& params, double band_m) {
  const Vec3 n = normalized(support.normal);
  const double d = support.d / norm(support.normal);
  const size_t count = objects.size();
  std::vector<double> base(count), top(count);
  for (size_t k = 0; k < count; ++k) {
    std::vector<double> h;
    for (const Vec3& p : objects[k].points) h.push_back(dot(n, p) + d);
    base[k] = quantile(h, 0.03);
    top[k] = quantile(h, 0.98);
  }
  for (size_t u = 0; u < count; ++u) {
    StackedObject& up = objects[u];
    if (base[u] < band_m || up.points.size() < 30) continue;
    // The object's bottom points, lowered by the band, must fall inside the solid of
    // the object below (grown by half the band): it stands on that object's top.
    int best = -1;
    double best_share = 0.5;
    for (size_t l = 0; l < count; ++l) {
      if (l == u || objects[l].shape.primitives.empty()) continue;
      if (std::abs(base[u] - top[l]) > band_m) continue;
      const ShapeFit& below = objects[l].shape.primitives.front();
      size_t bottom = 0, inside = 0;
      for (const Vec3& p : up.points) {
        if (dot(n, p) + d > base[u] + band_m / 3) continue;
        ++bottom;
        inside += within_shape(below, p - n * band_m, band_m / 2);
      }
      const double share = bottom ? static_cast<double>(inside) / bottom : 0.0;
      if (share > best_share) {
        best_share = share;
        best = static_cast<int>(l);
      }
    }
    if (best < 0) continue;
    up.rests_on = best;
    // The lower object's top face as the plane: n.x + d - top = 0.
    const Plane face{n, d - top[best]};
    ObjectShape refit = recognize_object_shape(up.points, up.normals, face, params);
    if (!refit.primitives.empty()) up.shape = std::move(refit);
  }
}

std::vector<int> objects_under_supports(const std::vector<std::vector<int>>& surface_pixels,
                                        const std::vector<int>& label, double min_share) {
  std::vector<int> owner(surface_pixels.size(), -1);
  for (size_t k = 0; k < surface_pixels.size(); ++k) {
    std::map<int, size_t> count;
    for (int i : surface_pixels[k])
      if (i >= 0 && static_cast<size_t>(i) < label.size() && label[static_cast<size_t>(i)] >= 0)
        ++count[label[static_cast<size_t>(i)]];
    for (const auto& [c, n] : count)
      if (!surface_pixels[k].empty() && n >= min_share * surface_pixels[k].size()) owner[k] = c;
  }
  return owner;
}

}  // namespace annex
