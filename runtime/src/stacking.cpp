// Objects standing on objects (stacking.h).
#include "stacking.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>

#include "quantile.h"

namespace annex {

namespace {

// The ring round a foot is read in this many directions (sectors), each needing
// kSectorMinPoints points for its fall to count.
constexpr int kSectors = 8;
constexpr int kSectorMinPoints = 4;

// Horizontal offset of p from the support's normal through `origin`.
Vec3 across(Vec3 p, Vec3 origin, Vec3 n) {
  const Vec3 v = p - origin;
  return v - n * dot(n, v);
}

// Sums of the distances r from a foot's centre and the heights h of the points in one
// sector of the ring round it.
struct RingSums {
  double r = 0, h = 0, rr = 0, rh = 0, hh = 0;
  int count = 0;
};

// The ring from lo to hi metres round `centre` (horizontally), heights from `floor_h`
// up, per sector: every object's points but objects[u]'s.
std::array<RingSums, kSectors> ring_sectors(const std::vector<StackedObject>& objects, size_t u,
                                            Vec3 centre, Vec3 n, double d, double lo, double hi,
                                            double floor_h) {
  std::array<RingSums, kSectors> sector{};
  const Vec3 e1 = normalized(across(centre + Vec3{1, 0, 0}, centre, n)), e2 = cross(n, e1);
  for (size_t k = 0; k < objects.size(); ++k) {
    if (k == u) continue;
    for (const Vec3& p : objects[k].points) {
      const Vec3 v = across(p, centre, n);
      const double h = dot(n, p) + d, r = norm(v);
      if (r < lo || r > hi || h < floor_h) continue;
      const double turn = std::atan2(dot(v, e2), dot(v, e1)) / (2 * std::numbers::pi) + 0.5;
      RingSums& s =
          sector[static_cast<size_t>(std::min(kSectors - 1, static_cast<int>(turn * kSectors)))];
      ++s.count, s.r += r, s.h += h, s.rr += r * r, s.rh += r * h, s.hh += h * h;
    }
  }
  return sector;
}

// Whether a sector's points fall away from the foot at a shoulder's angle: their
// principal direction between min_slope_deg and max_slope_deg below level, and their
// least-squares fall (height on distance) min_fall_t standard errors clear of level.
bool falls_away(const RingSums& s, const NeckParams& neck) {
  const double vr = s.rr - s.r * s.r / s.count, vh = s.hh - s.h * s.h / s.count;
  const double c = s.rh - s.r * s.h / s.count;
  if (!(vr > 0)) return false;
  const double fall_deg = -0.5 * std::atan2(2 * c, vr - vh) * 180 / std::numbers::pi;
  const double slope = c / vr;
  const double residual = std::max(0.0, vh - slope * c) / std::max(1, s.count - 2);
  return -slope > neck.min_fall_t * std::sqrt(residual / vr) && fall_deg > neck.min_slope_deg &&
         fall_deg < neck.max_slope_deg;
}

// Whether objects[u], whose foot is at height `base` over the support (normal n, offset
// d) and which stands on objects[below], rises from a slope (NeckParams): it is narrow
// against the lower object and stands on its axis, and over a ring just beyond its
// foot's reach the other objects' points fall away from it (falls_away) in two thirds
// of the directions seen, at least two. A shoulder falls away all round; a lid is level,
// and beyond a lid's edge the lower object's wall is upright. Every other object's
// points count, not only the one below's: a shoulder may be clustered apart from its
// bottle's body.
bool rises_from_slope(const std::vector<StackedObject>& objects, size_t u, size_t below, Vec3 n,
                      double d, double base, double band_m, const NeckParams& neck) {
  std::vector<Vec3> foot;
  for (const Vec3& p : objects[u].points)
    if (dot(n, p) + d <= base + band_m / 3) foot.push_back(p);
  if (foot.empty() || !(neck.max_width_share > 0) || objects[u].shape.primitives.empty())
    return false;
  // The foot's centre on the upper shape's axis (the centroid of the points seen lies
  // towards the camera: a round foot shows its front half).
  const Vec3 centre = objects[u].shape.primitives.front().primitive.center;
  std::vector<double> reach, width;
  for (const Vec3& p : foot) reach.push_back(norm(across(p, centre, n)));
  for (const Vec3& p : objects[below].points) width.push_back(norm(across(p, centre, n)));
  const double rho = quantile(reach, 0.9), wide = quantile(width, 0.9);
  if (rho > neck.max_width_share * wide) return false;
  // A neck rises on its body's axis (a stacked object stands anywhere on a top).
  const PhysicalPrimitive& body = objects[below].shape.primitives.front().primitive;
  if (norm(across(body.center, centre, n)) > neck.max_off_axis_share * wide) return false;
  const double lo = rho + neck.ring_gap_m;
  const double hi = lo + std::min(neck.ring_width_m, 0.5 * (wide - rho));
  const std::array<RingSums, kSectors> sector =
      ring_sectors(objects, u, centre, n, d, lo, hi, base - band_m);
  int count = 0, seen = 0, falling = 0;
  for (const RingSums& s : sector) {
    count += s.count;
    if (s.count < kSectorMinPoints) continue;
    ++seen;
    falling += falls_away(s, neck);
  }
  return count >= neck.ring_min_points && seen >= 2 && 3 * falling >= 2 * seen;
}

}  // namespace

void fit_stacked_objects(std::vector<StackedObject>& objects, const Plane& support,
                         const ShapeRecognizerParams& params, double band_m,
                         const NeckParams& neck) {
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
    if (rises_from_slope(objects, u, static_cast<size_t>(best), n, d, base[u], band_m, neck)) {
      up.part_of = best;
      continue;
    }
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
