// Furniture and room surfaces told from props (furniture_rules.h).
#include "furniture_rules.h"

#include "annex/runtime/object_shape_recognizer.h"
#include "point_scatter.h"
#include "smallest_eigenvector.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace annex {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 at(const Frame& f, int i) {
  const PointXYZRGB& p = f.points[static_cast<size_t>(i)];
  return {p.x, p.y, p.z};
}

// Grid rows runs_below_support follows a face down past its lowest pixel to the
// support's edge: a chair's back 10 cm behind the table 1.5 m away spans 20 grid rows.
constexpr int kBelowRows = 32;
// How flat a support's surface is beyond the depth noise: a table top, and the Kinect's
// own depth distortion over the few centimetres runs_below_support looks at.
constexpr double kFlatSurface = 0.003;

}  // namespace

std::vector<std::pair<int, int>> end_per_column(const Frame& f, const std::vector<int>& grid,
                                                bool top) {
  std::vector<std::pair<int, int>> ends;
  if (grid.empty()) return ends;
  int lo = f.width, hi = -1;
  for (int i : grid) lo = std::min(lo, i % f.width), hi = std::max(hi, i % f.width);
  std::vector<int> end(static_cast<size_t>(hi - lo + 1), -1);  // per column from lo
  for (int i : grid) {
    int& e = end[static_cast<size_t>(i % f.width - lo)];
    if (e < 0 || (top ? i < e : i > e)) e = i;
  }
  for (size_t c = 0; c < end.size(); ++c)
    if (end[c] >= 0) ends.emplace_back(lo + static_cast<int>(c), end[c]);
  return ends;
}

bool top_cut_by_band(const Frame& f, const std::vector<int>& grid, int step, Vec3 n, double d,
                     const ScanParams& params, const ToleranceAt& tolerance) {
  if (params.cut_top_share <= 0) return false;
  const std::vector<std::pair<int, int>> top = end_per_column(f, grid, true);
  // Too few columns to tell a cut front from noise.
  if (top.size() < 3) return false;
  const int row = step * f.width;
  size_t cut = 0, at_top = 0;
  for (const auto& [col, i] : top) {
    const Vec3 p = at(f, i);
    const double tol = tolerance(p.z);
    // Only a column whose topmost pixel lies at the band's top can show the cut: where
    // the silhouette's side crosses the column (a post slanted in the image by the view),
    // its top there is a side's edge, lower.
    if (dot(n, p) + d < params.max_height_m - tol) continue;
    ++at_top;
    // The row spacing on the cluster's own surface, from the pixel below: a front seen
    // at a grazing angle from above spaces its rows wider than the depth noise.
    const int b = i + row;
    double spacing = 0;
    if (b < static_cast<int>(f.points.size()) && has_depth(f.points[static_cast<size_t>(b)]))
      spacing = norm(p - at(f, b));
    for (int r = 1; r <= 2; ++r) {
      const int j = i - r * row;
      if (j < 0) break;
      if (!has_depth(f.points[static_cast<size_t>(j)])) continue;  // a dropout: look one row on
      const Vec3 q = at(f, j);
      // Still in the band yet not the cluster's: the cluster ends here, the band does not.
      if (dot(n, q) + d <= params.max_height_m) break;
      // No depth step: the surface runs on (at most the rows' spacing, widened by half
      // for the noise, plus two tolerances); a prop's top meets what is behind it.
      cut += norm(q - p) <= r * (1.5 * std::min(spacing, 3 * tol) + 2 * tol);
      break;
    }
  }
  // A cut shows in at least three columns at the band's top.
  return at_top >= 3 &&
         static_cast<double>(cut) >= params.cut_top_share * static_cast<double>(at_top);
}

