// Flat surfaces for virtual panels (plane_candidates.h): box tops from the recognizer's
// boxes, free rectangles of supports from an occupancy grid on each support's plane.
#include "annex/runtime/plane_candidates.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "annex/runtime/object_shape_recognizer.h"
#include "annex/runtime/scanner.h"

namespace annex {
namespace {

constexpr double kPi = 3.14159265358979323846;

PhysicalObject plane_object(std::string id, Vec3 center, Vec3 normal, Vec3 side_a, double a,
                            Vec3 side_b, double b) {
  // size_x is the longer side, x_axis runs along it.
  if (b > a) {
    std::swap(a, b);
    std::swap(side_a, side_b);
  }
  PhysicalPrimitive p;
  p.kind = ShapeKind::plane;
  p.dimensions_m = {a, b};
  p.center = center;
  p.axis = normalized(normal);
  p.x_axis = normalized(side_a - p.axis * dot(side_a, p.axis));
  PhysicalObject o;
  o.id = std::move(id);
  o.primitives.push_back(p);
  return o;
}

// A box's face for a panel, when it was seen: the broad face of a slab (a book, a
// tablet, a laptop's lid) on the side the camera sees, whichever way it faces; else the
// top face of a box standing on its support.
std::optional<PhysicalObject> box_face(const ScanCluster& sc, const PhysicalObject& object,
                                      const PlaneCandidateParams& params, double band) {
  if (sc.shape.primitives.empty()) return std::nullopt;
  const ShapeFit& fit = sc.shape.primitives.front();
  const PhysicalPrimitive& box = fit.primitive;
  if (box.kind != ShapeKind::box || box.dimensions_m.size() < 3) return std::nullopt;
  const Vec3 up = normalized(sc.support.normal);
  const Vec3 a = normalized(box.axis);
  const Vec3 u = normalized(fit.x_axis - a * dot(fit.x_axis, a));
  const Vec3 axes[3] = {u, cross(a, u), a};
  int thinnest = 0;
  for (int k = 1; k < 3; ++k)
    if (box.dimensions_m[static_cast<size_t>(k)] < box.dimensions_m[static_cast<size_t>(thinnest)])
      thinnest = k;
  const double broad = std::min(box.dimensions_m[static_cast<size_t>((thinnest + 1) % 3)],
                                box.dimensions_m[static_cast<size_t>((thinnest + 2) % 3)]);
  const bool slab = box.dimensions_m[static_cast<size_t>(thinnest)] < params.slab_ratio * broad;
  int top = 0;
  Vec3 n;
  std::string name = ".top";
  if (slab) {
    top = thinnest;
    // The camera is at the sensor frame's origin.
    n = dot(axes[top], box.center) <= 0 ? axes[top] : axes[top] * -1.0;
    if (std::abs(dot(axes[top], up)) < std::cos(params.max_face_tilt_deg * kPi / 180)) name = ".face";
  } else {
    for (int k = 1; k < 3; ++k)
      if (std::abs(dot(axes[k], up)) > std::abs(dot(axes[top], up))) top = k;
    const double c = std::abs(dot(axes[top], up));
    if (c < std::cos(params.max_face_tilt_deg * kPi / 180)) return std::nullopt;
    n = dot(axes[top], up) >= 0 ? axes[top] : axes[top] * -1.0;
  }
  const Vec3 center = box.center + n * (box.dimensions_m[static_cast<size_t>(top)] / 2);
  const int i = (top + 1) % 3, j = (top + 2) % 3;
  const double si = box.dimensions_m[static_cast<size_t>(i)];
  const double sj = box.dimensions_m[static_cast<size_t>(j)];
  if (std::min(si, sj) < params.min_side_m) return std::nullopt;
  // The face was seen: enough of the box's points lie on it.
  int on_face = 0;
  for (const Vec3& q : sc.points) {
    const Vec3 r = q - center;
    on_face += std::abs(dot(r, n)) <= band && std::abs(dot(r, axes[i])) <= si / 2 + band &&
               std::abs(dot(r, axes[j])) <= sj / 2 + band;
  }
  const double share = sc.points.empty() ? 0.0 : static_cast<double>(on_face) / sc.points.size();
  if (share < params.min_face_share) return std::nullopt;
  PhysicalObject o = plane_object(object.id + name, center, n, axes[i], si, axes[j], sj);
  o.point_count = on_face;
  o.fit = share;
  o.support_id = object.support_id;
  o.partial = object.partial;
  return o;
}

// Largest all-true axis-aligned rectangle of a grid (rows x cols), by the histogram
// method: {row0, col0, rows, cols}, rows = 0 when none. Of equally large ones, the one
// whose centre has the smallest `cost` (row, col of the centre doubled).
template <typename Cost>
std::array<int, 4> largest_rectangle(const std::vector<char>& cells, int rows, int cols,
                                     Cost cost) {
  std::vector<int> height(static_cast<size_t>(cols), 0);
  std::array<int, 4> best{0, 0, 0, 0};
  long best_area = 0;
  std::vector<int> stack;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c)
      height[c] = cells[static_cast<size_t>(r) * cols + c] ? height[c] + 1 : 0;
    stack.clear();
    for (int c = 0; c <= cols; ++c) {
      const int h = c < cols ? height[c] : 0;
      while (!stack.empty() && height[stack.back()] >= h) {
        const int top = stack.back();
        stack.pop_back();
        const int left = stack.empty() ? 0 : stack.back() + 1;
        const long area = static_cast<long>(height[top]) * (c - left);
        const std::array<int, 4> here{r - height[top] + 1, left, height[top], c - left};
        if (area > best_area ||
            (area == best_area && area > 0 &&
             cost(2 * here[0] + here[2], 2 * here[1] + here[3]) <
                 cost(2 * best[0] + best[2], 2 * best[1] + best[3]))) {
          best_area = area;
          best = here;
        }
      }
      stack.push_back(c);
    }
  }
  return best;
}

// Chebyshev dilation of a grid by `radius` cells (separable running maximum; the
// column pass walks the rows in memory order, one running "last set row" per column).
std::vector<char> dilate(const std::vector<char>& in, int rows, int cols, int radius) {
  if (radius <= 0) return in;
  std::vector<char> tmp(in.size(), 0), out(in.size(), 0);
  for (int r = 0; r < rows; ++r) {
    const char* row = in.data() + static_cast<size_t>(r) * cols;
    char* dst = tmp.data() + static_cast<size_t>(r) * cols;
    int last = -radius - 1;  // column of the last set cell seen
    for (int c = 0; c < cols + radius; ++c) {
      if (c < cols && row[c]) last = c;
      const int at = c - radius;
      if (at >= 0 && c - last <= 2 * radius) dst[at] = 1;
    }
  }
  std::vector<int> last(static_cast<size_t>(cols), -radius - 1);  // per column
  for (int r = 0; r < rows + radius; ++r) {
    if (r < rows) {
      const char* row = tmp.data() + static_cast<size_t>(r) * cols;
      for (int c = 0; c < cols; ++c)
        if (row[c]) last[static_cast<size_t>(c)] = r;
    }
    const int at = r - radius;
    if (at < 0) continue;
    char* dst = out.data() + static_cast<size_t>(at) * cols;
    for (int c = 0; c < cols; ++c) dst[c] = r - last[static_cast<size_t>(c)] <= 2 * radius;
  }
  return out;
}

std::vector<char> invert(std::vector<char> v) {
  for (char& x : v) x = !x;
  return v;
}