namespace {

// The first pixel with depth one to three grid rows on from pixel i (`row`: one grid row
// in pixels, negative upwards; a dropout is looked past), -1 when none.
int first_with_depth(const Frame& f, int i, int row) {
  const int count = static_cast<int>(f.points.size());
  for (int r = 1; r <= 3; ++r) {
    const int j = i + r * row;
    if (j < 0 || j >= count) return -1;
    if (has_depth(f.points[static_cast<size_t>(j)])) return j;
  }
  return -1;
}

// What lies one to three grid rows beyond the cluster's end pixel in each of its grid
// columns, above its top (`top`) or below its foot: the first valid pixel nearer to the
// camera than that pixel by more than the tolerance, or farther by as much.
FootView end_view(const Frame& f, const std::vector<int>& grid, int step,
                  const ToleranceAt& tolerance, bool top) {
  const std::vector<std::pair<int, int>> ends = end_per_column(f, grid, top);
  FootView v;
  v.columns = static_cast<int>(ends.size());
  const int row = (top ? -step : step) * f.width;
  for (const auto& [col, i] : ends) {
    const int j = first_with_depth(f, i, row);
    if (j < 0) continue;
    const double z = f.points[static_cast<size_t>(i)].z, qz = f.points[static_cast<size_t>(j)].z;
    v.nearer += qz < z - tolerance(z);
    v.farther += qz > z + tolerance(z);
  }
  return v;
}

// Whether something nearer hides the cluster's end in more than half of its columns.
bool end_hidden(const FootView& v) {
  return v.columns >= 3 && 2 * v.nearer > v.columns;
}

}  // namespace

bool foot_on_cut_body(const Frame& f, const std::vector<int>& grid, int step,
                      const std::function<bool(int)>& cut_below, const ToleranceAt& tolerance) {
  const std::vector<std::pair<int, int>> ends = end_per_column(f, grid, false);
  int cut = 0;
  for (const auto& [col, i] : ends) {
    const int j = first_with_depth(f, i, step * f.width);
    if (j < 0) continue;
    const double z = f.points[static_cast<size_t>(i)].z, qz = f.points[static_cast<size_t>(j)].z;
    cut += std::abs(qz - z) <= tolerance(z) && cut_below(j);
  }
  return ends.size() >= 3 && 2 * static_cast<size_t>(cut) > ends.size();
}

bool top_occluded(const Frame& f, const std::vector<int>& grid, int step,
                  const ToleranceAt& tolerance) {
  return end_hidden(end_view(f, grid, step, tolerance, true));
}

bool top_seen_ending(const Frame& f, const std::vector<int>& grid, int step,
                     const ToleranceAt& tolerance) {
  return seen_past(end_view(f, grid, step, tolerance, true));
}

bool foot_hidden_high(const Frame& f, const std::vector<int>& grid, int step, double bottom_h,
                      const ScanParams& params, const ToleranceAt& tolerance) {
  if (!(params.hidden_foot_min_height_m > 0 && bottom_h > params.hidden_foot_min_height_m))
    return false;
  const FootView v = foot_view(f, grid, step, tolerance);
  if (!params.partial_when_seen_under) return end_hidden(v);
  // Hidden or seen under: either way nothing at the foot's depth holds it up.
  return v.columns >= 3 && 2 * (v.nearer + v.farther) > v.columns;
}

FootView foot_view(const Frame& f, const std::vector<int>& grid, int step, const ToleranceAt& tolerance) {
  return end_view(f, grid, step, tolerance, false);
}

bool seen_past(const FootView& v) {
  return v.columns >= 3 && 2 * v.farther > v.columns;
}

bool hangs_seen_under(const Frame& f, const std::vector<int>& grid, int step, Vec3 n, double d, Vec3 low,
                      double low_h, double width, const ToleranceAt& tolerance) {
  // The view's slope at the lowest point: the camera's height over the support less the
  // point's, over the point's run along the plane from the camera's foot.
  const double run = norm(low - n * dot(n, low));
  if (!(run > 0) || !(low_h > width * (d - low_h) / run)) return false;
  return seen_past(foot_view(f, grid, step, tolerance));
}

bool view_under_meets_raised(const Frame& f, const std::vector<int>& grid, int step,
                             const Plane& support, double bands, const ToleranceAt& tolerance,
                             const ToleranceAt& band) {
  if (!(bands > 0)) return false;
  const std::vector<std::pair<int, int>> ends = end_per_column(f, grid, false);
  if (ends.empty()) return false;
  // Behind the body's farthest point: not under it (a body stacked on another, or a
  // piece of one, shows the lower one's top just behind its own lowest point).
  double far = 0;
  for (int i : grid) far = std::max(far, static_cast<double>(f.points[static_cast<size_t>(i)].z));
  far += tolerance(far);
  // The middle third of its columns: a prop's foot lies under its middle (a ball's is a
  // point), and a view beside the foot, under a cup's rim, may pass on past the support.
  const int span = ends.back().first - ends.front().first;
  const int lo = ends.front().first + span / 3, hi = ends.back().first - span / 3;
  int raised = 0, middle = 0;
  for (const auto& [col, i] : ends) {
    if (col < lo || col > hi) continue;
    ++middle;
    const int j = first_with_depth(f, i, step * f.width);
    if (j < 0) continue;
    const Vec3 q = at(f, j);
    raised +=
        q.z > far && dot(support.normal, q) + support.d > bands * std::max(kFlatSurface, band(q.z));
  }
  return middle >= 3 && 2 * raised > middle;
}

std::optional<Plane> own_support_around(const Frame& f, const std::vector<int>& grid, int step,
                                        const std::vector<int>& surface_of, int support,
                                        Vec3 support_n, const ScanParams& params) {
  constexpr size_t kLeastAround = 30;
  if (grid.empty()) return std::nullopt;
  int x0 = f.width, x1 = 0, y0 = f.height, y1 = 0;
  for (int i : grid) {
    x0 = std::min(x0, i % f.width), x1 = std::max(x1, i % f.width);
    y0 = std::min(y0, i / f.width), y1 = std::max(y1, i / f.width);
  }
  const int grow = std::max(x1 - x0, y1 - y0) / 2 + step;
  x0 = std::max(0, x0 - grow), x1 = std::min(f.width - 1, x1 + grow);
  y0 = std::max(0, y0 - grow), y1 = std::min(f.height - 1, y1 + grow);
  // The support's strided pixels in the grown box: on the grid, as surface_of marks them.
  const auto first_on_grid = [step](int v) { return (v + step - 1) / step * step; };
  std::vector<Vec3> around;
  for (int y = first_on_grid(y0); y <= y1; y += step)
    for (int x = first_on_grid(x0); x <= x1; x += step) {
      const int i = y * f.width + x;
      if (surface_of[static_cast<size_t>(i)] == support) around.push_back(at(f, i));
    }
  if (around.size() < kLeastAround) return std::nullopt;
  const PointScatter local = point_scatter(around);
  const Eigen::Vector3d e = smallest_eigenvector(local.scatter);
  Vec3 n{e.x(), e.y(), e.z()};
  if (dot(n, support_n) < 0) n = n * -1.0;
  if (dot(n, support_n) < std::cos(params.max_support_tilt_deg * kPi / 180)) return std::nullopt;
  const Vec3 m{local.mean.x(), local.mean.y(), local.mean.z()};
  return Plane{n, -dot(n, m)};
}

bool lies_on_own_support(const Frame& f, const std::vector<int>& grid, const Plane& around,
                         const ScanParams& params, const ToleranceAt& band) {
  if (!params.support_slab_check || grid.empty()) return false;
  // Each point's height in units of the band at its depth: within 1, it is the surface.
  std::vector<double> heights;
  heights.reserve(grid.size());
  for (int i : grid) {
    const Vec3 p = at(f, i);
    heights.push_back((dot(around.normal, p) + around.d) /
                      std::max(params.min_height_m, band(p.z)));
  }
  const size_t k = heights.size() * 9 / 10;
  std::nth_element(heights.begin(), heights.begin() + static_cast<std::ptrdiff_t>(k),
                   heights.end());
  return heights[k] < 1;
}

std::optional<Vec3> upright_panel(const Frame& f, const std::vector<int>& grid, Vec3 up,
                                  const ScanParams& params) {
  if (params.panel_noise_factor <= 0 || grid.size() < 10) return std::nullopt;
  std::vector<Vec3> pts;
  pts.reserve(grid.size());
  for (int i : grid) pts.push_back(at(f, i));
  const PointScatter face = point_scatter(pts);
  const Eigen::Vector3d& mean = face.mean;
  const Eigen::Matrix3d cov = face.scatter / static_cast<double>(grid.size());
  const Eigen::Vector3d n = smallest_eigenvector(cov);
  // Upright: the face's normal within 30 degrees of horizontal (sin 30 = 0.5).
  if (std::abs(n.x() * up.x + n.y() * up.y + n.z() * up.z) > 0.5) return std::nullopt;
  const double spread = std::sqrt(std::max(0.0, n.dot(cov * n)));
  if (spread > std::max(params.panel_flat_m,
                        params.panel_noise_factor * params.depth_noise.sigma_z(mean.z())))
    return std::nullopt;
  return Vec3{n.x(), n.y(), n.z()};
}