// The support's free rectangle: cells where its surface was seen and nothing stands
// within the clearance, in a grid aligned with the hull's minimum-area rectangle (a
// table's edges).
std::optional<PhysicalObject> free_region(const Frame& frame, const ScanSupport& sp,
                                          const ScanParams& scan_params,
                                          const PlaneCandidateParams& params) {
  if (sp.hull.size() < 3 || params.cell_m <= 0) return std::nullopt;
  const Vec3 n = normalized(sp.surface.plane.normal);
  const double d = sp.surface.plane.d;
  // Minimum-area rectangle: one of its sides lies along a hull edge.
  double best_area = std::numeric_limits<double>::infinity();
  Vec3 e_best{}, origin{};
  double len_e = 0, len_w = 0;
  for (size_t k = 0; k < sp.hull.size(); ++k) {
    Vec3 e = sp.hull[(k + 1) % sp.hull.size()] - sp.hull[k];
    e = e - n * dot(e, n);
    if (norm(e) < 1e-6) continue;
    e = normalized(e);
    const Vec3 w = cross(n, e);
    double lo_e = 1e18, hi_e = -1e18, lo_w = 1e18, hi_w = -1e18;
    for (const Vec3& q : sp.hull) {
      lo_e = std::min(lo_e, dot(q, e)), hi_e = std::max(hi_e, dot(q, e));
      lo_w = std::min(lo_w, dot(q, w)), hi_w = std::max(hi_w, dot(q, w));
    }
    const double area = (hi_e - lo_e) * (hi_w - lo_w);
    if (area < best_area) {
      best_area = area;
      e_best = e;
      len_e = hi_e - lo_e;
      len_w = hi_w - lo_w;
      origin = e * lo_e + w * lo_w - n * d;  // a point of the plane: n.origin + d = 0
    }
  }
  if (!std::isfinite(best_area)) return std::nullopt;
  const Vec3 e = e_best, w = cross(n, e);
  // At most 1000 cells a side: a far floor gets coarser cells.
  const double cell = std::max(params.cell_m, std::max(len_e, len_w) / 1000);
  const int cols = std::max(1, static_cast<int>(std::ceil(len_e / cell)));
  const int rows = std::max(1, static_cast<int>(std::ceil(len_w / cell)));
  // The points on the surface (seen) and above it (blocked) by cell of the full grid,
  // packed as row << 11 | column << 1 | seen (at most 1000 cells a side).
  std::vector<std::uint32_t> hits;
  hits.reserve(frame.points.size() / 2);
  int lo_r = rows, hi_r = -1, lo_c = cols, hi_c = -1;  // the seen cells' bounding box
  // floor(x / cell) when it lies in [0, n): a product with 1 / cell lies within a few
  // ulps of the quotient, so it gives the cell unless it is within 1e-6 of a cell's
  // edge, where the quotient itself decides.
  const double inv_cell = 1 / cell;
  auto cell_of = [&](double x, int n, int& out) {
    const double a = x * inv_cell;
    if (!(a > -1e-6 && a < n + 1e-6)) return false;
    const int k = static_cast<int>(a);
    const double frac = a - k;
    if (frac < 1e-6 || frac > 1 - 1e-6) {
      const double q = x / cell;
      if (!(q >= 0 && q < n)) return false;
      out = static_cast<int>(q);
      return true;
    }
    out = k;
    return true;
  };
  for (const PointXYZRGB& p : frame.points) {
    if (!std::isfinite(p.z) || p.z <= 0 || p.z > scan_params.max_depth_m) continue;
    const Vec3 q{p.x, p.y, p.z};
    const double h = dot(n, q) + d;
    if (h > scan_params.max_height_m) continue;
    const double band =
        std::max(scan_params.plane_distance_m,
                 scan_params.plane_noise_factor * scan_params.depth_noise.sigma_z(p.z));
    if (h < -band) continue;
    const Vec3 r = q - origin;
    int col = 0, row = 0;
    if (!cell_of(dot(r, e), cols, col) || !cell_of(dot(r, w), rows, row)) continue;
    const bool seen = h <= band;
    if (seen) {
      lo_r = std::min(lo_r, row), hi_r = std::max(hi_r, row);
      lo_c = std::min(lo_c, col), hi_c = std::max(hi_c, col);
    }
    hits.push_back(static_cast<std::uint32_t>(row) << 11 | static_cast<std::uint32_t>(col) << 1 |
                   (seen ? 1u : 0u));
  }
  if (hi_r < 0) return std::nullopt;  // no surface cell: no free cell
  // Free cells are seen cells after a closing by one cell, so they lie within the seen
  // cells' box grown by two; an object keeps cells within `clear` free. The grid is
  // cut to that box grown by 2 + clear cells (within the full grid): every cell that
  // can be free sees the same neighbourhood as on the full grid, and the cells beyond
  // the box's 2-cell margin are unseen either way. The largest rectangle's scan meets
  // the same rectangles in the same order (the cut rows and columns hold no free cell).
  const int clear = static_cast<int>(std::ceil(params.clearance_m / cell));
  const int margin = 2 + clear;
  const int r_begin = std::max(0, lo_r - margin), r_end = std::min(rows, hi_r + margin + 1);
  const int c_begin = std::max(0, lo_c - margin), c_end = std::min(cols, hi_c + margin + 1);
  const int crows = r_end - r_begin, ccols = c_end - c_begin;
  std::vector<char> seen(static_cast<size_t>(crows) * ccols, 0), blocked(seen.size(), 0);
  std::vector<int> count(seen.size(), 0);
  for (const std::uint32_t hit : hits) {
    const int row = static_cast<int>(hit >> 11), col = static_cast<int>(hit >> 1 & 1023);
    if (row < r_begin || row >= r_end || col < c_begin || col >= c_end) continue;
    const size_t at = static_cast<size_t>(row - r_begin) * ccols + (col - c_begin);
    if (hit & 1) {
      seen[at] = 1;
      ++count[at];
    } else {
      blocked[at] = 1;  // something stands there, up to the prism's top
    }
  }
  // Close pinholes between the pixels of a surface seen at a slant, then keep clear of
  // whatever stands on it.
  seen = invert(dilate(invert(dilate(seen, crows, ccols, 1)), crows, ccols, 1));
  const std::vector<char> near_object = dilate(blocked, crows, ccols, clear);
  std::vector<char> free_cells(seen.size(), 0);
  for (size_t i = 0; i < seen.size(); ++i) free_cells[i] = seen[i] && !near_object[i];
  // Where the hand reaches: the camera (the user's head) stands over the support's
  // near edge; distances on the plane from the camera's foot (in cells of the cut
  // grid), the nearest free cell the edge the hand arrives at.
  const Vec3 foot = n * -d;  // the camera at the origin, projected onto the plane
  const double fe = dot(foot - origin, e) / cell - c_begin;
  const double fw = dot(foot - origin, w) / cell - r_begin;
  auto reach_cells = [&](double row2, double col2) {  // centre doubled, in cells
    return std::hypot(col2 / 2 - fe, row2 / 2 - fw);
  };
  double nearest = std::numeric_limits<double>::infinity();
  for (int r = 0; r < crows; ++r)
    for (int c = 0; c < ccols; ++c)
      if (free_cells[static_cast<size_t>(r) * ccols + c])
        nearest = std::min(nearest, reach_cells(2 * r + 1, 2 * c + 1));
  std::vector<char> in_reach = free_cells;
  for (int r = 0; r < crows; ++r)
    for (int c = 0; c < ccols; ++c)
      if (reach_cells(2 * r + 1, 2 * c + 1) > nearest + params.reach_m / cell)
        in_reach[static_cast<size_t>(r) * ccols + c] = 0;
  std::array<int, 4> rect = largest_rectangle(in_reach, crows, ccols, reach_cells);
  if (std::min(rect[2], rect[3]) * cell < params.min_side_m)
    rect = largest_rectangle(free_cells, crows, ccols, reach_cells);
  const int r0 = rect[0] + r_begin, c0 = rect[1] + c_begin, nr = rect[2], nc = rect[3];
  const double size_e = nc * cell, size_w = nr * cell;
  if (nr == 0 || std::min(size_e, size_w) < params.min_side_m) return std::nullopt;
  const Vec3 center = origin + e * ((c0 + nc / 2.0) * cell) + w * ((r0 + nr / 2.0) * cell);
  PhysicalObject o =
      plane_object(sp.surface.id + ".free", center, n, e, size_e, w, size_w);
  int points = 0;
  for (int r = r0; r < r0 + nr; ++r)
    for (int c = c0; c < c0 + nc; ++c)
      points += count[static_cast<size_t>(r - r_begin) * ccols + (c - c_begin)];
  o.point_count = points;
  o.fit = 1.0;
  o.support_id = sp.surface.id;
  return o;
}

}  // namespace