bool foot_behind_higher_support(const Frame& f, const std::vector<int>& grid, int step,
                                const std::vector<int>& surface_of,
                                const std::function<bool(int)>& higher,
                                const ToleranceAt& tolerance) {
  const std::vector<std::pair<int, int>> ends = end_per_column(f, grid, false);
  size_t hidden = 0;
  for (const auto& [col, i] : ends) {
    const int j = first_with_depth(f, i, step * f.width);
    if (j < 0) continue;
    const double z = f.points[static_cast<size_t>(i)].z;
    const int o = surface_of[static_cast<size_t>(j)];
    hidden += f.points[static_cast<size_t>(j)].z < z - tolerance(z) && o >= 0 && higher(o);
  }
  return ends.size() >= 3 && 2 * hidden > ends.size();
}

bool foot_unseen(const Frame& f, const std::vector<int>& grid, int step,
                 const std::vector<int>& surface_of, int support) {
  const std::vector<std::pair<int, int>> ends = end_per_column(f, grid, false);
  if (ends.size() < 3) return false;
  const int row = step * f.width;
  const int count = static_cast<int>(f.points.size());
  size_t unseen = 0, looked = 0;
  for (const auto& [col, i] : ends) {
    for (int r = 1; r <= 3; ++r) {
      const int j = i + r * row;
      if (j >= count) break;
      if (!has_depth(f.points[static_cast<size_t>(j)])) continue;
      ++looked;
      unseen += surface_of[static_cast<size_t>(j)] != support;
      break;
    }
  }
  // Columns at the image's bottom show nothing below: they count for neither.
  return looked >= 3 && 2 * unseen > looked;
}

bool runs_below_support(const Frame& f, const std::vector<int>& grid, int step, const Plane& around,
                        const std::vector<int>& surface_of, int support, const ScanParams& params) {
  if (params.below_support_sigmas <= 0) return false;
  const Vec3 n = around.normal;
  const double d = around.d;
  const std::vector<std::pair<int, int>> ends = end_per_column(f, grid, false);
  if (ends.size() < 3) return false;
  const int row = step * f.width;
  const int count = static_cast<int>(f.points.size());
  size_t looked = 0, behind = 0;
  for (const auto& [col, i] : ends) {
    const Vec3 p = at(f, i);
    // Along the plane the depth noise moves an upright face's points by up to three
    // sigma_z; the support in front of the foot runs farther (a sphere's lowest visible
    // point lies ahead of its contact, the table's front edge 2 cm on).
    const double tol = 3 * params.depth_noise.sigma_z(p.z);
    bool seen = false, under = false;
    for (int r = 1; r <= kBelowRows; ++r) {
      const int j = i + r * row;
      if (j >= count) break;
      if (!has_depth(f.points[static_cast<size_t>(j)])) continue;  // a dropout: look on
      const Vec3 q = at(f, j);
      const Vec3 dq = q - p;
      if (norm(dq - n * dot(n, dq)) > tol) {
        // The face ends at another surface: below the plane, at the support's own
        // surface nearer to the camera, its edge hiding the rest of the face, or at what
        // stands on that surface in front of the edge (above the height band).
        const bool on_support =
            surface_of[static_cast<size_t>(j)] == support ||
            (params.below_support_ends_at_objects && dot(n, q) + d > params.min_height_m);
        behind += under && q.z < p.z && on_support;
        break;
      }
      seen = true;
      // The depth noise moves a point along its ray: its height by sigma_z times the
      // ray's slope against the plane (n . q / z), a millimetre or two at a grazing view.
      const double sigma_h = params.depth_noise.sigma_z(q.z) * std::abs(dot(n, q)) / q.z;
      under =
          under || dot(n, q) + d < -std::max(kFlatSurface, params.below_support_sigmas * sigma_h);
    }
    looked += seen;
  }
  return looked >= 3 && 2 * behind > looked;
}