std::vector<PhysicalObject> find_plane_candidates(const Frame& frame, const ScanResult& scan,
                                                  const ScanParams& scan_params,
                                                  const PlaneCandidateParams& params) {
  std::vector<PhysicalObject> out;
  for (size_t k = 0; k < scan.clusters.size() && k < scan.scene.objects.size(); ++k) {
    const double z = scan.scene.objects[k].primitives.empty()
                         ? 1.0
                         : scan.scene.objects[k].primitives.front().center.z;
    const double band =
        std::max(scan_params.plane_distance_m,
                 scan_params.plane_noise_factor * scan_params.depth_noise.sigma_z(z));
    if (auto face = box_face(scan.clusters[k], scan.scene.objects[k], params, band))
      out.push_back(std::move(*face));
  }
  const size_t faces = out.size();
  for (const ScanSupport& sp : scan.supports)
    if (sp.selected)
      if (auto region = free_region(frame, sp, scan_params, params)) out.push_back(std::move(*region));
  // A box whose top the scanner also found as a support (a carton's lid of 20 x 20 cm)
  // is reported once, as that support's free region (measured on the plane's points).
  std::vector<PhysicalObject> kept;
  for (size_t i = 0; i < out.size(); ++i) {
    bool repeated = false;
    const PhysicalPrimitive& a = out[i].primitives.front();
    for (size_t j = faces; j < out.size() && i < faces && !repeated; ++j) {
      const PhysicalPrimitive& b = out[j].primitives.front();
      const Vec3 r = a.center - b.center;
      const Vec3 y = cross(b.axis, b.x_axis);
      repeated = std::abs(dot(r, b.axis)) <= scan_params.plane_distance_m * 2 &&
                 std::abs(dot(r, b.x_axis)) <= b.dimensions_m[0] / 2 &&
                 std::abs(dot(r, y)) <= b.dimensions_m[1] / 2;
    }
    if (!repeated) kept.push_back(std::move(out[i]));
  }
  return kept;
}

PhysicalScene scene_with_surfaces(const ScanResult& scan) {
  PhysicalScene scene = scan.scene;
  scene.objects.insert(scene.objects.end(), scan.surfaces.begin(), scan.surfaces.end());
  return scene;
}

}  // namespace annex