bool foot_cut_by_bottom(const Frame& f, const std::vector<int>& pixels, int bottom,
                        const ScanParams& params, const ToleranceAt& band) {
  if (!params.foot_at_border || pixels.empty()) return false;
  // Each column's lowest pixel, on a row of columns: an object's pixels run to tens of
  // thousands (a map per pixel cost more than the rest of the partial tests together).
  int lo_col = f.width, hi_col = -1;
  for (int i : pixels) lo_col = std::min(lo_col, i % f.width), hi_col = std::max(hi_col, i % f.width);
  std::vector<int> lowest(static_cast<size_t>(hi_col - lo_col + 1), -1);
  for (int i : pixels) {
    int& l = lowest[static_cast<size_t>(i % f.width - lo_col)];
    l = std::max(l, i);
  }
  const double fy = grid_intrinsics(f).fy;
  int cut = 0;
  for (size_t c = 0; c < lowest.size(); ++c) {
    const int i = lowest[c];
    if (i < 0) continue;
    const int col = lo_col + static_cast<int>(c);
    const int y = i / f.width;
    const double z = f.points[static_cast<size_t>(i)].z;
    // The rows the support's band spans below the lowest pixel, seen face-on.
    const double band_m = std::max(params.min_height_m, band(z));
    const int band_rows = static_cast<int>(std::ceil(fy * band_m / std::max(z, 0.1)));
    bool off = y > bottom - std::max(0, params.border_px) - band_rows;
    if (!off && y < bottom) {
      off = true;
      for (int r = y + 1; r <= bottom && off; ++r)
        off = !has_depth(f.points[static_cast<size_t>(r * f.width + col)]);
    }
    cut += off;
    if (cut >= 3) return true;
  }
  return false;
}

namespace {

// Samples of a fit's outline: a cylinder's or cone's end circles, a torus's lowest and
// widest circles, a box's corners, a sphere's foot (the point nearest the support).
std::vector<Vec3> outline_samples(const ShapeFit& fit, Vec3 up) {
  constexpr int kRing = 48;
  const PhysicalPrimitive& p = fit.primitive;
  const std::vector<double>& d = p.dimensions_m;
  const Vec3 a = normalized(p.axis);
  Vec3 u = fit.x_axis - a * dot(fit.x_axis, a);
  if (norm(u) < 1e-6) u = cross(a, std::abs(a.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0});
  u = normalized(u);
  const Vec3 v = cross(a, u);
  std::vector<Vec3> out;
  const auto ring = [&](Vec3 c, double r) {
    for (int k = 0; k < kRing; ++k) {
      const double t = 2 * kPi * k / kRing;
      out.push_back(c + (u * std::cos(t) + v * std::sin(t)) * r);
    }
  };
  if (p.kind == ShapeKind::sphere && d.size() >= 1) out.push_back(p.center - up * d[0]);
  if ((p.kind == ShapeKind::cylinder || p.kind == ShapeKind::cone) && d.size() >= 2) {
    ring(p.center - a * (d[1] / 2), d[0]);
    ring(p.center + a * (d[1] / 2), p.kind == ShapeKind::cone ? p.narrow_radius_m : d[0]);
  }
  if (p.kind == ShapeKind::torus && d.size() >= 2) {
    ring(p.center - a * d[1], d[0]);
    ring(p.center, d[0] + d[1]);
  }
  if (p.kind == ShapeKind::box && d.size() >= 3)
    for (int k = 0; k < 8; ++k)
      out.push_back(p.center + u * (d[0] / 2 * ((k & 1) ? 1 : -1)) +
                    v * (d[1] / 2 * ((k & 2) ? 1 : -1)) + a * (d[2] / 2 * ((k & 4) ? 1 : -1)));
  return out;
}

}  // namespace

bool fitted_foot_off_image(const Frame& f, const ShapeFit& fit, const Plane& support,
                           const DepthRect& rect, const ScanParams& params,
                           const ToleranceAt& band) {
  if (!params.fitted_foot_at_border) return false;
  const std::vector<Vec3> samples = outline_samples(fit, support.normal);
  double lowest = std::numeric_limits<double>::infinity();
  for (Vec3 s : samples) lowest = std::min(lowest, dot(support.normal, s) + support.d);
  const CameraIntrinsics k = grid_intrinsics(f);
  const double border = std::max(0, params.border_px);
  for (Vec3 s : samples) {
    // Too near the camera's plane to project (a fit gone wild): no foot to speak of.
    if (s.z < params.sensor_min_range_m || s.z <= 0.05) continue;
    const double height = dot(support.normal, s) + support.d - lowest;
    if (height > std::max(params.min_height_m, band(s.z))) continue;
    const double x = k.fx * s.x / s.z + k.cx, y = k.fy * s.y / s.z + k.cy;
    if (x < rect.left + border || x > rect.right - border || y < rect.top + border ||
        y > rect.bottom - border)
      return true;
  }
  return false;
}

}  // namespace annex
