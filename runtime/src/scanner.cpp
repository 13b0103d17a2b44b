// The fast scanning pipeline on the organized grid (docs/perception.md):
//  plane    seeded RANSAC over every n-th pixel, restricted to near-horizontal
//           candidates, refined by least squares on its inliers;
//  prism    one pass over all pixels: height above that plane (bounded both ways, so
//           far floor cannot leak in) and inside the 2D convex hull of its inliers;
//  clusters region growing on the pixel grid with a 3D distance test;
//  mls      per sampled point, a local plane over its grid neighbours within a radius
//           (Moving Least Squares of order 1): smoothed point and normal;
//  shapes   ObjectShapeRecognizer per cluster.
#include "annex/runtime/scanner.h"
#include "annex/runtime/scan_workers.h"
#include "annex/runtime/plane_candidates.h"

#include "annex/runtime/object_segmenter.h"
#include "dropout_join.h"
#include "furniture_rules.h"
#include "occlusion_join.h"
#include "point_scatter.h"
#include "quantile.h"
#include "scan_pool.h"
#include "smallest_eigenvector.h"
#include "stacking.h"
#include "touching_split.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <random>
#include <span>
#include <unordered_set>

#include "annex/runtime/params_validation.h"

namespace annex {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

Vec3 to_vec(const PointXYZRGB& p) { return {p.x, p.y, p.z}; }

// Unorganized clouds are re-organized by projecting them with Kinect intrinsics
// (nearest point per pixel), so one grid pipeline serves both.
Frame organize(const Frame& in) {
  const CameraIntrinsics k;
  Frame out;
  out.width = k.width;
  out.height = k.height;
  out.timestamp_s = in.timestamp_s;
  out.index = in.index;
  out.intrinsics = k;
  PointXYZRGB nan;
  nan.x = nan.y = nan.z = std::numeric_limits<float>::quiet_NaN();
  out.points.assign(static_cast<size_t>(k.width) * k.height, nan);
  for (const PointXYZRGB& p : in.points) {
    if (!has_depth(p)) continue;
    const int u = static_cast<int>(std::lround(k.fx * p.x / p.z + k.cx));
    const int v = static_cast<int>(std::lround(k.fy * p.y / p.z + k.cy));
    if (u < 0 || v < 0 || u >= k.width || v >= k.height) continue;
    PointXYZRGB& q = out.points[static_cast<size_t>(v) * k.width + u];
    if (!has_depth(q) || p.z < q.z) q = p;
  }
  return out;
}

// The plane's inlier band at depth z: the configured width, or wider where the
// camera's axial noise grows (a floor 3 m away is ~1.4 cm noisy to a Kinect).
double plane_band(const ScanParams& params, double z) {
  return std::max(params.plane_distance_m,
                  params.plane_noise_factor * params.depth_noise.sigma_z(z));
}

// sigma_z at the pixel p over its ray's length |p|: the noise moves a point along its
// ray, so off a plane of normal n it is this times |n . p| (noise_across, band_noise).
double noise_per_ray_m(const DepthNoise& noise, Vec3 p) {
  return noise.sigma_z(p.z) / std::max(norm(p), 1e-9);
}

// The spread of the difference of two raw returns' depths at depth z (sigma_z sqrt 2):
// how far apart two pixels of one surface may read.
double two_returns_sigma(const DepthNoise& noise, double z) {
  return std::sqrt(2.0) * noise.sigma_z(z);
}

// The depth noise off a plane of normal n at the pixel p: sigma_z along its ray, seen
// across the plane (|n . ray|).
double noise_across(const DepthNoise& noise, Vec3 p, Vec3 n) {
  return noise_per_ray_m(noise, p) * std::abs(dot(n, p));
}

// The band of heights over a support's plane n where the pixel p is its surface, not an
// object's (band_along_ray): plane_noise_factor times the noise across the plane, times
// `scale`, what the support's own surface shows of it (surface_noise_scale); between
// plane_distance_m and `wide`, p's plane_band. `noise` is p's plane_noise_factor
// sigma_z / |p|, which a pass over every support computes once per pixel.
double surface_band(const ScanParams& params, Vec3 p, Vec3 n, double scale, double wide,
                    double noise) {
  if (!params.band_along_ray) return wide;
  return std::clamp(noise * std::abs(dot(n, p)) * scale, params.plane_distance_m, wide);
}

// p's plane_noise_factor sigma_z / |p| (surface_band).
double band_noise(const ScanParams& params, Vec3 p) {
  return params.plane_noise_factor * noise_per_ray_m(params.depth_noise, p);
}

// Cluster tolerance at depth z: the configured one, or wider where depth noise makes
// neighbours on one surface lie farther apart (a wardrobe 3.5 m away is not sliced).
double cluster_tolerance(const ScanParams& params, double z) {
  return std::max(params.cluster_tolerance_m,
                  params.cluster_noise_factor * params.depth_noise.sigma_z(z));
}

// The scan's worker threads (scan_pool.h), set by scan_frame for as long as it runs:
// the passes below reach them without a pool in every signature.
thread_local ScanPool* scan_pool = nullptr;

// ScanPool::bands on the scan's pool, or one band on the calling thread without one.
template <typename F>
size_t in_bands(size_t n, size_t min_band, F&& body) {
  if (scan_pool) return scan_pool->bands(n, min_band, body);
  body(size_t{0}, size_t{0}, n);
  return 1;
}

double cos_degrees(double deg) { return std::cos(deg * 3.14159265358979 / 180.0); }
double sin_degrees(double deg) {
  return std::sin(deg * 3.14159265358979 / 180.0);
}

struct PlaneFit {
  Vec3 n;
  double d = 0;
  bool ok = false;
};

// How high above a plane a cluster's lowest point may lie and still stand on it: an
// object's lowest pixels lie in the plane's band, which is no cluster's, give or take
// the clustering tolerance.
double foot_reach(const ScanParams& params, double z) {
  return std::max(params.min_height_m, plane_band(params, z)) + cluster_tolerance(params, z);
}

// Whether p, over `plane`, lies within the clustering tolerance of the height band's top.
bool at_band_top(const ScanParams& params, const PlaneFit& plane, Vec3 p) {
  return dot(plane.n, p) + plane.d > params.max_height_m - cluster_tolerance(params, p.z);
}

// Least-squares plane through points (smallest eigenvector of the covariance).
PlaneFit fit_plane(const std::vector<Vec3>& pts) {
  if (pts.size() < 3) return {};
  const PointScatter s = point_scatter(pts);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(s.scatter);
  const Eigen::Vector3d n = es.eigenvectors().col(0);
  return {{n.x(), n.y(), n.z()}, -n.dot(s.mean), true};
}

// The plane a search found; the caller's one pass over the pool counts its inliers.
struct PlaneSearch {
  PlaneFit plane;
};

// Seeded RANSAC over the strided pixels still in the pool (`free` marks them), then
// least squares on the winner's inliers. `pts` holds the pool pixels' points: the passes
// over the pool read a compact array, not every other pixel of the frame.
PlaneSearch find_plane(const Frame& f, const ScanParams& params, Vec3 up, double max_angle_deg,
                       const std::vector<int>& strided, const std::vector<Vec3>& pts,
                       const std::vector<char>& free, bool use_free, std::mt19937_64& rng) {
  PlaneSearch best;
  if (strided.size() < 50) return best;
  // Inliers are counted on a fixed subsample per hypothesis; the winner is refined
  // on every strided pixel.
  // The search and the fit use the fixed band: a depth-scaled one would favour big far
  // surfaces (a wall seen obliquely) over the support.
  const double band = params.plane_distance_m;
  std::uniform_int_distribution<size_t> pick(0, strided.size() - 1);
  // The probe is stored coordinate by coordinate so the count per hypothesis runs as
  // one vectorised loop (the same sums in the same order as dot()).
  constexpr int probe_size = 2000;
  std::array<std::vector<double>, 3> probe;
  for (auto& c : probe) c.resize(probe_size);
  for (int k = 0; k < probe_size; ++k) {
    const Vec3 p = pts[pick(rng)];
    probe[0][k] = p.x, probe[1][k] = p.y, probe[2][k] = p.z;
  }
  const double* px = probe[0].data();
  const double* py = probe[1].data();
  const double* pz = probe[2].data();
  const double cos_max = cos_degrees(max_angle_deg);
  // The hypotheses are drawn first (the generator's draws do not depend on the counts),
  // then counted in bands of hypotheses on the scan's threads, then the first with the
  // most inliers wins, as when each was counted as it was drawn.
  std::vector<PlaneFit> hyps;
  hyps.reserve(static_cast<size_t>(std::max(0, params.plane_iterations)));
  // The second and third points come from the first one's image neighbourhood: a
  // local triple lies on one surface far more often than three random pixels, so
  // small supports (a floor behind furniture) are still found.
  const int window = 24;
  std::uniform_int_distribution<int> offset(-window, window);
  for (int it = 0; it < params.plane_iterations; ++it) {
    const int i0 = strided[pick(rng)];
    const int x0 = i0 % f.width, y0 = i0 / f.width;
    auto near = [&]() {
      const int x = std::clamp(x0 + offset(rng), 0, f.width - 1);
      const int y = std::clamp(y0 + offset(rng), 0, f.height - 1);
      return y * f.width + x;
    };
    const int i1 = near(), i2 = near();
    if (!has_depth(f.points[i1]) || !has_depth(f.points[i2])) continue;
    // Later searches skip pixels whose grid pixel an earlier plane took.
    if (use_free) {
      const int s = std::max(1, params.pixel_stride);
      auto snap = [&](int i) { return (i / f.width / s * s) * f.width + i % f.width / s * s; };
      if (!free[snap(i1)] || !free[snap(i2)]) continue;
    }
    const Vec3 a = to_vec(f.points[i0]);
    const Vec3 b = to_vec(f.points[i1]);
    const Vec3 c = to_vec(f.points[i2]);
    Vec3 n = cross(b - a, c - a);
    const double len = norm(n);
    if (len < 1e-9) continue;
    n = n * (1.0 / len);
    if (dot(n, up) < 0) n = n * -1.0;
    if (dot(n, up) < cos_max) continue;
    const double d = -dot(n, a);
    if (d <= 0) continue;  // the camera must be above the support
    hyps.push_back({n, d, true});
  }
  std::vector<int> counts(hyps.size(), 0);
  // A band of 32 hypotheses is some 200k multiply-adds: well worth a spinning helper.
  in_bands(hyps.size(), 32, [&](size_t, size_t lo, size_t hi) {
    for (size_t h = lo; h < hi; ++h) {
      const Vec3 n = hyps[h].n;
      const double d = hyps[h].d;
      int count = 0;
      for (int k = 0; k < probe_size; ++k)
        count += std::abs(n.x * px[k] + n.y * py[k] + n.z * pz[k] + d) < band;
      counts[h] = count;
    }
  });
  PlaneFit hyp_best;
  int hyp_count = -1;
  for (size_t h = 0; h < hyps.size(); ++h)
    if (counts[h] > hyp_count) hyp_count = counts[h], hyp_best = hyps[h];
  if (!hyp_best.ok) return best;
  PlaneFit plane = hyp_best;
  for (int round = 0; round < 2; ++round) {
    // Every third strided pixel is plenty for a least-squares plane.
    std::vector<Vec3> in;
    in.reserve(strided.size() / 3 + 1);
    for (size_t k = 0; k < strided.size(); k += 3) {
      const Vec3 p = pts[k];
      if (std::abs(dot(plane.n, p) + plane.d) < band) in.push_back(p);
    }
    PlaneFit refit = fit_plane(in);
    if (!refit.ok) break;
    if (dot(refit.n, up) < 0) {
      refit.n = refit.n * -1.0;
      refit.d = -refit.d;
    }
    if (dot(refit.n, up) < cos_max) break;
    plane = refit;
  }
  best.plane = plane;
  return best;
}

struct Hull2 {
  Vec3 u, v;
  std::vector<std::array<double, 2>> pts;  // counter-clockwise
  // Quick answers (set by finish()): outside the bounding box is outside, inside the
  // disc around the vertices' mean that the edges leave free is inside. Both keep
  // kQuickMargin_m from the boundary, far beyond the rounding of the exact test below,
  // so they answer as it does.
  static constexpr double kQuickMargin_m = 1e-7;
  double lo_a = 0, hi_a = -1, lo_b = 0, hi_b = -1, mid_a = 0, mid_b = 0, inner2 = -1;
  void finish() {
    if (pts.size() < 3) return;
    lo_a = hi_a = pts[0][0], lo_b = hi_b = pts[0][1];
    mid_a = mid_b = 0;
    for (const auto& q : pts) {
      lo_a = std::min(lo_a, q[0]), hi_a = std::max(hi_a, q[0]);
      lo_b = std::min(lo_b, q[1]), hi_b = std::max(hi_b, q[1]);
      mid_a += q[0], mid_b += q[1];
    }
    mid_a /= static_cast<double>(pts.size());
    mid_b /= static_cast<double>(pts.size());
    double r = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < pts.size(); ++k) {
      const auto& o = pts[k];
      const auto& q = pts[(k + 1) % pts.size()];
      const double len = std::hypot(q[0] - o[0], q[1] - o[1]);
      if (len <= 0) continue;
      r = std::min(r, ((q[0] - o[0]) * (mid_b - o[1]) - (q[1] - o[1]) * (mid_a - o[0])) / len);
    }
    r -= kQuickMargin_m;
    inner2 = r > 0 && std::isfinite(r) ? r * r : -1;
  }
  // Binary search of the wedge around pts[0]: O(log n) per point.
  bool contains(Vec3 p) const {
    const size_t n = pts.size();
    if (n < 3) return false;
    const double a = dot(u, p), b = dot(v, p);
    if (a < lo_a - kQuickMargin_m || a > hi_a + kQuickMargin_m || b < lo_b - kQuickMargin_m ||
        b > hi_b + kQuickMargin_m)
      return false;
    if ((a - mid_a) * (a - mid_a) + (b - mid_b) * (b - mid_b) < inner2) return true;
    auto cross2 = [&](const std::array<double, 2>& o, const std::array<double, 2>& q) {
      return (q[0] - o[0]) * (b - o[1]) - (q[1] - o[1]) * (a - o[0]);
    };
    if (cross2(pts[0], pts[1]) < 0 || cross2(pts[0], pts[n - 1]) > 0) return false;
    size_t lo = 1, hi = n - 1;
    while (hi - lo > 1) {
      const size_t mid = (lo + hi) / 2;
      if (cross2(pts[0], pts[mid]) >= 0)
        lo = mid;
      else
        hi = mid;
    }
    return cross2(pts[lo], pts[hi]) >= 0;
  }
};

Hull2 convex_hull(const std::vector<Vec3>& in, Vec3 n) {
  Hull2 h;
  const Vec3 seed = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  h.u = normalized(cross(n, seed));
  h.v = cross(n, h.u);
  std::vector<std::array<double, 2>> pts;
  pts.reserve(in.size());
  for (const Vec3& p : in) pts.push_back({dot(h.u, p), dot(h.v, p)});
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() < 3) return h;
  std::vector<std::array<double, 2>> out(2 * pts.size());
  auto turn = [](const std::array<double, 2>& o, const std::array<double, 2>& a,
                 const std::array<double, 2>& b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  };
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && turn(out[k - 2], out[k - 1], pts[i]) <= 0) --k;
    out[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && turn(out[k - 2], out[k - 1], pts[i - 1]) <= 0) --k;
    out[k++] = pts[i - 1];
  }
  out.resize(k - 1);
  h.pts = std::move(out);
  h.finish();
  return h;
}

// A later support is parallel to the first one (a room's supports share one up), so it
// is one number: its height along that normal. The heights of the pool's points that
// face up (`use`, facing_up below) are binned by the plane band and the densest band
// wins: a support concentrates at one height, and walls, legs and objects' sides, which
// spread over every height, face sideways and take no part. Unlike a RANSAC triple, this
// finds a table seen at a grazing angle from just above its height, where dropout leaves
// a thin, holed strip and three-point normals scatter. Least squares on the band's
// points then refines the winner when the refit stays parallel to the first support (a
// refit on the up-facing points alone put fewer of the tuned set's objects 1.5 to 2.5 m
// away on a support at the right height: 90.3 against 94.2 %). `heights`: each point's
// height above the first support; `peak_points` (and `inliers`): the up-facing points in
// the winning band, `peak_height` its height.
PlaneSearch find_parallel_plane(const ScanParams& params, const PlaneFit& first,
                                const std::vector<Vec3>& pts, const std::vector<double>& heights,
                                const std::vector<char>& use, double max_tilt_deg,
                                int& peak_points, double& peak_height) {
  PlaneSearch best;
  peak_points = 0;
  peak_height = 0;
  if (pts.size() < 50) return best;
  const double band = params.plane_distance_m;
  // Heights above the first plane; the camera (height first.d) must be above the support.
  const double lo = -params.max_depth_m, hi = first.d;
  const int bins = static_cast<int>((hi - lo) / band) + 2;
  std::vector<int> count(static_cast<size_t>(bins), 0);
  for (size_t k = 0; k < pts.size(); ++k) {
    if (!use[k]) continue;
    const double h = heights[k];
    if (h <= lo || h >= hi) continue;
    ++count[static_cast<size_t>((h - lo) / band)];
  }
  // Bin pairs: a band of +-band around their shared edge.
  int peak = -1, peak_count = 0;
  for (int k = 1; k < bins; ++k) {
    const int c = count[static_cast<size_t>(k - 1)] + count[static_cast<size_t>(k)];
    if (c > peak_count) peak_count = c, peak = k;
  }
  if (peak < 0) return best;
  peak_points = peak_count;
  peak_height = lo + peak * band;
  PlaneFit plane{first.n, first.d - (lo + peak * band), true};
  if (plane.d <= 0) return best;
  const double cos_max = cos_degrees(max_tilt_deg);
  for (int round = 0; round < 2; ++round) {
    std::vector<Vec3> in;
    in.reserve(static_cast<size_t>(peak_count) / 3 + 1);
    for (size_t k = 0; k < pts.size(); k += 3)
      if (std::abs(dot(plane.n, pts[k]) + plane.d) < band) in.push_back(pts[k]);
    PlaneFit refit = fit_plane(in);
    if (!refit.ok) break;
    if (dot(refit.n, first.n) < 0) {
      refit.n = refit.n * -1.0;
      refit.d = -refit.d;
    }
    if (dot(refit.n, first.n) < cos_max || refit.d <= 0) break;
    plane = refit;
  }
  best.plane = plane;
  return best;
}

// 4-connected regions of plane inliers (still free) on the strided grid. Regions of
// at least `min_region` grid pixels and a tenth of the largest make up the support:
// coplanar specks elsewhere (an object's top at the same height) do not stretch it.
struct PlaneRegions {
  std::vector<Vec3> hull_points;  // each kept region's outermost pixels per grid row
  std::vector<int> members;       // strided pixels of the kept regions
  bool touches_bottom = false;    // a kept region reaches the image's bottom rows
};

// A strided pixel's cell on the strided grid (column, row), kept beside the pixel so
// the passes over the pool divide nothing.
struct GridCell {
  int x = 0, y = 0;
};

// Grid steps between a pixel and the neighbours its surface normal is taken from.
constexpr int kSurfaceNormalSteps = 4;

// A frame's pixels with the reach their surface normals are taken over: `reach` pixels
// on along the row and the column, and how far a neighbour may lie from the pixel on
// one surface: as far as a surface seen at `max_incidence_deg` spans over the pixels
// between them (ScanParams::surface_max_incidence_deg).
struct SurfaceGrid {
  const PointXYZRGB* pts;
  int w, h, reach;
  int least_reach;  // reach / 4; reach itself where any neighbour counts (90 degrees)
  float spread;     // per pixel apart and metre of depth: 1 / (focal cos(max_incidence_deg))
  DepthNoise noise;
  // Sigmas of two returns' difference (two_returns_sigma) a neighbour may lie further.
  static constexpr double kNoiseSigmas = 3;

  SurfaceGrid(const Frame& f, int reach_px, double max_incidence_deg, const DepthNoise& depth_noise)
      : pts(f.points.data()),
        w(f.width),
        h(f.height),
        reach(reach_px),
        least_reach(max_incidence_deg >= 90 ? reach_px : std::max(1, reach_px / 4)),
        spread(
            static_cast<float>(1 / (focal_px(f) * std::max(1e-9, cos_degrees(max_incidence_deg))))),
        noise(depth_noise) {}

  // Whether pixel j has depth and lies on pixel i's surface: within the spread an
  // oblique surface gives, plus three sigma of two returns' depth noise. Past that lies a
  // depth edge: a table's front face and the floor a metre behind it span a normal
  // facing up, and their heights gathered as a band below the table's top (fresh rooms
  // 9559). A NaN depth fails `z > 0`.
  bool on_surface(int i, int j, int apart) const {
    const PointXYZRGB &a = pts[i], &b = pts[j];
    if (!(b.z > 0)) return false;
    const float dx = b.x - a.x, dy = b.y - a.y, dz = b.z - a.z;
    const float most = a.z * spread * static_cast<float>(apart) +
                       static_cast<float>(kNoiseSigmas * two_returns_sigma(noise, a.z));
    return dx * dx + dy * dy + dz * dz <= most * most;
  }

  // The neighbour pixel i's (at `at` along a row or column of `size` pixels, one pixel
  // `step` apart in the frame) surface normal is taken from: the pixel `reach` on, or the
  // one as far back where that one is not on its surface, else the same at half the
  // reach, down to a quarter (a table seen at a grazing angle 2.5 m away is some eight
  // pixels tall: no pixel of it has both neighbours a full reach away on it); -1 where
  // none is.
  int neighbour(int i, int at, int size, int step) const {
    for (int r = reach; r >= least_reach; r /= 2) {
      if (at + r < size && on_surface(i, i + r * step, r)) return i + r * step;
      if (at >= r && on_surface(i, i - r * step, r)) return i - r * step;
    }
    return -1;
  }

  // The neighbours pixel i's (at x, y) surface normal is taken from, along the row and
  // along the column (neighbour).
  std::pair<int, int> neighbours(int i, int x, int y) const {
    return {neighbour(i, x, w, 1), neighbour(i, y, h, w)};
  }

  // Whether pixel i (at x, y) lies on a surface facing up rather than sideways: the
  // normal through its neighbours within 45 degrees of `up` (ux, uy, uz), nearer to
  // horizontal than to vertical.
  bool faces_up(int i, int x, int y, float ux, float uy, float uz) const {
    const PointXYZRGB& c = pts[i];
    const auto [right, down] = neighbours(i, x, y);
    if (right < 0 || down < 0) return false;
    const float ax = pts[right].x - c.x, ay = pts[right].y - c.y, az = pts[right].z - c.z;
    const float bx = pts[down].x - c.x, by = pts[down].y - c.y, bz = pts[down].z - c.z;
    const float nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
    const float along = nx * ux + ny * uy + nz * uz, len2 = nx * nx + ny * ny + nz * nz;
    return len2 > 0 && 2 * along * along >= len2;  // cos^2 >= cos^2(45 degrees)
  }
};

// The frame's pixels with their normals taken over four grid steps. Depth noise tilts
// a far floor's normals by some 30 degrees at 3.5 m (four grid steps span 5 cm there),
// not a wall's by 45.
SurfaceGrid surface_grid(const Frame& f, const ScanParams& params) {
  return {f, kSurfaceNormalSteps * std::max(1, params.pixel_stride),
          params.surface_max_incidence_deg, params.depth_noise};
}

// Which of `pixels` lie on a surface facing up (SurfaceGrid::faces_up); `cells` are their
// cells on the grid of `stride`.
std::vector<char> facing_up(const SurfaceGrid& grid, const std::vector<int>& pixels,
                            const std::vector<GridCell>& cells, int stride, Vec3 up) {
  const float ux = static_cast<float>(up.x), uy = static_cast<float>(up.y), uz = static_cast<float>(up.z);
  std::vector<char> out(pixels.size(), 0);
  // A NaN depth fails `z > 0`; a pixel with depth has finite coordinates here (the
  // pool holds valid pixels, and a NaN neighbour coordinate only makes the test fail).
  for (size_t k = 0; k < pixels.size(); ++k)
    out[k] = grid.faces_up(pixels[k], cells[k].x * stride, cells[k].y * stride, ux, uy, uz);
  return out;
}

// `inliers`: the strided pixels still free within the plane's depth-scaled band, and
// `cells` their grid cells.
std::vector<PlaneRegions> plane_regions(const Frame& f, const std::vector<int>& inliers,
                                        const std::vector<GridCell>& cells, int stride,
                                        int min_region, bool split) {
  const int gw = (f.width + stride - 1) / stride, gh = (f.height + stride - 1) / stride;
  // Each inlier cell holds its index in `cells` on the grid padded by two cells on every
  // side, which are never inliers: the neighbour steps below need no bounds test.
  const int pw = gw + 4;
  auto cell = [pw](int x, int y) { return static_cast<size_t>(y + 2) * pw + (x + 2); };
  // The grid is scratch kept per thread between calls and scans (-1 everywhere between
  // calls: only the inlier cells are set, and they are reset on the way out), so a call
  // costs its inliers, not a clear of the whole grid.
  thread_local std::vector<int> at;
  if (at.size() != static_cast<size_t>(pw) * (gh + 4)) at.assign(static_cast<size_t>(pw) * (gh + 4), -1);
  // Neighbours one or two grid steps away along the rows and columns: a surface seen at
  // a grazing angle loses pixels to dropout (a far table seen from just above its
  // height), and a single missing cell must not cut it apart. The relation is
  // symmetric, so joining each cell to its earlier neighbours (raster order) joins
  // every pair: one pass of union-find, each set's root its first cell.
  // A cell's parent is never a later cell (a join hangs the later root under the earlier
  // one, path halving only shortens paths), and a set's root is its first cell.
  std::vector<int> parent(cells.size());
  auto root = [&](int k) {
    while (parent[k] != k) k = parent[k] = parent[parent[k]];
    return k;
  };
  int prev_root = -1;  // the previous cell's root once it was placed
  for (size_t k = 0; k < cells.size(); ++k) {
    const size_t c = cell(cells[k].x, cells[k].y);
    at[c] = static_cast<int>(k);
    int r = static_cast<int>(k);
    parent[k] = r;
    auto join = [&](int m) {
      const int rm = root(m);
      if (rm == r) return;
      // The earlier root stays: a set's root is its first cell in raster order.
      if (rm < r)
        parent[r] = rm, r = rm;
      else
        parent[rm] = r;
    };
    // Two cells back along the row or column is already joined to one cell back when
    // that is an inlier (they are each other's neighbours). The cell one back along the
    // row, when an inlier, is the previous one (k - 1), whose root is the one it was left
    // with: nothing has joined since.
    if (at[c - 1] >= 0)
      parent[k] = r = prev_root;
    else if (const int m2 = at[c - 2]; m2 >= 0)
      join(m2);
    if (const int m = at[c - pw]; m >= 0)
      join(m);
    else if (const int m2 = at[c - 2 * pw]; m2 >= 0)
      join(m2);
    prev_root = r;
  }
  for (const GridCell& g : cells) at[cell(g.x, g.y)] = -1;
  // Regions are numbered in the order of their first cells, as a scan of the grid that
  // floods each region from its first cell would number them.
  std::vector<int> region(cells.size());
  std::vector<int> sizes;
  // A cell's parent is an earlier cell of its set, numbered already: no root walk.
  for (size_t k = 0; k < cells.size(); ++k) {
    const int p = parent[k];
    if (p == static_cast<int>(k)) {
      region[k] = static_cast<int>(sizes.size());
      sizes.push_back(0);
    } else {
      region[k] = region[static_cast<size_t>(p)];
    }
    ++sizes[static_cast<size_t>(region[k])];
  }
  const int largest = sizes.empty() ? 0 : *std::max_element(sizes.begin(), sizes.end());
  std::vector<char> keep(sizes.size(), 0);
  for (size_t k = 0; k < sizes.size(); ++k)
    keep[k] = sizes[k] >= min_region && sizes[k] * 10 >= largest;
  // Only each grid row's outermost pixels of a region can be hull vertices: an image
  // row seen on a plane is a line, and its inner pixels lie between the outer two.
  // `split`: one support per kept region, else one for all of them.
  std::vector<int> slot(sizes.size(), -1);
  std::vector<PlaneRegions> out;
  std::vector<size_t> slot_size;
  for (size_t k = 0; k < sizes.size(); ++k)
    if (keep[k]) {
      if (split || out.empty()) out.emplace_back(), slot_size.push_back(0);
      slot[k] = static_cast<int>(out.size()) - 1;
      slot_size.back() += static_cast<size_t>(sizes[k]);
    }
  for (size_t o = 0; o < out.size(); ++o) out[o].members.reserve(slot_size[o]);
  // Only inlier cells carry a label: the grid rows are walked through the raster-ordered
  // inliers, each row closed when the next inlier lies on a later one.
  std::vector<int> first(out.size(), -1), last(out.size());
  auto close_row = [&](int y) {
    for (size_t o = 0; o < out.size(); ++o) {
      if (first[o] < 0) continue;
      for (int x : {first[o], last[o]})
        out[o].hull_points.push_back(
            to_vec(f.points[static_cast<size_t>(y) * stride * f.width + x * stride]));
      first[o] = -1;
    }
  };
  int row = -1;
  for (size_t k = 0; k < inliers.size(); ++k) {
    const int i = inliers[k], x = cells[k].x, y = cells[k].y;
    if (y != row) {
      if (row >= 0) close_row(row);
      row = y;
    }
    const int l = region[k];
    if (slot[l] < 0) continue;
    const int o = slot[l];
    out[o].members.push_back(i);  // a strided pixel: y * stride * width + x * stride
    if (first[o] < 0) first[o] = x;
    last[o] = x;
    if (y >= gh - 2) out[o].touches_bottom = true;
  }
  if (row >= 0) close_row(row);
  return out;
}

// The part of a region that is a surface seen from above rather than a band across a
// vertical one (a far wall cut by the plane band). Along each image column a horizontal
// surface runs away from the camera; a vertical one crosses the band in a few rows whose
// distance along the plane differs only by depth noise. A column is seen from above when
// its extent along the view, laid on the plane, clears three plane bands at its depth.
// A region seen from above in most of its columns is kept whole; otherwise its best run
// of such columns: a table seen from just above its height is one region with the wall
// beside it at the same height, whose columns are short. The kept part's hull points
// are each grid row's outermost kept pixels; `touches_bottom` is kept as it was.
PlaneRegions seen_from_above(const Frame& f, const PlaneRegions& region, const PlaneFit& plane,
                             const ScanParams& params) {
  const Vec3 view = normalized(Vec3{0, 0, 1} - plane.n * plane.n.z);
  std::map<int, std::pair<double, double>> span;  // column -> min, max along the view
  std::map<int, double> depth;
  for (int i : region.members) {
    const Vec3 p = to_vec(f.points[i]);
    const double t = dot(view, p);
    auto [it, fresh] = span.try_emplace(i % f.width, t, t);
    if (!fresh) it->second = {std::min(it->second.first, t), std::max(it->second.second, t)};
    depth[i % f.width] = p.z;
  }
  // A region seen from above in most of its columns is kept whole.
  size_t long_columns = 0;
  for (const auto& [col, mm] : span) long_columns += mm.second - mm.first >= 3 * plane_band(params, depth[col]);
  if (2 * long_columns >= span.size()) return region;
  // Else the run of such columns with most of them; short gaps in it stay (objects on
  // the surface hide all but a short stretch of it there), and it must make up most of
  // the region's columns between its ends: a band across clutter, long here and there,
  // is no surface.
  struct Run {
    int first = 0, last = 0, count = 0;
  };
  std::vector<Run> runs;
  for (const auto& [col, mm] : span) {
    if (mm.second - mm.first < 3 * plane_band(params, depth[col])) continue;
    // A gap wider than a quarter of the run so far ends it.
    if (runs.empty() || col - runs.back().last > std::max(8, (runs.back().last - runs.back().first) / 4))
      runs.push_back({col, col, 0});
    runs.back().last = col;
    ++runs.back().count;
  }
  int first_col = f.width, last_col = -1, best_count = 0;
  for (const Run& r : runs) {
    int inside = 0;
    for (const auto& [col, mm] : span) inside += col >= r.first && col <= r.last;
    if (r.count > best_count && 2 * r.count > inside)
      best_count = r.count, first_col = r.first, last_col = r.last;
  }
  PlaneRegions out;
  out.touches_bottom = region.touches_bottom;
  std::map<int, std::pair<int, int>> row_ends;  // image row -> outermost kept pixels
  for (int i : region.members) {
    if (i % f.width < first_col || i % f.width > last_col) continue;
    out.members.push_back(i);
    auto [it, fresh] = row_ends.try_emplace(i / f.width, i, i);
    if (!fresh) it->second = {std::min(it->second.first, i), std::max(it->second.second, i)};
  }
  for (const auto& [row, ends] : row_ends) {
    out.hull_points.push_back(to_vec(f.points[ends.first]));
    if (ends.second != ends.first) out.hull_points.push_back(to_vec(f.points[ends.second]));
  }
  return out;
}

double hull_area(const Hull2& h) {
  double a = 0;
  for (size_t k = 0; k < h.pts.size(); ++k) {
    const auto& p = h.pts[k];
    const auto& q = h.pts[(k + 1) % h.pts.size()];
    a += p[0] * q[1] - q[0] * p[1];
  }
  return std::abs(a) * 0.5;
}

// Region growing over prism pixels on the strided grid: neighbours within
// +-window grid steps join when closer than the tolerance in 3D (a Euclidean
// clustering that uses the image grid as its neighbour search).
// `mask` holds 1 + the index of the support a candidate pixel stands on: pixels join
// only over the same support.
std::vector<std::vector<int>> grow_clusters(const Frame& f, const std::vector<char>& mask,
                                            const std::vector<int>& seeds, int step,
                                            const ScanParams& params) {
  // The candidates not yet in a cluster: `mask` with each pixel cleared as it joins one,
  // so a neighbour takes one test (same support, still free), not two.
  std::vector<char> open = mask;
  std::vector<std::vector<int>> clusters;
  const int w = std::max(1, params.cluster_window_px / step);
  // Seeds and their neighbours are strided pixels: each queued pixel keeps its grid cell,
  // so the window's clip takes no division (a strided pixel's x / step is its grid
  // column, (width - 1 - x) / step the last grid column less it, as for rows).
  const int last_gx = (f.width - 1) / step, last_gy = (f.height - 1) / step;
  std::vector<int> queue;
  std::vector<GridCell> queued;
  for (int start : seeds) {
    if (!open[start]) continue;
    queue.assign(1, start);
    queued.assign(1, {start % f.width / step, start / f.width / step});
    open[start] = 0;
    for (size_t q = 0; q < queue.size(); ++q) {
      const int i = queue[q], gx = queued[q].x, gy = queued[q].y, x = gx * step, y = gy * step;
      const PointXYZRGB& p = f.points[i];
      const double tol = cluster_tolerance(params, p.z), tol2 = tol * tol;
      // The window clipped to the image once per pixel, not tested per neighbour.
      const int dy0 = -std::min(w, gy), dy1 = std::min(w, last_gy - gy);
      const int dx0 = -std::min(w, gx), dx1 = std::min(w, last_gx - gx);
      const char own = mask[i];
      for (int dy = dy0; dy <= dy1; ++dy) {
        const int row = (y + dy * step) * f.width;
        for (int dx = dx0; dx <= dx1; ++dx) {
          const int j = row + x + dx * step;
          if (open[j] != own) continue;
          const PointXYZRGB& o = f.points[j];
          const double ddx = p.x - o.x, ddy = p.y - o.y, ddz = p.z - o.z;
          if (ddx * ddx + ddy * ddy + ddz * ddz > tol2) continue;
          open[j] = 0;
          queue.push_back(j);
          queued.push_back({gx + dx, gy + dy});
        }
      }
    }
    clusters.push_back(queue);
  }
  return clusters;
}

// Whether a cluster's surface runs on above the height band: grid neighbours of its
// pixels that are above max_height_m yet on the cluster's surface. Walls, cupboards and
// people do; an object on the support ends below the band's top. A neighbour is on the
// surface when it is within the cluster tolerance in 3D, or when it continues the line
// through the pixel and its opposite neighbour within that tolerance (and within three
// tolerances of it): a cupboard's front seen at a grazing angle from above spaces its
// rows wider than the depth noise, but evenly, while an object's top edge against the
// wall behind it is a step the line misses by far.
bool continues_above(const Frame& f, const std::vector<int>& grid_pixels, int step,
                     const PlaneFit& plane, const ScanParams& params) {
  size_t joins = 0;
  auto point = [&](int x, int y) -> const PointXYZRGB* {
    if (x < 0 || y < 0 || x >= f.width || y >= f.height) return nullptr;
    const PointXYZRGB& q = f.points[static_cast<size_t>(y) * f.width + x];
    return has_depth(q) ? &q : nullptr;
  };
  for (int i : grid_pixels) {
    const int x = i % f.width, y = i / f.width;
    const PointXYZRGB& p = f.points[i];
    const double tol = cluster_tolerance(params, p.z), tol2 = tol * tol;
    const int nb[4][2] = {{-step, 0}, {step, 0}, {0, -step}, {0, step}};
    for (const auto& d : nb) {
      const PointXYZRGB* q = point(x + d[0], y + d[1]);
      if (!q || dot(plane.n, to_vec(*q)) + plane.d <= params.max_height_m) continue;
      const double dx = q->x - p.x, dy = q->y - p.y, dz = q->z - p.z;
      const double gap2 = dx * dx + dy * dy + dz * dz;
      if (gap2 <= tol2) {
        ++joins;
        continue;
      }
      const PointXYZRGB* r = point(x - d[0], y - d[1]);
      if (!r || gap2 > 9 * tol2) continue;
      const double ex = dx - (p.x - r->x), ey = dy - (p.y - r->y), ez = dz - (p.z - r->z);
      joins += ex * ex + ey * ey + ez * ez <= tol2;
    }
  }
  // A few joins suffice for a thin leg seen from afar (a handful of grid pixels wide),
  // and a tall thin post joins along its top edge alone (cut_join_column_share).
  size_t asked = grid_pixels.size() / 50;
  if (params.cut_join_column_share > 0) {
    std::vector<int> columns;
    columns.reserve(grid_pixels.size());
    for (int i : grid_pixels) columns.push_back(i % f.width);
    std::sort(columns.begin(), columns.end());
    const auto width =
        static_cast<double>(std::unique(columns.begin(), columns.end()) - columns.begin());
    asked = std::min(asked, static_cast<size_t>(params.cut_join_column_share * width));
  }
  return joins >= std::max<size_t>(8, asked);
}

// Whether a cluster's surface is seen running on below the plane under its foot: under
// its lowest pixel, in most of its grid columns, a pixel below the plane's band lies
// within the clustering tolerance of that pixel along the plane, before anything nearer
// hides the view. A wall behind a board's seen part runs on down past the board's
// height; a cup standing on the board does not, and the board, nearer, lies under it.
bool runs_on_below(const Frame& f, const std::vector<int>& grid, int step, const PlaneFit& plane,
                   const ScanParams& params) {
  constexpr int kRows = 16;  // grid rows looked down: a band's width down a wall 3 m away
  const std::vector<std::pair<int, int>> foot = end_per_column(f, grid, false);
  int runs = 0;
  for (const auto& [col, i] : foot) {
    const Vec3 p = to_vec(f.points[i]);
    const double tol = cluster_tolerance(params, p.z);
    for (int r = 1; r <= kRows; ++r) {
      const size_t j = static_cast<size_t>(i) + static_cast<size_t>(r * step * f.width);
      if (j >= f.points.size()) break;
      if (!has_depth(f.points[j])) continue;
      const Vec3 q = to_vec(f.points[j]);
      if (q.z < p.z - tol) break;  // something nearer hides what lies below
      const double h = dot(plane.n, q) + plane.d;
      if (h >= -plane_band(params, q.z)) continue;
      const Vec3 v = q - p;
      runs += norm(v - plane.n * dot(plane.n, v)) < 2 * tol;
      break;
    }
  }
  return 2 * runs > static_cast<int>(foot.size());
}

// Whether pixel q (with depth) belongs with the cluster's grid pixel c in its block:
// above the support's band, below the height band's top, within the clustering
// tolerance (tol2 its square) of c.
bool expands_to(const PointXYZRGB& c, const PointXYZRGB& q, double tol2, const PlaneFit& plane,
                double band_scale, const ScanParams& params) {
  const double h = dot(plane.n, to_vec(q)) + plane.d;
  if (h > params.max_height_m) return false;
  // surface_band is no wider than plane_band: asked only below that.
  const double wide = plane_band(params, q.z);
  if (h < wide &&
      h < std::max(params.min_height_m, surface_band(params, to_vec(q), plane.n, band_scale, wide,
                                                     band_noise(params, to_vec(q)))))
    return false;
  const double dx = c.x - q.x, dy = c.y - q.y, dz = c.z - q.z;
  return dx * dx + dy * dy + dz * dz <= tol2;
}

// Full-resolution pixels of a cluster found on the strided grid: each grid pixel's
// block, keeping pixels in the height band and near their grid pixel in 3D.
std::vector<int> expand_cluster(const Frame& f, const std::vector<int>& grid_pixels, int step,
                                const PlaneFit& plane, double band_scale,
                                const ScanParams& params) {
  // Pixels come out in raster order: grid pixels sorted, then each grid row's blocks
  // emitted one image row at a time (blocks do not overlap), so nothing larger than
  // the grid list is sorted.
  std::vector<int> grid = grid_pixels;
  std::sort(grid.begin(), grid.end());
  std::vector<int> out;
  out.reserve(grid.size() * step * step);
  for (size_t row = 0; row < grid.size();) {
    const int y = grid[row] / f.width;
    size_t end = row;
    while (end < grid.size() && grid[end] / f.width == y) ++end;
    for (int dy = 0; dy < step && y + dy < f.height; ++dy)
      for (size_t k = row; k < end; ++k) {
        const int x = grid[k] % f.width;
        const PointXYZRGB& c = f.points[grid[k]];
        const double tol = cluster_tolerance(params, c.z), tol2 = tol * tol;
        for (int dx = 0; dx < step && x + dx < f.width; ++dx) {
          const int j = (y + dy) * f.width + x + dx;
          const PointXYZRGB& q = f.points[j];
          if (has_depth(q) && expands_to(c, q, tol2, plane, band_scale, params)) out.push_back(j);
        }
      }
    row = end;
  }
  return out;
}

// Whether a cluster's foot shows: in at least half of its image columns (x0..x1) that
// show anything one to three rows below its lowest pixel, the first such pixel is of no
// other cluster. One standing on another (a box on a box) or behind a nearer one does not
// show where it meets its support.
bool foot_shows(const Frame& f, const std::vector<int>& pixels, const std::vector<int>& label,
                int x0, int x1) {
  constexpr int kRowsBelow = 3;
  const int own = label[static_cast<size_t>(pixels.front())];
  std::vector<int> lowest(static_cast<size_t>(x1 - x0 + 1), -1);
  for (int i : pixels) {
    int& low = lowest[static_cast<size_t>(i % f.width - x0)];
    low = std::max(low, i / f.width);
  }
  int seen = 0, other = 0;
  for (int x = x0; x <= x1; ++x) {
    const int y = lowest[static_cast<size_t>(x - x0)];
    if (y < 0) continue;
    for (int r = y + 1; r <= std::min(f.height - 1, y + kRowsBelow); ++r) {
      const size_t i = static_cast<size_t>(r) * f.width + x;
      if (!has_depth(f.points[i])) continue;
      ++seen;
      other += label[i] >= 0 && label[i] != own;
      break;
    }
  }
  return 2 * other <= seen;
}

// The support's surface seen around a cluster (SupportAround, the recognizer's free-space
// test): the pixels of no cluster in its image box grown by a quarter of its larger side,
// on the support's plane within the depth noise (plane_noise_factor sigma_z, at most
// min_height_m: an object's own lowest pixels lie in the band above it), and not
// enclosed by clusters' pixels along both their row and their column (an open
// container's inner floor, inside its rim and its far wall, a cluster of its own when the
// floor parts them). Empty when the cluster's foot does not show (foot_shows). A small box
// is read whole; a large one every k-th row and column, so at most about kMostVisited
// pixels are visited.
SupportAround support_around(const Frame& f, const std::vector<int>& pixels,
                             const std::vector<int>& label, const Plane& support,
                             const ScanParams& params) {
  constexpr long long kMostVisited = 40000;
  SupportAround out;
  if (pixels.empty()) return out;
  int x0 = f.width, x1 = 0, y0 = f.height, y1 = 0;
  for (int i : pixels) {
    x0 = std::min(x0, i % f.width), x1 = std::max(x1, i % f.width);
    y0 = std::min(y0, i / f.width), y1 = std::max(y1, i / f.width);
  }
  const Vec3 n = normalized(support.normal);
  const double d = support.d / norm(support.normal);
  if (!foot_shows(f, pixels, label, x0, x1)) return out;
  const int grow = std::max(x1 - x0, y1 - y0) / 4 + 1;
  x0 = std::max(0, x0 - grow), x1 = std::min(f.width - 1, x1 + grow);
  y0 = std::max(0, y0 - grow), y1 = std::min(f.height - 1, y1 + grow);
  const int bw = x1 - x0 + 1, bh = y1 - y0 + 1;
  int step = 1;
  while (static_cast<long long>(bw) * bh > kMostVisited * step * step) ++step;
  out.pixels_per_point = step * step;
  out.object_pixels = static_cast<int>(pixels.size());
  // The clusters' extent along each visited row and column of the box.
  std::vector<int> row_lo(static_cast<size_t>(bh), f.width), row_hi(row_lo.size(), -1);
  std::vector<int> col_lo(static_cast<size_t>(bw), f.height), col_hi(col_lo.size(), -1);
  for (int y = y0; y <= y1; y += step)
    for (int x = x0; x <= x1; x += step)
      if (label[static_cast<size_t>(y) * f.width + x] >= 0) {
        const size_t u = static_cast<size_t>(x - x0), v = static_cast<size_t>(y - y0);
        row_lo[v] = std::min(row_lo[v], x), row_hi[v] = std::max(row_hi[v], x);
        col_lo[u] = std::min(col_lo[u], y), col_hi[u] = std::max(col_hi[u], y);
      }
  for (int y = y0; y <= y1; y += step)
    for (int x = x0; x <= x1; x += step) {
      const size_t i = static_cast<size_t>(y) * f.width + x;
      const size_t u = static_cast<size_t>(x - x0), v = static_cast<size_t>(y - y0);
      const bool enclosed = row_lo[v] < x && x < row_hi[v] && col_lo[u] < y && y < col_hi[u];
      if (label[i] >= 0 || enclosed || !has_depth(f.points[i])) continue;
      const Vec3 p = to_vec(f.points[i]);
      const double h = dot(n, p) + d;
      const double noise = params.plane_noise_factor * params.depth_noise.sigma_z(p.z);
      if (std::abs(h) < std::min(noise, params.min_height_m)) out.points.push_back(p);
    }
  return out;
}

// MLS of order 1 on a deterministic subsample of a cluster: for each sampled pixel,
// the covariance of same-cluster grid neighbours within the radius gives a local
// plane; the point moves onto it and takes its normal (oriented to the camera).
void smooth_cluster(const Frame& f, const std::vector<int>& pixels, const std::vector<int>& label,
                    int id, const ScanParams& params, std::vector<Vec3>& points,
                    std::vector<Vec3>& normals) {
  const int budget = std::max(100, params.shape.max_fit_points);
  const size_t step = std::max<size_t>(1, pixels.size() / budget + (pixels.size() % budget ? 1 : 0));
  points.clear();
  normals.clear();
  const int w = params.mls_window_px;
  const double fx = focal_px(f);
  for (size_t k = 0; k < pixels.size(); k += step) {
    const int i = pixels[k], x = i % f.width, y = i / f.width;
    const Vec3 p = to_vec(f.points[i]);
    // Far away, pixels spread and depth steps grow (1.8 cm at 2.5 m): the radius
    // widens to reach the window's pixels and span the noise, else no plane is found.
    const double pixel_m = p.z / fx;  // the pixels' spacing at that depth
    const double r =
        std::max({params.mls_radius_m, 3 * params.depth_noise.sigma_z(p.z), 1.5 * w * pixel_m});
    const double r2 = r * r;
    // The sums of the coordinates and of their six distinct products (the second
    // moments are symmetric), two to a packed pair: each lane adds the same products in
    // the same order as one sum at a time would (the same values), in half the steps.
    Eigen::Array2d s_xy(0, 0), s_xx_yy(0, 0), s_xy_yz(0, 0), s_xz_zz(0, 0);
    double sz = 0;
    int n = 0;
    const int hop = w > 3 ? 2 : 1;  // a sparser window keeps the cost flat
    // The window's first offsets inside the image (the same offsets as testing each).
    int dy0 = -w, dx0 = -w;
    while (y + dy0 < 0) dy0 += hop;
    while (x + dx0 < 0) dx0 += hop;
    // ... and the last: both bounds in one compare per step.
    const int dy1 = std::min(w, f.height - 1 - y), dx1 = std::min(w, f.width - 1 - x);
    for (int dy = dy0; dy <= dy1; dy += hop) {
      const int row = (y + dy) * f.width;
      for (int dx = dx0; dx <= dx1; dx += hop) {
        const int j = row + x + dx;
        if (label[j] != id) continue;
        const PointXYZRGB& pj = f.points[j];
        const double qx = pj.x, qy = pj.y, qz = pj.z;
        const double ex = qx - p.x, ey = qy - p.y, ez = qz - p.z;
        if (ex * ex + ey * ey + ez * ez > r2) continue;
        const Eigen::Array2d xy(qx, qy);
        s_xy += xy;
        sz += qz;
        s_xx_yy += xy * xy;
        s_xy_yz += xy * Eigen::Array2d(qy, qz);
        s_xz_zz += Eigen::Array2d(qx, qz) * qz;
        ++n;
      }
    }
    const double sx = s_xy[0], sy = s_xy[1], sxx = s_xx_yy[0], syy = s_xx_yy[1];
    const double sxy = s_xy_yz[0], syz = s_xy_yz[1], sxz = s_xz_zz[0], szz = s_xz_zz[1];
    if (n < 5 || params.mls_radius_m <= 0) {
      points.push_back(p);
      normals.push_back({0, 0, 0});
      continue;
    }
    const Eigen::Vector3d mean = Eigen::Vector3d(sx, sy, sz) / n;
    Eigen::Matrix3d sq;
    sq << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
    const Eigen::Matrix3d cov = sq / n - mean * mean.transpose();
    Eigen::Vector3d nn = smallest_eigenvector(cov);
    const Eigen::Vector3d pv(p.x, p.y, p.z);
    if (nn.dot(pv) > 0) nn = -nn;
    // Veil points (mixed pixels along depth edges) lie on surfaces seen edge-on.
    if (-nn.dot(pv) < params.min_view_cos * pv.norm()) continue;
    const Eigen::Vector3d proj = pv - nn * nn.dot(pv - mean);
    points.push_back({proj.x(), proj.y(), proj.z()});
    normals.push_back({nn.x(), nn.y(), nn.z()});
  }
}

// smooth_cluster of a cluster's part with its own pixels as its only neighbours, on a
// label of the calling thread's (all -1 between calls) rather than the scan's, which
// stays as the clusters' fits running beside it read it.
void smooth_part(const Frame& f, const std::vector<int>& pixels, const ScanParams& params,
                 std::vector<Vec3>& points, std::vector<Vec3>& normals) {
  thread_local std::vector<int> own;
  if (own.size() != f.points.size()) own.assign(f.points.size(), -1);
  for (int i : pixels) own[static_cast<size_t>(i)] = 0;
  smooth_cluster(f, pixels, own, 0, params, points, normals);
  for (int i : pixels) own[static_cast<size_t>(i)] = -1;
}

// Items in order of decreasing cost (ties in item order): handed out that way, a big
// item is started first instead of last, where it would leave the other core idle.
std::vector<size_t> largest_first(const std::vector<size_t>& cost) {
  std::vector<size_t> order(cost.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return cost[a] > cost[b]; });
  return order;
}

// Runs body(k) for every item k < n on the scan's worker threads (scan_pool, set for
// the whole of scan_frame), or on the calling thread without them. Items are handed out
// in `order` when given (see largest_first), else in index order; the caller keeps
// results per item.
template <typename F>
void parallel_for(size_t n, F body, const std::vector<size_t>* order = nullptr) {
  if (scan_pool) {
    scan_pool->run(n, body, order);
    return;
  }
  for (size_t k = 0; k < n; ++k) body(order ? (*order)[k] : k);
}

// Whether at least `share` of `pts` (none: false) lie within `solid` grown by `margin`:
// the count stops once the answer is known (the share reached, or out of reach with the
// points left), so it answers as the full count does.
bool mostly_inside(const ShapeFit& solid, const std::vector<Vec3>& pts, double margin, double share) {
  if (pts.empty()) return false;
  const double need = share * static_cast<double>(pts.size());
  size_t inside = 0;
  for (size_t m = 0; m < pts.size(); ++m) {
    if (static_cast<double>(inside) >= need) return true;
    if (static_cast<double>(inside + (pts.size() - m)) < need) return false;
    inside += within_shape(solid, pts[m], margin);
  }
  return static_cast<double>(inside) >= need;
}

// Whether a piece hangs in the air from object `owner` (its index in `label`): its foot
// (the 5 % quantile of its pixels' heights) lies above its support's band at its depth,
// and under its foot, in more than half of its columns (three at least), the first pixel
// with depth one to three grid rows (`step` pixels) down is the owner's, or lies beyond
// the foot by more than three sigma of the depth noise while the foot is higher than
// anything of its own its width could hide beneath it (hangs_seen_under's geometry: a
// ball's underside curves away under its lowest pixel). A dropout proves nothing.
bool hangs_from(const Frame& f, const ScanCluster& sc, int owner, const std::vector<int>& label,
                const ScanParams& params, int step) {
  if (sc.pixels.empty()) return false;
  const Vec3 n = sc.support.normal;
  const Vec3 view_x = normalized(Vec3{1, 0, 0} - n * n.x);
  std::vector<double> heights, depths;
  double x_lo = 1e9, x_hi = -1e9, low_h = 1e9;
  Vec3 low;
  for (int i : sc.pixels) {
    const Vec3 p = to_vec(f.points[static_cast<size_t>(i)]);
    const double h = dot(n, p) + sc.support.d;
    heights.push_back(h);
    depths.push_back(p.z);
    x_lo = std::min(x_lo, dot(view_x, p)), x_hi = std::max(x_hi, dot(view_x, p));
    if (h < low_h) low_h = h, low = p;
  }
  const double foot = quantile(heights, 0.05);
  if (foot <= plane_band(params, quantile(depths, 0.5))) return false;
  const double run = norm(low - n * dot(n, low));
  const bool above_own = run > 0 && foot > (x_hi - x_lo) * (sc.support.d - foot) / run;
  const std::vector<std::pair<int, int>> ends = end_per_column(f, sc.pixels, false);
  const int count = static_cast<int>(f.points.size());
  int under = 0;
  for (const auto& [col, i] : ends)
    for (int r = 1; r <= 3; ++r) {
      const int j = i + r * step * f.width;
      if (j >= count) break;
      if (!has_depth(f.points[static_cast<size_t>(j)])) continue;
      const double z = f.points[static_cast<size_t>(i)].z;
      under +=
          label[static_cast<size_t>(j)] == owner ||
          (above_own && f.points[static_cast<size_t>(j)].z > z + 3 * params.depth_noise.sigma_z(z));
      break;
    }
  return ends.size() >= 3 && 2 * static_cast<size_t>(under) > ends.size();
}

// Whether a piece's lowest point lies a third of the stacking band below the top of a
// bigger object: beside it, as a handle, not on its top, as what stands there.
bool hangs_beside(const ScanCluster& part, const ScanCluster& big) {
  const Vec3 n = part.support.normal;
  const double d = part.support.d;
  double low = 1e9, top = -1e9;
  for (const Vec3& p : part.points) low = std::min(low, dot(n, p) + d);
  for (const Vec3& p : big.points) top = std::max(top, dot(n, p) + d);
  return low < top - kStackBand_m / 3;
}

// An object that took parts (merge_parts): its index after the merge, itself before it,
// and the parts it took.
struct GrownObject {
  size_t index = 0;
  ScanCluster before;
  std::vector<ScanCluster> parts;
};

// Two objects on a support cannot interpenetrate: a cluster lying mostly inside a
// bigger object's fitted solid is a part of it that a depth edge cut off (a bottle's
// handle behind its rim). Each such part joins the biggest object that contains it
// (its pixels, and `label`, the owner's) and is removed; returns the grown objects
// (each as it was and its parts), biggest first, which the caller smooths and fits
// again. An object whose extent no one sees (`unseen`: cut by the image border, or
// hidden in half) holds no part: its fitted primitive spans what is seen of it, not its
// solid (a shelf's side and board edge cut by the border, fitted as one box, span the
// board and what stands on it). What lies in such an object and in no other is kept
// apart, its pixels marked in `apart` (a piece of the cut object, or an object of its
// own: no one can tell). A piece hanging from an object (`hangs(piece, object)`: nothing
// of its own holds it up), beside it (hangs_beside), whose solid grown by
// part_hang_reach_m holds it is a part of it too (a mug's handle cut off at the crease
// where it meets the wall), and so is what rises from an object (`rises_from`, per
// cluster: restack; -1 none).
std::vector<GrownObject> merge_parts(const ScanParams& params, ScanResult& result,
                                     std::vector<int>& label,
                                     const std::function<bool(const ScanCluster&)>& unseen,
                                     const std::function<bool(const ScanCluster&, size_t)>& hangs,
                                     const std::vector<int>& rises_from, std::vector<char>& apart) {
  const size_t n = result.clusters.size();
  if (n < 2 || params.part_margin_m <= 0) return {};
  std::vector<size_t> by_size(n);
  std::iota(by_size.begin(), by_size.end(), 0);
  std::stable_sort(by_size.begin(), by_size.end(), [&](size_t a, size_t b) {
    return result.clusters[a].pixels.size() > result.clusters[b].pixels.size();
  });
  // Whether each part lies in each bigger object's solid, tested for every pair on the
  // scan's threads (the pairs are independent), then the owners taken in size order as
  // before: the first bigger object, itself no part, that holds the part.
  std::vector<std::vector<char>> holds(n);
  parallel_for(n, [&](size_t k) {
    const ScanCluster& part = result.clusters[by_size[k]];
    holds[k].assign(k, 0);
    for (size_t j = 0; j < k; ++j) {
      const ScanCluster& big = result.clusters[by_size[j]];
      if (big.shape.primitives.empty() || !(big.support == part.support)) continue;
      const ShapeFit& solid = big.shape.primitives.front();
      if (mostly_inside(solid, part.points, params.part_margin_m, params.part_share)) {
        holds[k][j] = 1;
      } else if (params.part_hang_reach_m > params.part_margin_m && hangs_beside(part, big) &&
                 mostly_inside(solid, part.points, params.part_hang_reach_m, params.part_share)) {
        holds[k][j] = hangs(part, by_size[j]);
      }
    }
  });
  // Whether an object that would hold a part has its extent unseen (it then holds
  // none): asked once per object, not once per part it would hold.
  std::vector<char> unseen_big(n, 0);
  for (size_t j = 0; j < n && params.unseen_hold_no_parts; ++j)
    for (size_t k = j + 1; k < n; ++k)
      if (holds[k][j]) {
        unseen_big[j] = unseen(result.clusters[by_size[j]]);
        break;
      }
  std::vector<int> owner(n, -1);
  for (size_t k = 1; k < n; ++k) {
    bool in_unseen = false;
    for (size_t j = 0; j < k && owner[by_size[k]] < 0; ++j) {
      if (owner[by_size[j]] >= 0) continue;
      if (holds[k][j] && !unseen_big[j]) owner[by_size[k]] = static_cast<int>(by_size[j]);
      in_unseen = in_unseen || (holds[k][j] && unseen_big[j]);
    }
    if (owner[by_size[k]] < 0 && in_unseen)
      for (int i : result.clusters[by_size[k]].pixels) apart[static_cast<size_t>(i)] = 1;
  }
  // A part rising from an object that is itself no part, when nothing is its part.
  for (size_t c = 0; c < n && c < rises_from.size(); ++c) {
    const int o = rises_from[c];
    if (o < 0 || owner[c] >= 0 || owner[static_cast<size_t>(o)] >= 0 ||
        std::find(owner.begin(), owner.end(), static_cast<int>(c)) != owner.end() ||
        (params.unseen_hold_no_parts && unseen(result.clusters[static_cast<size_t>(o)])))
      continue;
    owner[c] = o;
  }
  // Each owner as it was, then its parts (kept to be given back: restore_spoiled).
  std::vector<GrownObject> grown_of(n);
  for (size_t c = 0; c < n; ++c)
    if (owner[c] >= 0 && grown_of[owner[c]].parts.empty())
      grown_of[owner[c]].before = result.clusters[owner[c]];
  for (size_t c = 0; c < n; ++c) {
    if (owner[c] < 0) continue;
    ScanCluster& big = result.clusters[owner[c]];
    for (int i : result.clusters[c].pixels) label[i] = owner[c];
    const auto middle = big.pixels.insert(big.pixels.end(), result.clusters[c].pixels.begin(),
                                          result.clusters[c].pixels.end());
    std::inplace_merge(big.pixels.begin(), middle, big.pixels.end());  // both sorted
    grown_of[owner[c]].parts.push_back(std::move(result.clusters[c]));
  }
  // The objects kept, and the grown ones among them by their new index.
  std::vector<ScanCluster> kept;
  std::vector<GrownObject> grown;
  for (size_t c = 0; c < n; ++c) {
    if (owner[c] >= 0) continue;
    if (!grown_of[c].parts.empty()) {
      grown_of[c].index = kept.size();
      grown.push_back(std::move(grown_of[c]));
    }
    kept.push_back(std::move(result.clusters[c]));
  }
  result.clusters = std::move(kept);
  // Biggest first (the caller's refits cost about their pixels).
  std::stable_sort(grown.begin(), grown.end(), [&](const GrownObject& a, const GrownObject& b) {
    return result.clusters[a.index].pixels.size() > result.clusters[b.index].pixels.size();
  });
  return grown;
}

// The kind of a cluster's shape; none when unknown.
std::optional<ShapeKind> kind_of(const ScanCluster& c) {
  if (c.shape.primitives.empty()) return std::nullopt;
  return c.shape.primitives.front().primitive.kind;
}

// A grown object whose refit is another shape, explaining its points less than it did
// alone by more than `slack`, took what was no part of it: a part a depth edge cut off
// (a handle) leaves its owner's shape as it was, while a neighbour's piece beside its
// solid (one cut off a touching body) bends it into another. It is as it was, each part
// an object again (appended, its pixels labelled so). Returns the objects restored and
// appended.
std::vector<size_t> restore_spoiled(std::vector<GrownObject>& grown,
                                    std::vector<ScanCluster>& clusters, std::vector<int>& label,
                                    double slack) {
  std::vector<size_t> changed;
  for (GrownObject& g : grown) {
    const ScanCluster& now = clusters[g.index];
    const bool worse = now.shape.fit < g.before.shape.fit - slack;
    if (!worse || kind_of(now) == kind_of(g.before)) continue;
    clusters[g.index] = std::move(g.before);
    changed.push_back(g.index);
    for (ScanCluster& part : g.parts) {
      for (int i : part.pixels) label[static_cast<size_t>(i)] = static_cast<int>(clusters.size());
      changed.push_back(clusters.size());
      clusters.push_back(std::move(part));
    }
  }
  return changed;
}

// Objects standing on another object's top are fitted on that top (stacking.h). Returns
// per cluster the object it rises from (a neck on its shoulder, to be merged as its
// part), or -1.
std::vector<int> restack(ScanResult& result, std::vector<std::vector<Vec3>>& normals,
                         const ScanParams& params) {
  std::vector<int> part_of(result.clusters.size(), -1);
  if (!params.stack_on_objects || result.clusters.size() < 2) return part_of;
  // Stacks form on one support at a time: the objects standing on the same surface.
  std::vector<bool> done(result.clusters.size(), false);
  for (size_t first = 0; first < result.clusters.size(); ++first) {
    if (done[first]) continue;
    const Plane support = result.clusters[first].support;
    std::vector<size_t> group;
    for (size_t c = first; c < result.clusters.size(); ++c)
      if (!done[c] && result.clusters[c].support == support) {
        group.push_back(c);
        done[c] = true;
      }
    if (group.size() < 2) continue;
    std::vector<StackedObject> objects(group.size());
    for (size_t g = 0; g < group.size(); ++g) {
      objects[g].points = std::move(result.clusters[group[g]].points);
      objects[g].normals = std::move(normals[group[g]]);
      objects[g].shape = std::move(result.clusters[group[g]].shape);
    }
    NeckParams neck;
    neck.min_slope_deg = params.neck_min_slope_deg;
    neck.max_width_share = params.neck_max_width_share;
    fit_stacked_objects(objects, support, params.shape, kStackBand_m, neck);
    for (size_t g = 0; g < group.size(); ++g) {
      result.clusters[group[g]].points = std::move(objects[g].points);
      normals[group[g]] = std::move(objects[g].normals);
      result.clusters[group[g]].shape = std::move(objects[g].shape);
      if (objects[g].rests_on >= 0)
        result.clusters[group[g]].on_object = static_cast<int>(group[objects[g].rests_on]);
      if (objects[g].part_of >= 0) part_of[group[g]] = static_cast<int>(group[objects[g].part_of]);
    }
  }
  return part_of;
}

}  // namespace

Vec3 effective_up(const ScanParams& params) {
  // A camera pitched down by t sees the world's up rotated about its x axis by t:
  // (0, -1, 0) becomes (0, -cos t, -sin t).
  const double t = params.camera_tilt_deg * 3.14159265358979 / 180.0;
  const Vec3 u = normalized(params.up);
  return normalized(Vec3{u.x, u.y * std::cos(t) - u.z * std::sin(t),
                         u.y * std::sin(t) + u.z * std::cos(t)});
}

// A support found by the plane stage: its plane, its kept regions, their points (full
// resolution) and, once the scan grows it, its hull.
struct Found {
  PlaneFit plane;
  Hull2 hull;
  Hull2 reach;  // the hull grown by overhang_margin_m (empty when 0)
  // A small support's hull grown by seen_part_reach_m, where its surface may run on
  // unseen (empty: none; see there).
  Hull2 around;
  PlaneRegions regions;
  int points = 0;
};

namespace {

// Per support, how far its own surface lies off its plane in units of the noise across
// it (noise_across): a robust sigma (the median of |h| / noise over 0.6745) of its
// regions' pixels (an even sample of at most kMostSamples); at least 1. Above 1 where the
// plane is fitted off (a far table's tilted by degrees) or the sensor bends the surface:
// the band (surface_band) widens with it.
std::vector<double> surface_noise_scale(const Frame& f, const std::vector<Found>& found,
                                        const ScanParams& params) {
  constexpr size_t kMostSamples = 1000, kLeast = 30;
  std::vector<double> scale(found.size(), 1.0);
  if (!params.band_along_ray) return scale;
  for (size_t k = 0; k < found.size(); ++k) {
    const std::vector<int>& members = found[k].regions.members;
    const size_t step = members.size() / kMostSamples + 1;
    std::vector<double> ratio;
    ratio.reserve(members.size() / step + 1);
    for (size_t m = 0; m < members.size(); m += step) {
      const Vec3 p = to_vec(f.points[static_cast<size_t>(members[m])]);
      const double h = dot(found[k].plane.n, p) + found[k].plane.d;
      ratio.push_back(std::abs(h) /
                      std::max(noise_across(params.depth_noise, p, found[k].plane.n), 1e-6));
    }
    if (ratio.size() < kLeast) continue;
    std::nth_element(ratio.begin(), ratio.begin() + ratio.size() / 2, ratio.end());
    scale[k] = std::max(1.0, ratio[ratio.size() / 2] / 0.6745);
  }
  return scale;
}

// Clusters grown around a small support's seen part (seen_part_reach_m: their pixels are
// marked 1 + the support count + its index) are kept when they stand on its plane: the
// lowest point in its band, give or take the clustering tolerance, the surface not running
// on below it (runs_on_below), its top below the height band's, and not one upright face.
// Their pixels are then that support's; the others' leave the prism.
void keep_standing_around(const Frame& f, const std::vector<Found>& found,
                          std::vector<std::vector<int>>& grids, std::vector<char>& mask, int step,
                          const ScanParams& params) {
  const size_t ns = found.size();
  const auto stands = [&](const std::vector<int>& grid, const PlaneFit& plane) {
    double low_h = 1e9, low_z = 0;
    for (int i : grid) {
      const Vec3 p = to_vec(f.points[static_cast<size_t>(i)]);
      if (at_band_top(params, plane, p)) return false;
      const double h = dot(plane.n, p) + plane.d;
      if (h < low_h) low_h = h, low_z = p.z;
    }
    return low_h <= foot_reach(params, low_z) && !runs_on_below(f, grid, step, plane, params);
  };
  std::vector<std::vector<int>> kept;
  kept.reserve(grids.size());
  for (std::vector<int>& grid : grids) {
    const auto m = static_cast<size_t>(mask[static_cast<size_t>(grid.front())]);
    if (m <= ns) {
      kept.push_back(std::move(grid));
      continue;
    }
    const size_t k = m - ns - 1;
    // One upright flat face alone there is the furniture's own panel (a shelf's back
    // between two boards): a prop seen from above shows its top or its curve.
    const bool keep =
        stands(grid, found[k].plane) && !upright_panel(f, grid, found[k].plane.n, params);
    for (int i : grid) mask[static_cast<size_t>(i)] = keep ? static_cast<char>(k + 1) : 0;
    if (keep) kept.push_back(std::move(grid));
  }
  grids = std::move(kept);
}

// Whether `sample` lies on `plane`: its median height above it within `gap` (supports
// lie at least min_support_gap_m apart). False for an empty sample.
bool on_plane(const PlaneFit& plane, const std::vector<Vec3>& sample, double gap) {
  if (sample.empty()) return false;
  std::vector<double> hs;
  hs.reserve(sample.size());
  for (const Vec3& p : sample) hs.push_back(dot(plane.n, p) + plane.d);
  std::nth_element(hs.begin(), hs.begin() + hs.size() / 2, hs.end());
  return std::abs(hs[hs.size() / 2]) < gap;
}

// The area a support's strided pixels cover on its plane: each pixel's footprint at its
// depth, (z / fx)^2 widened by 1 / cos of the view's angle to the plane's normal, times
// the stride's cells. What a count of pixels means in square metres depends on both: a
// board 2 m away seen at a grazing angle covers 30 times a near table's area per pixel.
double seen_area_m2(const Frame& f, const std::vector<int>& members, const PlaneFit& plane,
                    int stride) {
  const double fx = focal_px(f);
  double area = 0;
  for (int i : members) {
    const Vec3 p = to_vec(f.points[static_cast<size_t>(i)]);
    const double r = norm(p);
    // A ray within 2.5 degrees of the plane is seen edge-on: its footprint is unbounded.
    const double cos_view = std::max(0.045, std::abs(dot(plane.n, p)) / std::max(r, 1e-9));
    area += (p.z / fx) * (p.z / fx) / cos_view;
  }
  return area * stride * stride;
}

// Whether a later support's pixels are enough: min_plane_points of them, or (at depth)
// a seen area of min_support_seen_share times min_support_area_m2 (seen_area_m2).
bool holds_support(const Frame& f, const std::vector<int>& members, const PlaneFit& plane,
                   const ScanParams& params) {
  const int stride = std::max(1, params.pixel_stride);
  if (static_cast<long long>(members.size()) * stride * stride >= params.min_plane_points) return true;
  return params.min_support_seen_share > 0 &&
         seen_area_m2(f, members, plane, stride) >=
             params.min_support_seen_share * params.min_support_area_m2;
}

// Whether a region's part seen from above (seen_from_above) is a support: its pixels
// hold one (holds_support) and its hull spans min_support_area_m2.
bool seen_part_is_support(const Frame& f, const PlaneRegions& seen, const PlaneFit& plane,
                          const ScanParams& params) {
  return holds_support(f, seen.members, plane, params) &&
         hull_area(convex_hull(seen.hull_points, plane.n)) >= params.min_support_area_m2;
}

// Where a kept plane's noisy edge can lie: the cells, support_gap_reach_m square on the
// plane, within reach of its regions' pixels. A band within min_support_gap_m of a plane
// is that plane's own far edge, left outside its band by the depth noise, only there:
// the noise moves a point along its ray, support_gap_reach_sigmas of the axial sigma at
// its depth from the surface's seen pixels (3 sigma: 1.8 cm at 2 m, 6 cm at 3.5 m), and
// a cell's reach is its farthest pixel's, in whole cells, one at least (its neighbours).
// Farther away it is another surface at nearly the same height (a shelf's board 5 cm
// above the table's top, 10 cm behind its far edge: fresh rooms 9855). Cells of pixels,
// not the regions' hulls: a table's region holds the strip its band cuts across the wall
// behind it, and a hull spanning the two covers a cabinet top beside the table (unseen
// rooms 7030). Empty with the rule off (never asked then).
struct GapReach {
  Vec3 u, v;
  double cell = 1;
  long a0 = 0, b0 = 0, na = 0, nb = 0;  // the cells' bounds, the widest reach beyond the pixels'
  std::vector<char> near_cells;         // na x nb, 1 at a cell within reach of a region's pixel
  static constexpr long kMaxReachCells = 8;
  // floor(x / cell) as a whole number: the truncation, one less below zero where it
  // rounded up (exact for a finite quotient; std::floor is a library call without SSE4.1).
  static long cell_of(double x, double cell) {
    const double q = x / cell;
    const long t = static_cast<long>(q);
    return t - (static_cast<double>(t) > q);
  }
  long cell_of(double x) const { return cell_of(x, cell); }
  bool near(Vec3 p) const {
    const long a = cell_of(dot(u, p)) - a0;
    const long b = cell_of(dot(v, p)) - b0;
    return a >= 0 && a < na && b >= 0 && b < nb && near_cells[static_cast<size_t>(a * nb + b)];
  }
};

GapReach gap_reach(const Frame& f, const std::vector<PlaneRegions>& regions, const PlaneFit& plane,
                   const ScanParams& params) {
  GapReach r;
  if (params.support_gap_reach_m <= 0) return r;
  // The loops read local copies: their stores (a double, a char) could alias r's fields,
  // which the compiler would then load again per pixel.
  const Vec3 seed = std::abs(plane.n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 u = normalized(cross(plane.n, seed)), v = cross(plane.n, u);
  r.u = u, r.v = v;
  // The pixels' coordinates on the plane and their reach (the depth noise's), and the
  // cells: at most some four million of them whatever the points' spread (a frame of bad
  // depths spans kilometres), coarser cells then, which only widen the reach. The array
  // is sized once: the serial plane stage walks every member here.
  size_t n = 0;
  for (const PlaneRegions& reg : regions) n += reg.members.size();
  std::vector<std::array<double, 3>> uvr;
  uvr.reserve(n);
  double lo_u = std::numeric_limits<double>::infinity(), hi_u = -lo_u, lo_v = lo_u, hi_v = -lo_u;
  double widest = 0;
  for (const PlaneRegions& reg : regions)
    for (int i : reg.members) {
      const Vec3 p = to_vec(f.points[static_cast<size_t>(i)]);
      const double a = dot(u, p), b = dot(v, p),
                   reach = params.support_gap_reach_sigmas * params.depth_noise.sigma_z(p.z);
      uvr.push_back({a, b, reach});
      lo_u = std::min(lo_u, a), hi_u = std::max(hi_u, a), lo_v = std::min(lo_v, b), hi_v = std::max(hi_v, b);
      widest = std::max(widest, reach);
    }
  if (uvr.empty() || !(hi_u >= lo_u) || !(hi_v >= lo_v)) return r;
  r.cell =
      std::max(params.support_gap_reach_m, std::sqrt((hi_u - lo_u + 1) * (hi_v - lo_v + 1) / 4e6));
  const double cell = r.cell;
  // A reach in whole cells, one at least (the neighbours); bounded, as a bad depth's is not.
  // (Within one cell the quotient is at most 1: most pixels skip the division.)
  const auto in_cells = [cell](double reach) {
    if (reach <= cell) return 1L;
    return std::clamp(static_cast<long>(std::ceil(reach / cell)), 1L, GapReach::kMaxReachCells);
  };
  const long margin = in_cells(widest);
  r.a0 = r.cell_of(lo_u) - margin, r.b0 = r.cell_of(lo_v) - margin;
  r.na = r.cell_of(hi_u) + 1 + margin - r.a0, r.nb = r.cell_of(hi_v) + 1 + margin - r.b0;
  const long a0 = r.a0, b0 = r.b0, nb = r.nb;
  // Each cell's reach in cells, 0 where it holds no pixel.
  std::vector<char> held(static_cast<size_t>(r.na * nb), 0);
  for (const auto& [a, b, reach] : uvr) {
    char& c = held[static_cast<size_t>((GapReach::cell_of(a, cell) - a0) * nb +
                                       (GapReach::cell_of(b, cell) - b0))];
    c = static_cast<char>(std::max<long>(c, in_cells(reach)));
  }
  // Each held cell and the cells within its reach are near.
  r.near_cells.assign(held.size(), 0);
  for (long a = 0; a < r.na; ++a)
    for (long b = 0; b < r.nb; ++b)
      if (const long m = held[static_cast<size_t>(a * nb + b)])
        for (long da = -m; da <= m; ++da)
          for (long db = -m; db <= m; ++db)
            r.near_cells[static_cast<size_t>((a + da) * nb + b + db)] = 1;
  return r;
}

// Whether a region meets a kept plane's pixels without a step: over the pairs of grid
// neighbours (one or two grid steps apart along a row or a column), one the region's and
// one the kept plane's (`on_kept` is 1 at the kept plane's strided pixels),
// both on a surface facing up, the median height difference along the plane's normal
// lies within `sigmas` of the depth noise at their depth. A far floor bent by the
// sensor's distortion rises from its plane smoothly (milk_cartoon: 2.5 cm at the image's
// corner); a board above the next section's meets it at a step of its height, and the
// step's face, which joins the two heights, faces sideways. nullopt where they do not
// meet.
std::optional<bool> meets_without_step(const Frame& f, const SurfaceGrid& grid,
                                       const std::vector<int>& members,
                                       const std::vector<char>& on_kept, const PlaneFit& plane,
                                       int stride, double sigmas) {
  const int w = f.width, h = f.height;
  const float ux = static_cast<float>(plane.n.x), uy = static_cast<float>(plane.n.y),
              uz = static_cast<float>(plane.n.z);
  const PointXYZRGB* pts = f.points.data();
  std::vector<double> steps;  // in sigmas
  for (int i : members) {
    const int x = i % w, y = i / w;
    if (!grid.faces_up(i, x, y, ux, uy, uz)) continue;
    const Vec3 p = to_vec(pts[i]);
    for (int k = 1; k <= 2; ++k)
      for (const auto& [dx, dy] :
           {std::pair{k, 0}, std::pair{-k, 0}, std::pair{0, k}, std::pair{0, -k}}) {
        const int nx = x + dx * stride, ny = y + dy * stride;
        if (nx < 0 || nx >= w || ny < 0 || ny >= h) continue;
        const int j = ny * w + nx;
        if (!on_kept[static_cast<size_t>(j)] || !grid.faces_up(j, nx, ny, ux, uy, uz)) continue;
        const Vec3 q = to_vec(pts[j]);
        steps.push_back(std::abs(dot(plane.n, p - q)) / grid.noise.sigma_z(0.5 * (p.z + q.z)));
      }
  }
  if (steps.empty()) return std::nullopt;
  std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2),
                   steps.end());
  return steps[steps.size() / 2] < sigmas;
}

// The mean of the surface's own normals at `pixels` (unit, each turned toward the
// camera), through the neighbours facing_up reads (SurfaceGrid::neighbours); zero when
// none has both neighbours. Each normal follows the surface the pixel lies on, whatever
// plane selected it.
Vec3 mean_surface_normal(const Frame& f, const SurfaceGrid& grid, const std::vector<int>& pixels) {
  const PointXYZRGB* pts = f.points.data();
  Vec3 sum{0, 0, 0};
  for (int i : pixels) {
    const auto [right, down] = grid.neighbours(i, i % f.width, i / f.width);
    if (right < 0 || down < 0) continue;
    const Vec3 p = to_vec(pts[i]);
    const Vec3 n = cross(to_vec(pts[right]) - p, to_vec(pts[down]) - p);
    const double len = norm(n);
    if (!(len > 0)) continue;
    sum = sum + n * ((dot(n, p) < 0 ? 1.0 : -1.0) / len);
  }
  return sum;
}

// Whether a first plane's inliers are a band cut obliquely across a surface steeper
// than any support (a wall, a wardrobe's front): their least-squares plane, or the mean
// of the surface normals at them, faces further than max_plane_angle_deg from up.
// RANSAC takes a triple's plane when it holds the most inliers; a triple on a wall
// tilted toward up within the cone holds a strip of the wall as wide as the band
// allows, which outnumbers a table seen at a grazing angle (unseen 3038: a level camera
// 25 cm above the table, the wall 2.2 m away, its strips six props). find_plane keeps
// such a hypothesis unrefined, as its refit leaves the cone. The strip fitted on its
// own is the wall's plane where its width across the band exceeds the depth noise; where
// the noise is as wide (a wall 2.5 m away cut at 17 degrees: a strip 8 cm tall under
// 1 cm of noise, unseen rooms 7013) the fit keeps the band's tilt, but the normals the
// wall's pixels span with their neighbours are the wall's. A support's inliers fit the
// support and face its way. Every third inlier within the fixed band, as find_plane's refit.
// `grid`: the frame's SurfaceGrid (find_supports builds it once).
bool slices_steep_surface(const Frame& f, const SurfaceGrid& grid, const std::vector<int>& inliers,
                          const PlaneFit& plane, Vec3 up, const ScanParams& params) {
  std::vector<Vec3> pts;
  std::vector<int> sample;
  pts.reserve(inliers.size() / 3 + 1);
  sample.reserve(inliers.size() / 3 + 1);
  for (size_t k = 0; k < inliers.size(); k += 3) {
    const Vec3 p = to_vec(f.points[static_cast<size_t>(inliers[k])]);
    if (std::abs(dot(plane.n, p) + plane.d) < params.plane_distance_m)
      pts.push_back(p), sample.push_back(inliers[k]);
  }
  const double cos_cone = cos_degrees(params.max_plane_angle_deg);
  const PlaneFit fit = fit_plane(pts);
  if (fit.ok && std::abs(dot(fit.n, up)) < cos_cone) return true;
  if (!params.first_plane_normals_up) return false;
  const Vec3 m = mean_surface_normal(f, grid, sample);
  const double len = norm(m);
  return len > 0 && dot(m, up) < cos_cone * len;
}

}  // namespace

namespace {

// The strided pixels with depth within max_depth_m, in raster order, with what the
// plane stage's pool reads of each (its grid cell, its point, its plane band), and the
// counts per grid row and column (the image border). Built in chunks of grid rows on
// the scan's threads, in two passes: the counts per row give each row's place in the
// arrays, then each chunk fills its rows there, so the arrays are the pool's from the
// start (the pool was a copy of a list built pixel by pixel on the calling thread).
struct StridedPixels {
  std::vector<int> index;       // pixel index
  std::vector<GridCell> cells;  // its cell on the strided grid
  std::vector<Vec3> pts;        // its point
  std::vector<double> band;     // plane_band at its depth
  std::vector<int> rows, cols;  // valid strided pixels per grid row and per grid column
};

StridedPixels strided_pixels(const Frame& f, const ScanParams& params, int stride) {
  const int gw = (f.width + stride - 1) / stride, gh = (f.height + stride - 1) / stride;
  StridedPixels s;
  s.rows.assign(static_cast<size_t>(gh), 0);
  s.cols.assign(static_cast<size_t>(gw), 0);
  auto kept = [&](const PointXYZRGB& p) { return has_depth(p) && p.z <= params.max_depth_m; };
  const size_t cells = static_cast<size_t>(gw) * static_cast<size_t>(gh);
  if (!scan_pool || scan_pool->threads() == 1) {
    // One thread: one pass, each kept pixel appended (the passes below read the frame
    // twice, which only pays on two threads). The same pixels in the same order.
    s.index.reserve(cells), s.cells.reserve(cells), s.pts.reserve(cells), s.band.reserve(cells);
    for (int gy = 0; gy < gh; ++gy)
      for (int x = 0, gx = 0; x < f.width; x += stride, ++gx) {
        const int i = gy * stride * f.width + x;
        const PointXYZRGB& p = f.points[static_cast<size_t>(i)];
        if (!kept(p)) continue;
        s.index.push_back(i);
        s.cells.push_back({gx, gy});
        s.pts.push_back(to_vec(p));
        s.band.push_back(plane_band(params, s.pts.back().z));
        ++s.rows[static_cast<size_t>(gy)];
        ++s.cols[static_cast<size_t>(gx)];
      }
    return s;
  }
  // Chunks of 16 grid rows (some 2500 pixels at a 640-pixel width), handed out one at a
  // time: a helper that starts late (woken from sleep) takes fewer of them.
  constexpr int kChunkRows = 16;
  const size_t chunks = static_cast<size_t>((gh + kChunkRows - 1) / kChunkRows);
  auto rows_of = [&](size_t c) {
    return std::pair{static_cast<int>(c) * kChunkRows, std::min(gh, static_cast<int>(c + 1) * kChunkRows)};
  };
  std::vector<std::vector<int>> chunk_cols(chunks);
  // The four arrays are sized for every grid cell while the rows are counted (items 0 to
  // 3, one array each: a fresh array's pages are faulted in and zeroed, 0.24 ms on the
  // milk frame on one thread) and cut to the kept pixels once filled.
  constexpr size_t kArrays = 4;
  parallel_for(kArrays + chunks, [&](size_t item) {
    if (item < kArrays) {
      if (item == 0) s.pts.resize(cells);
      if (item == 1) s.band.resize(cells);
      if (item == 2) s.cells.resize(cells);
      if (item == 3) s.index.resize(cells);
      return;
    }
    const size_t c = item - kArrays;
    std::vector<int>& cols = chunk_cols[c];
    cols.assign(static_cast<size_t>(gw), 0);
    const auto [lo, hi] = rows_of(c);
    for (int gy = lo; gy < hi; ++gy) {
      const PointXYZRGB* row = f.points.data() + static_cast<size_t>(gy) * stride * f.width;
      int n = 0;
      for (int x = 0, gx = 0; x < f.width; x += stride, ++gx)
        if (kept(row[x])) ++n, ++cols[static_cast<size_t>(gx)];
      s.rows[static_cast<size_t>(gy)] = n;
    }
  });
  for (const std::vector<int>& cols : chunk_cols)
    for (size_t gx = 0; gx < s.cols.size(); ++gx) s.cols[gx] += cols[gx];
  std::vector<size_t> start(static_cast<size_t>(gh) + 1, 0);
  for (size_t gy = 0; gy < s.rows.size(); ++gy) start[gy + 1] = start[gy] + static_cast<size_t>(s.rows[gy]);
  parallel_for(chunks, [&](size_t c) {
    const auto [lo, hi] = rows_of(c);
    size_t k = start[static_cast<size_t>(lo)];
    for (int gy = lo; gy < hi; ++gy) {
      const int y = gy * stride;
      for (int x = 0, gx = 0; x < f.width; x += stride, ++gx) {
        const int i = y * f.width + x;
        const PointXYZRGB& p = f.points[static_cast<size_t>(i)];
        if (!kept(p)) continue;
        s.index[k] = i;
        s.cells[k] = {gx, gy};
        s.pts[k] = to_vec(p);
        s.band[k] = plane_band(params, s.pts[k].z);
        ++k;
      }
    }
  });
  const size_t n = start.back();
  s.index.resize(n);
  s.cells.resize(n);
  s.pts.resize(n);
  s.band.resize(n);
  return s;
}

}  // namespace

namespace {

// How far beyond `room` stands_at_far_edge looks for the support's surface, in steps
// of a centimetre: an object's silhouette overhangs the near edge (a ball's lowest
// pixels lie in front of its contact, past a table's front edge), and the surface
// behind it shows within a few centimetres.
constexpr double kFarEdgeLookAhead = 0.5, kFarEdgeStep = 0.01;

// Whether the cluster stands at or past its support's far edge rather than on it: in
// more than half of its image columns (at least three) none of the `surface` hulls (the
// support's regions on its plane: a board seen between objects is several) holds a
// point from `room(z)` to kFarEdgeLookAhead beyond that behind the column's lowest pixel
// laid on the plane, along the view. What stands on a surface has the surface under its
// whole depth, hidden behind its face.
bool stands_at_far_edge(const Frame& f, const std::vector<int>& grid, const PlaneFit& plane,
                        const std::vector<const Hull2*>& surface, const ToleranceAt& room) {
  const std::vector<std::pair<int, int>> lowest = end_per_column(f, grid, false);
  if (lowest.size() < 3) return false;
  const auto on_surface = [&](Vec3 q) {
    return std::any_of(surface.begin(), surface.end(),
                       [&](const Hull2* h) { return h->contains(q); });
  };
  const Vec3 ahead = normalized(Vec3{0, 0, 1} - plane.n * plane.n.z);
  size_t at_edge = 0;
  for (const auto& [col, i] : lowest) {
    const Vec3 p = to_vec(f.points[static_cast<size_t>(i)]);
    const Vec3 foot = p - plane.n * (dot(plane.n, p) + plane.d);
    const double from = room(p.z);
    bool behind = false;
    for (double t = from; t <= from + kFarEdgeLookAhead && !behind; t += kFarEdgeStep)
      behind = on_surface(foot + ahead * t);
    at_edge += !behind;
  }
  return 2 * at_edge > lowest.size();
}

// Whether an upright face (its normal `face`) is at least `share` as wide as the
// support's hull along the face laid on the plane (normal `up`): a face as wide as the
// surface it stands on is that furniture's, not a prop on it.
bool spans_support(const Frame& f, const std::vector<int>& grid, Vec3 face, Vec3 up,
                   const Hull2& hull, double share) {
  if (grid.empty() || hull.pts.size() < 3) return false;
  const Vec3 along = normalized(cross(up, face));
  const double da = dot(along, hull.u), db = dot(along, hull.v);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int i : grid) {
    const double t = dot(along, to_vec(f.points[static_cast<size_t>(i)]));
    lo = std::min(lo, t), hi = std::max(hi, t);
  }
  double hull_lo = std::numeric_limits<double>::infinity(), hull_hi = -hull_lo;
  for (const auto& q : hull.pts) {
    const double t = q[0] * da + q[1] * db;
    hull_lo = std::min(hull_lo, t), hull_hi = std::max(hull_hi, t);
  }
  return hi - lo >= share * (hull_hi - hull_lo);
}

}  // namespace

// Whether `regions` of `plane` are seen from fewer than grazing_support_deg above it:
// the camera's height over the plane against the regions' mean range.
bool seen_at_grazing(const Frame& f, const std::vector<PlaneRegions>& regions,
                     const PlaneFit& plane, const ScanParams& params) {
  double range = 0;
  size_t n = 0;
  for (const PlaneRegions& r : regions)
    for (int i : r.members) range += norm(to_vec(f.points[static_cast<size_t>(i)])), ++n;
  if (n == 0 || params.grazing_support_deg <= 0) return false;
  return plane.d < range / static_cast<double>(n) * sin_degrees(params.grazing_support_deg);
}

// The rays crossing `plane` within the joint hull of `regions`: those that end on it
// (a point within its band) and those that see past it (a point below it by more than
// its band), of which those ending on another support (`on_support`, by pixel).
struct RaysThrough {
  size_t on = 0, through = 0, through_support = 0;
};

RaysThrough rays_through(const Frame& f, const std::vector<PlaneRegions>& regions,
                         const PlaneFit& plane, const std::vector<char>& on_support,
                         const ScanParams& params) {
  std::vector<Vec3> hull_points;
  for (const PlaneRegions& r : regions)
    hull_points.insert(hull_points.end(), r.hull_points.begin(), r.hull_points.end());
  const Hull2 hull = convex_hull(hull_points, plane.n);
  const int stride = std::max(1, params.pixel_stride);
  RaysThrough rays;
  for (int y = 0; y < f.height; y += stride)
    for (int x = 0; x < f.width; x += stride) {
      const size_t i = static_cast<size_t>(y) * f.width + x;
      if (!has_depth(f.points[i])) continue;
      const Vec3 p = to_vec(f.points[i]);
      const double h = dot(plane.n, p) + plane.d, band = plane_band(params, p.z);
      if (std::abs(h) < band) {
        rays.on += hull.contains(p);
      } else if (h < -band && hull.contains(p * (-plane.d / dot(plane.n, p)))) {
        ++rays.through;
        rays.through_support += on_support[i] != 0;
      }
    }
  return rays;
}

namespace {

// A plane fitted by least squares with each point weighted by the inverse of the
// camera's axial noise variance at its depth, with what tells how well it is known.
struct WeightedPlane {
  PlaneFit fit;            // its normal on `toward`'s side
  double sigma = 0;        // the residuals' spread, in units of each point's sigma_z
  Eigen::Matrix3d axes;    // the scatter's eigenvectors (normal first) ...
  Eigen::Vector3d spread;  // ... and eigenvalues
  Eigen::Vector3d mean;
  double weight = 0;  // the weights' sum
  // The normal's standard error about its worse-known axis, radians.
  double tilt_se() const { return sigma / std::sqrt(spread(1)); }
  // How far `other` lies from this fit, tilt and height at the mean together, in this
  // fit's standard errors squared (a chi-square of three degrees of freedom).
  double joint_chi2(const PlaneFit& other) const {
    const Eigen::Vector3d n(other.n.x, other.n.y, other.n.z);
    const double t1 = n.dot(axes.col(1)), t2 = n.dot(axes.col(2));
    const double h = n.dot(mean) + other.d;
    return (t1 * t1 * spread(1) + t2 * t2 * spread(2) + h * h * weight) / (sigma * sigma);
  }
};

WeightedPlane weighted_plane(const std::vector<Vec3>& pts, Vec3 toward, const DepthNoise& noise) {
  WeightedPlane out;
  if (pts.size() < 50) return out;
  std::vector<double> w(pts.size());
  for (size_t k = 0; k < pts.size(); ++k)
    w[k] = 1 / (noise.sigma_z(pts[k].z) * noise.sigma_z(pts[k].z));
  const WeightedScatter ws = weighted_point_scatter(pts, w);
  const Eigen::Vector3d& mean = ws.mean;
  out.weight = ws.weight;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(ws.scatter);
  out.axes = es.eigenvectors();
  out.spread = es.eigenvalues();
  out.mean = mean;
  const double var = out.spread(0) / static_cast<double>(pts.size() - 3);
  if (!(var > 0) || !(out.spread(1) > 0)) return out;
  out.sigma = std::sqrt(var);
  Eigen::Vector3d n = out.axes.col(0);
  if (n.dot(Eigen::Vector3d(toward.x, toward.y, toward.z)) < 0) n = -n;
  out.fit = {{n.x(), n.y(), n.z()}, -n.dot(mean), true};
  return out;
}

// Rounds of the trim below: each keeps the pixels within kTrimSigmas robust sigmas of
// the last fit; four bring a table's fit from its band's outliers onto its surface.
constexpr int kTrimRounds = 4;
constexpr double kTrimSigmas = 2.5;

// weighted_plane on `in`, then trimmed and fitted again `rounds` times, the sigma
// taken from the median absolute residual (in units of each point's sigma_z): the
// outliers to one side of a band (objects' feet, a support's front edge) lean a least-
// squares fit toward them; the median does not.
WeightedPlane trimmed_plane(const std::vector<Vec3>& in, Vec3 toward, const DepthNoise& noise,
                            int rounds = kTrimRounds) {
  WeightedPlane own = weighted_plane(in, toward, noise);
  std::vector<double> residual(in.size()), sorted;
  std::vector<Vec3> kept;
  for (int round = 0; round < rounds && own.fit.ok; ++round) {
    for (size_t k = 0; k < in.size(); ++k)
      residual[k] = std::abs(dot(own.fit.n, in[k]) + own.fit.d) / noise.sigma_z(in[k].z);
    sorted = residual;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    // A normal distribution's sigma from its median absolute residual.
    const double robust_sigma = 1.4826 * sorted[sorted.size() / 2];
    kept.clear();
    for (size_t k = 0; k < in.size(); ++k)
      if (residual[k] < kTrimSigmas * robust_sigma) kept.push_back(in[k]);
    own = weighted_plane(kept, toward, noise);
  }
  return own;
}

// Which of `members` (strided pixels) lie on a surface facing `n`'s way: the normal of
// the members within kFaceWindow grid steps around each (at least kFaceLeast of them)
// within `max_deg` of `n` (0: all of them). A vertical face in the band (a table's apron seen from
// just above its height, a wall where the plane meets it) lies along any plane through its strip
// and to one side of the surface: the fit leans toward it (unseen 3038: the apron was 45 % of the
// table's pixels, its plane 1.6 degrees off). A pixel is one of some 25 in its window, so which
// pixels stay hardly depends on their own depth errors (the normal through a pixel and two
// neighbours does: a fit on those pixels leaned by 1.1 degrees on tuned 2023).
constexpr int kFaceWindow = 2;
constexpr size_t kFaceLeast = 6;
std::vector<char> facing_plane(const Frame& f, const std::vector<int>& members, int stride, Vec3 n,
                               double max_deg) {
  if (max_deg <= 0) return std::vector<char>(members.size(), 1);
  const std::unordered_set<int> member_set(members.begin(), members.end());
  std::vector<char> keep(members.size(), 0);
  const int reach = kFaceWindow * stride;
  std::vector<Vec3> window;
  for (size_t k = 0; k < members.size(); ++k) {
    const int x = members[k] % f.width, y = members[k] / f.width;
    window.clear();
    for (int dy = -reach; dy <= reach; dy += stride)
      for (int dx = -reach; dx <= reach; dx += stride) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= f.width || yy >= f.height) continue;
        const int j = yy * f.width + xx;
        if (member_set.count(j)) window.push_back(to_vec(f.points[static_cast<size_t>(j)]));
      }
    if (window.size() < kFaceLeast) continue;
    const Eigen::Vector3d e = smallest_eigenvector(point_scatter(window).scatter);
    keep[k] = std::abs(e.x() * n.x + e.y() * n.y + e.z() * n.z) >= cos_degrees(max_deg);
  }
  return keep;
}

// The median of `pts`' distances from `plane`, each in units of the axial noise at its
// depth.
double median_abs_residual(const std::vector<Vec3>& pts, const PlaneFit& plane,
                           const DepthNoise& noise) {
  std::vector<double> r;
  r.reserve(pts.size());
  for (const Vec3& q : pts) r.push_back(std::abs(dot(plane.n, q) + plane.d) / noise.sigma_z(q.z));
  if (r.empty()) return 0;
  std::nth_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(r.size() / 2), r.end());
  return r[r.size() / 2];
}

// A support region's own plane: least squares on its pixels in the band, each weighted
// by the inverse of the camera's axial noise variance at its depth, then trimmed and
// fitted again kTrimRounds times, the sigma taken from the median absolute residual. The
// band holds the objects' feet and the top of the support's front edge, outliers to one
// side the fit leans toward; the median does not. (Only the pixels facing up, as the
// plane search takes them, gave a table seen at a slant (tuned 2023) a tilt of 1.1
// degrees: which pixels the noise turns up depends on their own depth errors.)
// One plane through two surfaces a few centimetres apart (a table and a lower cabinet
// beside it, each its own region) tilts to pass both; each region alone lies flat. The
// region keeps `joint` (nullopt) unless the joint plane's tilt and height, in the own fit's
// standard errors, lie support_fit_sigmas from it and that fit's tilt is known to within
// support_fit_max_se_deg (a narrow strip's tilt is not: the noise along it is not
// independent from pixel to pixel).
std::optional<PlaneFit> region_plane(const Frame& f, const std::vector<int>& members,
                                     const PlaneFit& joint, const ScanParams& params) {
  if (params.support_fit_sigmas <= 0) return std::nullopt;
  std::vector<Vec3> in;
  const std::vector<char> facing = facing_plane(f, members, std::max(1, params.pixel_stride),
                                                joint.n, params.support_fit_facing_deg);
  for (size_t k = 0; k < members.size(); ++k) {
    const Vec3 q = to_vec(f.points[static_cast<size_t>(members[k])]);
    if (facing[k] && std::abs(dot(joint.n, q) + joint.d) < plane_band(params, q.z)) in.push_back(q);
  }
  const WeightedPlane own = trimmed_plane(in, joint.n, params.depth_noise);
  if (!own.fit.ok) return std::nullopt;
  const double z = params.support_fit_sigmas;
  const bool apart = own.joint_chi2(joint) > z * z;
  const bool sure = own.tilt_se() < params.support_fit_max_se_deg * std::numbers::pi / 180;
  const bool near = dot(own.fit.n, joint.n) >= cos_degrees(0.5 * params.max_support_tilt_deg);
  // ... and it explains the pixels better than the found plane by their median distance
  // (least median of squares: half of them may be another surface's). A far region
  // whose band holds a chair's seat behind the table leans toward the seat, and its
  // standard errors do not show it (unseen rooms 7030: 1.5 degrees off the truth, the
  // found plane 0.03).
  const double joint_median = median_abs_residual(in, joint, params.depth_noise);
  const bool better = !params.support_fit_median_test ||
                      median_abs_residual(in, own.fit, params.depth_noise) < joint_median;
  if (apart && sure && near && better && own.fit.d > 0) return own.fit;
  // Its tilt unsure (a small top far away), its height is not: the joint plane through
  // its pixels' weighted mean, when that lies support_fit_sigmas of the height's standard
  // error and more than the fixed band off the joint plane, and lies nearer its pixels.
  if (!sure && params.support_fit_height_alone) {
    const double h = dot(joint.n, Vec3{own.mean.x(), own.mean.y(), own.mean.z()}) + joint.d;
    const PlaneFit shifted{joint.n, joint.d - h, true};
    const bool off =
        h * h * own.weight > z * z * own.sigma * own.sigma && std::abs(h) > params.plane_distance_m;
    if (off && shifted.d > 0 && median_abs_residual(in, shifted, params.depth_noise) < joint_median)
      return shifted;
  }
  return std::nullopt;
}

// A region's members once it lies on its own plane: the strided pixels inside its hull
// within that plane's band that lie in no other plane's regions. Those found with the
// joint plane lie in its band: on a plane a centimetre off it, the region would keep
// pixels beneath its surface and lack the ones just above, and an object's foot would
// stand on none of its pixels (unseen 3038's bottle, flagged partial as one upright face
// whose foot is unseen).
std::vector<int> members_on(const Frame& f, const PlaneRegions& region, const PlaneFit& own,
                            const ScanParams& params, const std::vector<int>& strided,
                            const std::vector<int>& plane_of, size_t plane_index) {
  const Hull2 hull = convex_hull(region.hull_points, own.n);
  std::vector<int> out;
  for (int i : strided) {
    const int o = plane_of[static_cast<size_t>(i)];
    if (o >= 0 && o != static_cast<int>(plane_index)) continue;
    const Vec3 p = to_vec(f.points[static_cast<size_t>(i)]);
    if (std::abs(dot(own.n, p) + own.d) < plane_band(params, p.z) && hull.contains(p))
      out.push_back(i);
  }
  return out;
}

}  // namespace

// Rounds of first_plane_noise_fit at most, and the turn of the normal under which the
// fit has settled: far from its start a round moves it a few degrees, settled far
// less than the noise leaves unsure. Each round fits every kNoiseFitSample-th pool
// point: a support's thousands are plenty for three parameters, and the fit is asked
// of every frame.
constexpr int kNoiseFitRounds = 10;
constexpr double kNoiseFitSettled_rad = 1e-4;
constexpr size_t kNoiseFitSample = 8;

// The first plane fitted again on the sensor's noise model (first_plane_noise_fit): the
// pool points within each one's noise band of the plane (`band`, plane_band at its
// depth), fitted by trimmed_plane, round after round from the new plane until it
// settles. RANSAC's plane comes from three points and its fixed band, which on a floor
// 3 m away is under one sigma_z: the band keeps the strip the triple's plane cuts from
// the floor, and least squares on a strip that narrow returns the triple's own tilt (a
// camera tilted 49 degrees over plain 6102's floor: every support 9 degrees off). Each
// round's band, as wide as the noise, takes in more of the surface the plane lies on.
// A round whose plane leaves `max_angle_deg` of `up` ends the rounds before it.
PlaneFit noise_fit_plane(const std::vector<Vec3>& pool, const std::vector<double>& band,
                         PlaneFit plane, Vec3 up, double max_angle_deg, const DepthNoise& noise) {
  std::vector<Vec3> in;
  for (int round = 0; round < kNoiseFitRounds; ++round) {
    in.clear();
    for (size_t k = 0; k < pool.size(); k += kNoiseFitSample)
      if (std::abs(dot(plane.n, pool[k]) + plane.d) < band[k]) in.push_back(pool[k]);
    const WeightedPlane own = trimmed_plane(in, up, noise, 1);
    if (!own.fit.ok || dot(own.fit.n, up) < cos_degrees(max_angle_deg) || own.fit.d <= 0) break;
    const double turn = std::acos(std::min(1.0, dot(own.fit.n, plane.n)));
    plane = own.fit;
    if (turn < kNoiseFitSettled_rad) break;
  }
  return plane;
}

// Every support: planes extracted one after another, each one's inliers leaving the
// search. A plane counts when its kept regions hold min_plane_points. Kept out of line
// so the plane stage shows on its own in a profile.
// `strided`: strided_pixels' arrays, which become the pool (its index is copied: the
// prism stage reads the strided pixels after this).
[[gnu::noinline]] std::vector<Found> find_supports(const Frame& f, const ScanParams& params,
                                                   StridedPixels& strided, Vec3 up,
                                                   std::mt19937_64& rng) {
  const int stride = std::max(1, params.pixel_stride);
  const SurfaceGrid normals = surface_grid(f, params);  // the up-facing test's neighbours
  const double cos_tilt = cos_degrees(params.max_support_tilt_deg);
  std::vector<Found> found;
  std::vector<char> free(f.points.size(), 0);
  for (int i : strided.index) free[i] = 1;
  std::vector<int> pool = strided.index;
  std::vector<GridCell> pool_cells = std::move(strided.cells);
  std::vector<Vec3> pool_pts = std::move(strided.pts);
  std::vector<double> pool_band = std::move(strided.band);  // each pool point's plane band
  const int min_region = std::max(1, params.min_plane_points / (4 * stride * stride));
  std::vector<std::pair<PlaneFit, std::vector<PlaneRegions>>> planes;
  std::vector<int> inliers;
  std::vector<GridCell> inlier_cells;
  // After the first plane: which pool points face up (facing_up), the later searches'
  // candidates. The loop ends when no band of them is as large as a support's smallest
  // region, so every horizontal surface of support size is tried, however many walls
  // and objects the frame holds; max_planes bounds the supports kept.
  std::vector<char> pool_up;
  std::vector<double> pool_h;  // with pool_up: each pool point's height above the first plane
  bool up_ready = false;
  std::vector<char> first_up;   // pool_up and pool_h of the plane last tried as the first
  std::vector<double> first_h;
  // Up-facing points within min_support_gap_m of a kept plane can give no later support
  // (supports lie that far apart, below): they leave the candidates with its inliers.
  // Only within a kept plane's reach (gap_reach): a board 3 cm below the table's height
  // against the wall behind it is another surface, not the table's noisy edge.
  std::vector<GapReach> reach;  // per kept plane
  // Per kept plane, found when the regions' gap test below first asks (it seldom does):
  // its regions' hull on its plane, and whether it can be a support beside the floor (a
  // region of it, seen from above, holds one and spans min_support_area_m2, as the
  // supports are made below; -1 until asked).
  std::vector<std::optional<Hull2>> kept_hull;
  std::vector<signed char> kept_holds;
  const auto hull_of = [&](size_t o) -> const Hull2& {
    if (!kept_hull[o]) {
      std::vector<Vec3> hull_points;
      for (const PlaneRegions& r : planes[o].second)
        hull_points.insert(hull_points.end(), r.hull_points.begin(), r.hull_points.end());
      kept_hull[o] = convex_hull(hull_points, planes[o].first.n);
    }
    return *kept_hull[o];
  };
  const auto holds_one = [&](size_t o) {
    if (kept_holds[o] < 0) {
      const PlaneFit& plane = planes[o].first;
      kept_holds[o] = 0;
      for (const PlaneRegions& r : planes[o].second) {
        if (seen_part_is_support(f, seen_from_above(f, r, plane, params), plane, params)) {
          kept_holds[o] = 1;
          break;
        }
      }
    }
    return kept_holds[o] == 1;
  };
  // The strided pixels of the kept plane meets_without_step last asked about.
  std::vector<char> on_kept;
  size_t on_kept_plane = std::numeric_limits<size_t>::max();
  auto near_kept = [&](size_t kept, Vec3 p) {
    return params.support_gap_reach_m <= 0 || reach[kept].near(p);
  };
  auto clear_near = [&](size_t kept_index) {
    const PlaneFit& kept = planes[kept_index].first;
    for (size_t k = 0; k < pool.size(); ++k)
      if (pool_up[k] && std::abs(dot(kept.n, pool_pts[k]) + kept.d) < params.min_support_gap_m &&
          near_kept(kept_index, pool_pts[k]))
        pool_up[k] = 0;
  };
  while (static_cast<int>(planes.size()) < params.max_planes && pool.size() >= 50) {
    // A plane holds at most the whole pool: when that is below min_plane_points no
    // search can give one (the search would end the loop the same way).
    if (static_cast<long long>(pool.size()) * stride * stride < params.min_plane_points) break;
    if (!planes.empty() && !up_ready) {
      // Found beside the first plane's regions (below), for this pool and this plane.
      pool_up = std::move(first_up);
      pool_h = std::move(first_h);
      up_ready = true;
      clear_near(0);
    }
    int peak = 0;
    double peak_height = 0;
    std::vector<size_t> at_peak;  // the pool's up-facing points in the peak's band
    PlaneSearch ps = planes.empty() ? find_plane(f, params, up, params.max_plane_angle_deg, pool,
                                                 pool_pts, free, false, rng)
                                    : find_parallel_plane(
                                          params, planes.front().first, pool_pts, pool_h, pool_up,
                                          0.5 * params.max_support_tilt_deg, peak, peak_height);
    // The first plane fitted on the noise model replaces RANSAC's when it turns it by
    // noise_fit_min_turn_deg or more (scanner.h says why).
    if (planes.empty() && ps.plane.ok && params.first_plane_noise_fit) {
      const PlaneFit fitted = noise_fit_plane(pool_pts, pool_band, ps.plane, up,
                                              params.max_plane_angle_deg, params.depth_noise);
      if (dot(fitted.n, ps.plane.n) <= cos_degrees(params.noise_fit_min_turn_deg))
        ps.plane = fitted;
    }
    // A band with fewer up-facing points than a support's smallest region holds no
    // support. Seen at a grazing angle (a level camera 26 cm above a table 2.5 m away)
    // a fifth of a table's pixels still face up: dropout takes most of the rest.
    if (!planes.empty() && peak < min_region) break;
    if (!ps.plane.ok) break;
    if (!planes.empty()) {
      // The up-facing points of the peak's band (its pair of bins, peak_height +- band).
      const double band = params.plane_distance_m;
      for (size_t k = 0; k < pool.size(); ++k)
        if (pool_up[k] && pool_h[k] >= peak_height - 1.5 * band && pool_h[k] < peak_height + 1.5 * band)
          at_peak.push_back(k);
      // The band an earlier support's own (its noisy far edge left outside its band;
      // supports lie min_support_gap_m apart, below): these points leave the
      // candidates, and the next band is tried.
      std::vector<Vec3> sample;
      for (size_t m = 0; m < at_peak.size(); m += 7) sample.push_back(pool_pts[at_peak[m]]);
      // Within each earlier plane's reach only (gap_reach): there the points near it
      // leave, and a band beyond it (a board against the wall) is tried again.
      bool echo = false;
      for (size_t o = 0; o < planes.size() && !echo; ++o) {
        std::vector<Vec3> near_sample;
        for (const Vec3& q : sample)
          if (near_kept(o, q)) near_sample.push_back(q);
        echo = on_plane(planes[o].first, near_sample, params.min_support_gap_m);
        if (echo)
          for (size_t k : at_peak)
            if (near_kept(o, pool_pts[k])) pool_up[k] = 0;
      }
      if (echo) continue;
    }
    // One pass finds the inliers for the regions and for leaving the pool, and counts
    // those within the fixed band: a first plane holding fewer than min_plane_points
    // there ends the search (find_plane's count, once its own pass over the pool).
    inliers.clear();
    inlier_cells.clear();
    int fixed_band_inliers = 0;
    for (size_t k = 0; k < pool.size(); ++k) {
      const double h = std::abs(dot(ps.plane.n, pool_pts[k]) + ps.plane.d);
      fixed_band_inliers += h < params.plane_distance_m;
      if (h < pool_band[k]) {
        inliers.push_back(pool[k]);
        inlier_cells.push_back(pool_cells[k]);
      }
    }
    if (planes.empty() && fixed_band_inliers * stride * stride < params.min_plane_points) break;
    if (!planes.empty() && !holds_support(f, inliers, ps.plane, params)) {
      // Too few points at this height (an object's top): its up-facing points leave
      // the candidates, and the next band is tried.
      for (size_t k : at_peak) pool_up[k] = 0;
      continue;
    }
    // The regions and the pool's compaction read only the inliers: two items on the
    // scan's threads. Beside the first plane's regions the compacted pool's up-facing
    // points and heights above that plane are found too (facing_up), which the next
    // search reads once the plane counts (at the loop's top); they are found again for
    // the next plane tried as the first should this one not count.
    // A first plane's test against a band cut across a wall (slices_steep_surface) reads
    // only its inliers too: a third item, its answer read once the regions count. Its
    // reach (gap_reach) follows its regions in their item: no test below changes a first
    // plane's regions, so they are the ones it is kept with.
    std::vector<PlaneRegions> regions;
    const bool first_plane = planes.empty();
    const bool test_steep = first_plane && params.first_plane_fits_up;
    bool steep = false;
    GapReach first_reach;
    parallel_for(test_steep ? 3 : 2, [&](size_t job) {
      if (job == 0) {
        regions = plane_regions(f, inliers, inlier_cells, stride, min_region, true);
        if (first_plane) first_reach = gap_reach(f, regions, ps.plane, params);
        return;
      }
      if (job == 2) {
        steep = slices_steep_surface(f, normals, inliers, ps.plane, up, params);
        return;
      }
      // Its inliers leave the search whether it counts or not (an object's top).
      for (int i : inliers) free[i] = 0;
      size_t kept = 0;
      for (size_t k = 0; k < pool.size(); ++k)
        if (free[pool[k]]) {
          if (up_ready) pool_up[kept] = pool_up[k], pool_h[kept] = pool_h[k];
          pool_band[kept] = pool_band[k];
          pool[kept] = pool[k], pool_cells[kept] = pool_cells[k], pool_pts[kept++] = pool_pts[k];
        }
      pool.resize(kept);
      pool_band.resize(kept);
      pool_cells.resize(kept);
      pool_pts.resize(kept);
      if (up_ready) pool_up.resize(kept), pool_h.resize(kept);
      if (first_plane) {
        first_up = facing_up(normals, pool, pool_cells, stride, ps.plane.n);
        first_h.resize(pool.size());
        for (size_t k = 0; k < pool.size(); ++k) first_h[k] = dot(ps.plane.n, pool_pts[k]) + ps.plane.d;
      }
    });
    // A first plane counts its regions' pixels; a later one asks holds_support of them.
    size_t member_count = 0;
    for (const PlaneRegions& r : regions) member_count += r.members.size();
    if (first_plane) {
      if (static_cast<long long>(member_count) * stride * stride < params.min_plane_points) continue;
    } else {
      std::vector<int> members;
      members.reserve(member_count);
      for (const PlaneRegions& r : regions) members.insert(members.end(), r.members.begin(), r.members.end());
      if (!holds_support(f, members, ps.plane, params)) continue;
    }
    // The first plane is a surface facing up, not a band cut obliquely across a wall
    // (slices_steep_surface); its inliers have left the pool, and the search goes on.
    if (test_steep && steep) continue;
    // Later supports share the first one's up once refined (single RANSAC triples on
    // a far, noisy floor scatter by more than that).
    if (!planes.empty() && dot(ps.plane.n, planes.front().first.n) < cos_tilt) continue;
    // ... with the camera clearly above them: a plane at the camera's own height (a
    // box's top level with the lens) is seen edge-on and shows nothing standing on it.
    if (!planes.empty() && ps.plane.d < params.min_support_gap_m) continue;
    // ... and lie clearly above or below every earlier one where they are seen: a
    // plane through the far floor's noise is not a second support.
    if (params.support_gap_reach_m <= 0) {
      std::vector<Vec3> sample;
      for (const PlaneRegions& r : regions)
        for (size_t m = 0; m < r.members.size(); m += 7) sample.push_back(to_vec(f.points[r.members[m]]));
      bool apart = true;
      for (const auto& [other, other_regions] : planes)
        apart = apart && !on_plane(other, sample, params.min_support_gap_m);
      if (!apart) continue;
    } else {
      // Region by region, within each earlier plane's reach (gap_reach): a board
      // beyond the table's reach stays though the table's noisy edge at its height
      // does not. A region lying mostly beyond the reach and outside the plane's hull is
      // another surface, though its end touches it (fresh rooms 9839: a board 2 m away,
      // 5 cm above the next section's, a sixteenth of it beside that one); over the hull
      // it stands on the plane (a low box's top: OSD learn20, a box 5.5 cm tall, whose
      // top's edges alone lie in the table's reach). The floor bent by the sensor's
      // distortion where it reaches the image's corners is the floor too: it meets the
      // floor without a step (meets_without_step). A table's neighbour that does is
      // kept: a second table, or the far part of one tilted off the floor's up. Only a
      // plane that can be a support (the lowest, or one of whose regions holds one)
      // claims a region so: a band 1.7 cm above a board, kept as a plane and dropped
      // below with no region holding a support seen from above, took the board's region
      // as its edge (held-out room 5041: the torus on the board, 1.7 m away, missed).
      size_t lowest_kept = 0;
      for (size_t o = 1; o < planes.size(); ++o)
        if (planes[o].first.d > planes[lowest_kept].first.d) lowest_kept = o;
      const auto claims = [&](size_t o) {
        return !params.edges_of_supports_only || o == lowest_kept || holds_one(o);
      };
      // Whether region r is kept plane o's noisy edge or stands on it.
      const auto edge_of = [&](const PlaneRegions& r, size_t o) {
        std::vector<Vec3> sampled, sample;  // every seventh pixel, and those in o's reach
        for (size_t m = 0; m < r.members.size(); m += 7) {
          sampled.push_back(to_vec(f.points[r.members[m]]));
          if (near_kept(o, sampled.back())) sample.push_back(sampled.back());
        }
        if (!on_plane(planes[o].first, sample, params.min_support_gap_m)) return false;
        const double least = params.support_edge_min_share * static_cast<double>(sampled.size());
        if (static_cast<double>(sample.size()) >= least) return claims(o);
        const Hull2& hull = hull_of(o);
        const auto over =
            std::count_if(sampled.begin(), sampled.end(), [&](Vec3 q) { return hull.contains(q); });
        if (static_cast<double>(over) >= least) return claims(o);
        if (o != lowest_kept || params.support_floor_step_sigmas <= 0) return false;
        if (on_kept_plane != o) {
          on_kept.assign(f.points.size(), 0);
          for (const PlaneRegions& k : planes[o].second)
            for (int i : k.members) on_kept[static_cast<size_t>(i)] = 1;
          on_kept_plane = o;
        }
        return meets_without_step(f, normals, r.members, on_kept, planes[o].first, stride,
                                  params.support_floor_step_sigmas)
            .value_or(false);
      };
      std::erase_if(regions, [&](const PlaneRegions& r) {
        for (size_t o = 0; o < planes.size(); ++o)
          if (edge_of(r, o)) return true;
        return false;
      });
      if (regions.empty()) continue;
    }
    // A later plane is a support only where it is seen from above (seen_from_above): a
    // height band across a wall behind the table holds up-facing points where the depth
    // noise tilts its normals, but no column of it runs away from the camera. Without
    // this, such a band below the table was taken for the floor (the lowest plane keeps
    // all its regions: samples/recordings/tabletop's wall, 32 cm below its table).
    // A region with no part seen from above is such a band, no part of the support
    // (params.support_regions_seen_only).
    if (!planes.empty()) {
      std::vector<int> above;
      std::vector<PlaneRegions> kept;
      for (PlaneRegions& r : regions) {
        const std::vector<int> seen = seen_from_above(f, r, ps.plane, params).members;
        above.insert(above.end(), seen.begin(), seen.end());
        if (!seen.empty() || !params.support_regions_seen_only) kept.push_back(std::move(r));
      }
      if (!holds_support(f, above, ps.plane, params)) continue;
      regions = std::move(kept);
    }
    kept_hull.emplace_back();
    kept_holds.push_back(-1);
    planes.emplace_back(ps.plane, std::move(regions));
    reach.push_back(first_plane ? std::move(first_reach) : gap_reach(f, planes.back().second, ps.plane, params));
    if (up_ready) clear_near(planes.size() - 1);
  }
  // The lowest plane is the floor (or the one support seen): one support of all its
  // regions, as a floor seen between furniture is one floor. Every other plane gives
  // one support per region (a box's top and a cabinet's top at one height are two),
  // each spanning at least min_support_area_m2.
  size_t lowest_plane = 0;
  for (size_t k = 1; k < planes.size(); ++k)
    if (planes[k].first.d > planes[lowest_plane].first.d) lowest_plane = k;
  auto one_support = [&](const PlaneFit& plane, const std::vector<PlaneRegions>& regions) {
    Found fd;
    fd.plane = plane;
    for (const PlaneRegions& r : regions) {
      fd.regions.members.insert(fd.regions.members.end(), r.members.begin(), r.members.end());
      fd.regions.hull_points.insert(fd.regions.hull_points.end(), r.hull_points.begin(),
                                    r.hull_points.end());
      fd.regions.touches_bottom = fd.regions.touches_bottom || r.touches_bottom;
    }
    fd.points = static_cast<int>(fd.regions.members.size()) * stride * stride;
    found.push_back(std::move(fd));
  };
  // Whether plane k's regions, joined, hide what lies below them: fewer than
  // grazing_max_through_share of the rays crossing their hull see past it, and no more
  // than a support's smallest region of them end on another support.
  auto hides_below = [&](size_t k) {
    std::vector<char> on_support(f.points.size(), 0);
    for (size_t o = 0; o < planes.size(); ++o)
      if (o != k)
        for (const PlaneRegions& r : planes[o].second)
          for (int i : r.members) on_support[static_cast<size_t>(i)] = 1;
    const RaysThrough rays = rays_through(f, planes[k].second, planes[k].first, on_support, params);
    return static_cast<double>(rays.through) <
               params.grazing_max_through_share * static_cast<double>(rays.on + rays.through) &&
           static_cast<long long>(rays.through_support) * stride * stride <
               params.min_plane_points / 4;
  };
  // Which plane's kept regions each strided pixel lies in (-1: none).
  std::vector<int> plane_of(f.points.size(), -1);
  for (size_t k = 0; k < planes.size(); ++k)
    for (const PlaneRegions& r : planes[k].second)
      for (int i : r.members) plane_of[static_cast<size_t>(i)] = static_cast<int>(k);
  for (size_t k = 0; k < planes.size(); ++k) {
    auto& [plane, regions] = planes[k];
    if (k == lowest_plane) {
      one_support(plane, regions);
      continue;
    }
    // Each region's part seen from above, kept as a support where it holds one and
    // spans min_support_area_m2.
    std::vector<PlaneRegions> above;
    std::vector<char> holds;
    size_t members = 0, seen = 0;
    for (const PlaneRegions& region : regions) {
      above.push_back(seen_from_above(f, region, plane, params));
      const PlaneRegions& a = above.back();
      holds.push_back(seen_part_is_support(f, a, plane, params));
      members += region.members.size();
      seen += a.members.size();
    }
    // A support seen at grazing incidence, its edges in more of its pixels than its
    // surface, is one support of all its regions, as the floor (grazing_support_deg):
    // where a patch of it returned, the rest is there too, if it hides what lies below.
    const bool some_support = std::find(holds.begin(), holds.end(), 1) != holds.end();
    if (some_support &&
        static_cast<double>(seen) < params.grazing_max_seen_share * static_cast<double>(members) &&
        seen_at_grazing(f, regions, plane, params) && hides_below(k)) {
      one_support(plane, regions);
      continue;
    }
    // Regions that each hold a support and, joined, hide what lies below them are one
    // surface parted by what stands on it (a table seen from just above its height, its
    // middle hidden by a ball and a bowl); two tops at one height with the floor seen
    // between them are two.
    if (params.join_parted_surfaces && std::count(holds.begin(), holds.end(), 1) >= 2 &&
        hides_below(k)) {
      std::vector<PlaneRegions> parts;
      for (size_t r = 0; r < above.size(); ++r)
        if (holds[r]) parts.push_back(std::move(above[r]));
      one_support(plane, parts);
      continue;
    }
    for (size_t r = 0; r < above.size(); ++r) {
      if (!holds[r]) continue;
      Found fd;
      fd.regions = std::move(above[r]);
      fd.plane = plane;
      if (const std::optional<PlaneFit> own = region_plane(f, fd.regions.members, plane, params)) {
        fd.plane = *own;
        fd.regions.members =
            members_on(f, fd.regions, fd.plane, params, strided.index, plane_of, k);
      }
      fd.points = static_cast<int>(fd.regions.members.size()) * stride * stride;
      found.push_back(std::move(fd));
    }
  }
  return found;
}

void order_and_name_objects(ScanResult& result) {
  // Mean x/z and y/z are the image column and row up to the intrinsics.
  const size_t n = result.clusters.size();
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::vector<double> col(n, 0), row(n, 0);
  for (size_t k = 0; k < n; ++k) {
    const auto& pts = result.clusters[k].points;
    for (const Vec3& p : pts) {
      col[k] += p.x / p.z;
      row[k] += p.y / p.z;
    }
    if (!pts.empty()) {
      col[k] /= static_cast<double>(pts.size());
      row[k] /= static_cast<double>(pts.size());
    }
  }
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return col[a] != col[b] ? col[a] < col[b] : row[a] < row[b];
  });
  std::vector<ScanCluster> clusters;
  std::vector<PhysicalObject> objects;
  for (size_t k : order) {
    clusters.push_back(std::move(result.clusters[k]));
    objects.push_back(std::move(result.scene.objects[k]));
  }
  for (size_t k = 0; k < objects.size(); ++k) objects[k].id = std::to_string(k + 1).insert(0, 1, 'p');
  // An object standing on another one names it by its new index and id.
  std::vector<int> new_index(n, -1);
  for (size_t k = 0; k < n; ++k) new_index[order[k]] = static_cast<int>(k);
  for (size_t k = 0; k < n; ++k) {
    int& below = clusters[k].on_object;
    below = below >= 0 && below < static_cast<int>(n) ? new_index[static_cast<size_t>(below)] : -1;
    objects[k].on_object = below >= 0 ? objects[static_cast<size_t>(below)].id : std::string();
  }
  result.clusters = std::move(clusters);
  result.scene.objects = std::move(objects);
}

namespace {

// The pixel-unit parameters for a camera that sees k times the pixels along a line that
// pixel_units_focal_px gives (ScanParams::pixel_units_focal_px).
void scale_pixel_units(ScanParams& p, double k) {
  const auto area = [k](int& n) { n = std::max(1, static_cast<int>(std::lround(n * k * k))); };
  const auto line = [k](int& n) { n = std::max(1, static_cast<int>(std::lround(n * k))); };
  for (int* n : {&p.min_plane_points, &p.min_cluster_points, &p.min_cluster_points_far,
                 &p.max_cluster_points, &p.min_whole_points, &p.segment.min_object_points,
                 &p.shape.min_foot_seen_pixels})
    area(*n);
  for (int* n : {&p.pixel_stride, &p.cluster_window_px, &p.mls_window_px}) line(*n);
}

// One Kinect's focal length differs from another's by its calibration, up to this factor
// either way from the nominal 525 px (TUM's 517 to 535, NYU's 583, OSD's 525): the
// pixel-unit parameters hold as given over that range (ScanParams::pixel_units_focal_px).
constexpr double kFocalCalibrationSpread = 1.15;

// The parameters with the frame's camera: the recognizer counts pixels with its focal
// length (ShapeRecognizerParams::focal_px), the recognizer and the segmenter take the
// scan's depth noise, the pixel-unit parameters follow the focal length from the
// nearer end of the calibrations' range, and the segmenter's level cut keeps a part as
// small as a cluster standing alone.
ScanParams with_camera_of(const Frame& f, const ScanParams& given) {
  ScanParams p = given;
  p.shape.focal_px = focal_px(f);
  p.shape.depth_noise = p.segment.depth_noise = p.depth_noise;
  const double k = p.shape.focal_px / p.pixel_units_focal_px;
  if (p.pixel_units_focal_px > 0 && std::isfinite(k) && k > 0) {
    if (k > kFocalCalibrationSpread) scale_pixel_units(p, k / kFocalCalibrationSpread);
    if (k < 1 / kFocalCalibrationSpread) scale_pixel_units(p, k * kFocalCalibrationSpread);
  }
  p.segment.level_min_part_points = p.min_cluster_points;
  return p;
}

// A hull grows by a disc around each corner, of kGrowDirections points.
constexpr int kGrowDirections = 16;

Hull2 grown_hull(const Hull2& h, Vec3 n, double by) {
  static const auto directions = [] {
    std::array<std::pair<double, double>, kGrowDirections> d;
    for (int j = 0; j < kGrowDirections; ++j) {
      const double t = 2 * 3.14159265358979 * j / kGrowDirections;
      d[static_cast<size_t>(j)] = {std::cos(t), std::sin(t)};
    }
    return d;
  }();
  std::vector<Vec3> grown;
  grown.reserve(h.pts.size() * kGrowDirections);
  for (const auto& q : h.pts)
    for (const auto& [c, s] : directions)
      grown.push_back(h.u * (q[0] + by * c) + h.v * (q[1] + by * s));
  return convex_hull(grown, n);
}

// Support k's hulls (its kept regions, plus the camera's foot on the plane when the
// support runs out of the image's bottom or is the lowest, grown by the margins) set in
// `fd`, and its record.
ScanSupport support_of(const Frame& f, Found& fd, size_t k, bool lowest, const ScanParams& params) {
  std::vector<Vec3> hull_points = fd.regions.hull_points;
  if (params.hull_to_camera && (fd.regions.touches_bottom || lowest))
    hull_points.push_back(fd.plane.n * -fd.plane.d);
  fd.hull = convex_hull(hull_points, fd.plane.n);
  // The floor runs on under what stands on it beyond its visible patches (a storage
  // box in front of a floor seen between furniture): its hull grows by
  // floor_margin_m; every support by hull_margin_m.
  const double margin = std::max(params.hull_margin_m, lowest ? params.floor_margin_m : 0.0);
  if (margin > 0 && fd.hull.pts.size() >= 3) fd.hull = grown_hull(fd.hull, fd.plane.n, margin);
  if (params.overhang_margin_m > 0 && fd.hull.pts.size() >= 3)
    fd.reach = grown_hull(fd.hull, fd.plane.n, params.overhang_margin_m);
  ScanSupport sup;
  sup.surface.id = "s" + std::to_string(k + 1);
  sup.surface.plane = {fd.plane.n, fd.plane.d};
  sup.surface.point_count = fd.points;
  sup.area_m2 = hull_area(fd.hull);
  sup.furniture = sup.area_m2 > params.furniture_area_m2;
  if (params.seen_part_reach_m > 0 && !lowest && !sup.furniture && fd.hull.pts.size() >= 3)
    fd.around = grown_hull(fd.hull, fd.plane.n, params.seen_part_reach_m);
  // The smallest squared distance, then its root: the root is monotonic.
  double nearest2 = 1e18;
  for (int i : fd.regions.members) {
    const Vec3 p = to_vec(f.points[i]);
    nearest2 = std::min(nearest2, dot(p, p));
  }
  sup.distance_m = fd.regions.members.empty() ? 1e9 : std::sqrt(nearest2);
  for (const auto& q : fd.hull.pts) {
    Vec3 p = fd.hull.u * q[0] + fd.hull.v * q[1];
    p = p - fd.plane.n * (dot(fd.plane.n, p) + fd.plane.d);
    sup.hull.push_back(p);
  }
  return sup;
}

}  // namespace

Result<ScanResult> scan_frame(const Frame& input, const ScanParams& params) {
  ScanWorkers workers;  // started for this scan only
  return scan_frame(input, params, workers);
}

Result<ScanResult> scan_frame(const Frame& input, const ScanParams& given, ScanWorkers& workers) {
  // Parameters set in code are checked like a config file's (params_validation.h).
  if (Status s = validate_scan_params(given); !s) return s.error();
  if (input.width <= 0 || input.height <= 0 ||
      input.points.size() != static_cast<size_t>(input.width) * input.height)
    return Error{"frame size " + std::to_string(input.width) + "x" + std::to_string(input.height) +
                     " does not match its " + std::to_string(input.points.size()) + " points",
                 {"frame " + std::to_string(input.index), 0, 0}};
  const Frame reorganized = input.organized() ? Frame{} : organize(input);
  const Frame& f = input.organized() ? input : reorganized;
  const std::string frame_name = "frame " + std::to_string(input.index);
  if (Status s = validate_intrinsics(grid_intrinsics(f), frame_name + " intrinsics"); !s)
    return s.error();
  const ScanParams params = with_camera_of(f, given);
  const Location where{frame_name, 0, 0};
  ScanResult result;
  std::mt19937_64 rng(params.shape.seed);
  const Vec3 up = effective_up(params);
  // The worker threads, started once for the whole scan or kept from the caller's last
  // one (scan_pool.h, scan_workers.h).
  ScanPool& pool = workers.pool(params.threads);
  struct UsePool {
    ScanPool* before;
    explicit UsePool(ScanPool* p) : before(scan_pool) { scan_pool = p; }
    ~UsePool() { scan_pool = before; }
  } use_pool(&pool);

  auto t0 = Clock::now();
  const int stride = std::max(1, params.pixel_stride);
  StridedPixels strided_px = strided_pixels(f, params, stride);
  const std::vector<int>& strided = strided_px.index;
  // Valid strided pixels per grid row and column (the image border below).
  const int gw = (f.width + stride - 1) / stride, gh = (f.height + stride - 1) / stride;
  const std::vector<int> valid_rows = std::move(strided_px.rows), valid_cols = std::move(strided_px.cols);
  if (strided.size() < 50) {
    // Valid points that all lie beyond the range are most often a cloud in millimetres.
    std::vector<float> far;
    for (size_t i = 0; i < f.points.size(); i += 97)
      if (has_depth(f.points[i])) far.push_back(f.points[i].z);
    if (far.size() < 10) return Error{"the frame has no valid depth points", where};
    std::nth_element(far.begin(), far.begin() + far.size() / 2, far.end());
    const double median = far[far.size() / 2];
    char text[160];
    std::snprintf(text, sizeof text, "no depth within max_depth_m (%g m): the median depth is %g%s",
                  params.max_depth_m, median,
                  median > 50 ? "; Annex expects metres (is this cloud in millimetres?)" : "");
    return Error{text, where};
  }
  std::vector<Found> found = find_supports(f, params, strided_px, up, rng);
  const double cos_tilt = cos_degrees(params.max_support_tilt_deg);
  if (found.empty())
    return Error{"no horizontal plane found (support must be within " +
                     std::to_string(static_cast<int>(params.max_plane_angle_deg)) +
                     " degrees of the up vector; see max_plane_angle_deg, up, camera_tilt_deg)",
                 where};
  std::stable_sort(found.begin(), found.end(),
                   [](const Found& a, const Found& b) { return a.points > b.points; });
  result.stages.push_back({"plane", ms_since(t0)});

  t0 = Clock::now();
  // Hulls (support_of): a support running out of the image's bottom continues towards
  // the camera, hidden by the objects on it or out of view, and the lowest support (the
  // floor when it shows) always runs under the camera: the camera is above it, so
  // objects in front of its visible part stand on it too.
  size_t lowest = 0;
  for (size_t k = 1; k < found.size(); ++k)
    if (found[k].plane.d > found[lowest].plane.d) lowest = k;
  // Each support's hulls and record on the scan's threads (each reads only its own
  // support), the largest outlines first: the floor's is most of the work.
  result.supports.resize(found.size());
  std::vector<size_t> outline_sizes(found.size());
  for (size_t k = 0; k < found.size(); ++k) outline_sizes[k] = found[k].regions.hull_points.size();
  const std::vector<size_t> outline_order = largest_first(outline_sizes);
  parallel_for(
      found.size(),
      [&](size_t k) { result.supports[k] = support_of(f, found[k], k, k == lowest, params); },
      &outline_order);
  // Which supports' objects are reported.
  {
    std::vector<size_t> reach;
    for (size_t k = 0; k < result.supports.size(); ++k)
      if (result.supports[k].distance_m <= params.support_reach_m) reach.push_back(k);
    auto pick = [&](auto better) {
      size_t best = reach.front();
      for (size_t k : reach)
        if (better(result.supports[k], result.supports[best])) best = k;
      result.supports[best].selected = true;
    };
    if (params.supports == SupportSelection::id) {
      bool any = false;
      for (ScanSupport& sp : result.supports)
        if (sp.surface.id == params.support_id) sp.selected = any = true;
      if (!any) {
        std::string ids;
        for (const ScanSupport& sp : result.supports) ids += (ids.empty() ? "" : ", ") + sp.surface.id;
        return Error{"no support '" + params.support_id + "' in this frame (found: " + ids + ")",
                     where};
      }
    } else if (reach.empty()) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "no support within support_reach_m (%g m): the nearest is %.2f m away",
                    params.support_reach_m, result.supports.front().distance_m);
      return Error{text, where};
    } else if (params.supports == SupportSelection::nearest) {
      pick([](const ScanSupport& a, const ScanSupport& b) { return a.distance_m < b.distance_m; });
    } else if (params.supports == SupportSelection::highest) {
      // Highest along up: the camera's height above it is smallest.
      pick([](const ScanSupport& a, const ScanSupport& b) { return a.surface.plane.d < b.surface.plane.d; });
    } else if (params.supports == SupportSelection::largest) {
      pick([](const ScanSupport& a, const ScanSupport& b) {
        return a.surface.point_count > b.surface.point_count;
      });
    } else {
      for (size_t k : reach) result.supports[k].selected = true;
    }
  }
  for (const ScanSupport& sp : result.supports)
    if (sp.selected) result.scene.supports.push_back(sp.surface);
  for (size_t k = 0; k < result.supports.size(); ++k)
    if (result.supports[k].selected) {
      result.plane = result.supports[k].surface.plane;
      result.hull = result.supports[k].hull;
      result.plane_inliers = result.supports[k].surface.point_count;
      break;
    }
  result.scene.support = result.plane;

  // The prism test runs on the strided grid: a pixel is a candidate of the nearest
  // support below it whose hull it stands in, within the height band. Pixels on a
  // furniture support's surface are never candidates. Clusters grow there and are
  // then expanded to full resolution.
  const size_t ns = found.size();
  std::vector<char> mask(f.points.size(), 0);
  std::vector<char> beyond(f.points.size(), 0);  // candidates beyond the hull (overhang)
  std::vector<int> seeds;
  // Pixels are independent: the pass runs in chunks of kPrismChunk strided pixels
  // handed out one at a time (a helper woken late from the plane stage's serial stretch
  // takes fewer: with one band per thread the caller waited for its band), each chunk's
  // seeds kept apart and joined in chunk order (raster order, as one pass gives them).
  // What stands across a support's far edge hangs behind itself, hidden from the camera:
  // a pixel beyond the hull whose point overhang_margin_m nearer the camera's foot (along
  // the plane) is inside the hull lies past the far edge (office1's cupboard behind its
  // desk), not across a near or side one.
  const auto beyond_far_edge = [&](const Found& fd, Vec3 p) {
    const Vec3 d = p - fd.plane.n * -fd.plane.d;
    const Vec3 along = d - fd.plane.n * dot(fd.plane.n, d);
    const double len = norm(along);
    return len > 0 && fd.hull.contains(p - along * (params.overhang_margin_m / len));
  };
  const std::vector<double> band_scale = surface_noise_scale(f, found, params);
  constexpr size_t kPrismChunk = 4096;
  const size_t prism_bands = (strided.size() + kPrismChunk - 1) / kPrismChunk;
  std::vector<std::vector<int>> band_seeds(prism_bands), around_seeds(prism_bands);
  // Which support's surface each strided pixel is (-1: none), for the clusters' tests
  // below: the pass's first item, beside its chunks.
  std::vector<int> surface_of;
  parallel_for(prism_bands + 1, [&](size_t item) {
    if (item == 0) {
      surface_of.assign(f.points.size(), -1);
      for (size_t k = 0; k < ns; ++k)
        for (int i : found[k].regions.members)
          surface_of[static_cast<size_t>(i)] = static_cast<int>(k);
      return;
    }
    const size_t b = item - 1;
    const size_t lo = b * kPrismChunk, hi = std::min(strided.size(), lo + kPrismChunk);
    std::vector<int>& out = band_seeds[b];
    for (size_t s = lo; s < hi; ++s) {
      const int i = strided[s];
      const Vec3 p = to_vec(f.points[i]);
      int owner = -1, reached = -1, around = -1;
      double owner_h = 1e9, reached_h = 1e9, around_h = 1e9;
      bool surface = false;
      // The pixel's terms of plane_band and surface_band, once for every support.
      const double wide = plane_band(params, p.z);
      const double noise = band_noise(params, p);
      for (size_t k = 0; k < ns; ++k) {
        const Found& fd = found[k];
        const double h = dot(fd.plane.n, p) + fd.plane.d;
        if (h > params.max_height_m || h <= -wide) continue;
        // surface_band, no wider than plane_band: asked only within that. Below the plane
        // the band stays plane_band: nothing but noise lies there.
        const double band =
            h >= wide ? wide : surface_band(params, p, fd.plane.n, band_scale[k], wide, noise);
        // On the surface itself only a furniture support's hull matters (most strided
        // pixels lie there: the hull test is skipped for the others).
        if (h < std::max(params.min_height_m, band)) {
          surface = surface || (result.supports[k].furniture && fd.hull.contains(p));
          continue;
        }
        if (!fd.hull.contains(p)) {
          if (h < reached_h && fd.reach.contains(p) && !beyond_far_edge(fd, p))
            reached_h = h, reached = static_cast<int>(k);
          else if (h < around_h && fd.around.contains(p))
            around_h = h, around = static_cast<int>(k);
          continue;
        }
        if (h < owner_h) owner_h = h, owner = static_cast<int>(k);
      }
      if (surface) continue;
      // Beyond the hull's edge but within overhang_margin_m of it: a part of what stands
      // across the edge, joined only by a cluster grown from inside (never a seed).
      if (owner < 0) {
        if (reached >= 0) {
          mask[i] = static_cast<char>(reached + 1), beyond[i] = 1;
        } else if (around >= 0) {
          // Around a small support's seen part: marked apart, so it joins no other cluster.
          mask[i] = static_cast<char>(ns + 1 + static_cast<size_t>(around));
          around_seeds[b].push_back(i);
        }
        continue;
      }
      mask[i] = static_cast<char>(owner + 1);
      out.push_back(i);
    }
  });
  for (size_t b = 0; b < prism_bands; ++b) seeds.insert(seeds.end(), band_seeds[b].begin(), band_seeds[b].end());
  for (size_t b = 0; b < prism_bands; ++b)
    seeds.insert(seeds.end(), around_seeds[b].begin(), around_seeds[b].end());
  result.stages.push_back({"prism", ms_since(t0)});

  t0 = Clock::now();
  struct Candidate {
    std::vector<int> pixels;
    int support = 0;
  };
  std::vector<Candidate> clusters;
  // The pixels of clusters whose extent no one sees (a nearer support or object hides
  // their top, or they are one upright face).
  std::vector<char> hidden;  // sized with the label beside the grids' tests (below)
  std::vector<int> label;
  // Index of a support above cluster `grid`'s own (k) whose surface, nearer to the
  // camera, lies just above the cluster's top in most of its image columns, or -1.
  // A support seen from above always appears above in the image what stands under it
  // and behind its front edge; a few grid rows of look-up span the support's edge.
  // At most this many grid rows up (a 6 cm edge 35 cm from the camera, the Kinect's
  // nearest range, spans 45 image rows).
  constexpr int kEdgeRows = 24;
  auto hidden_under = [&](const std::vector<int>& grid, int k) {
    const PlaneFit& own = found[static_cast<size_t>(k)].plane;
    const std::vector<std::pair<int, int>> top = end_per_column(f, grid, true);
    std::map<int, int> votes;
    for (const auto& [col, i] : top) {
      const double z = f.points[i].z;
      // How much farther a pixel above may lie and still be as near as the top
      // (top_look_noise_sigmas).
      const double near_tol =
          std::max(cluster_tolerance(params, z),
                   params.top_look_noise_sigmas * two_returns_sigma(params.depth_noise, z));
      // The first pixel of the support's front edge above the cluster, once seen: the
      // look-up spans six grid rows, or the edge's thickness (support_edge_m) where it
      // covers more rows (a table's edge 60 cm from the camera spans ten).
      std::optional<Vec3> edge;
      for (int r = 1; r <= kEdgeRows; ++r) {
        const int j = i - r * stride * f.width;
        if (j < 0) break;
        if (!has_depth(f.points[j])) continue;
        if (r > 6 && (!edge || norm(to_vec(f.points[j]) - *edge) > params.support_edge_m)) break;
        int o = surface_of[static_cast<size_t>(j)];
        if (o < 0) {
          // Not in a support's region, yet on a higher support's plane (a table top
          // seen at a grazing angle keeps only part of itself as its region).
          const Vec3 q = to_vec(f.points[j]);
          for (size_t s = 0; s < ns && o < 0; ++s)
            if (static_cast<int>(s) != k && found[s].plane.d < own.d &&
                std::abs(dot(found[s].plane.n, q) + found[s].plane.d) < plane_band(params, q.z))
              o = static_cast<int>(s);
        }
        if (o < 0 || o == k) {
          // The support's front edge (its thickness) is no support pixel: look on
          // past pixels as near as the support would be, stop at anything behind.
          if (f.points[j].z > z + near_tol) break;
          if (!edge) edge = to_vec(f.points[j]);
          continue;
        }
        const PlaneFit& sup = found[static_cast<size_t>(o)].plane;
        if (sup.d < own.d && f.points[j].z < z + near_tol) ++votes[o];
        break;
      }
    }
    for (const auto& [o, n] : votes)
      if (2 * n > static_cast<int>(top.size())) return o;
    return -1;
  };
  // The size floor falls with the square of depth, as a surface's pixel count does.
  auto least_points = [&](const std::vector<int>& grid) {
    double z = 0;
    for (int i : grid) z += f.points[i].z;
    z /= static_cast<double>(grid.size());
    return std::max(params.min_cluster_points_far,
                    static_cast<int>(params.min_cluster_points / std::max(1.0, z * z)));
  };
  // The clustering tolerance at a depth, for the rules that compare depths.
  const auto tolerance = [&](double z) { return cluster_tolerance(params, z); };
  // An object across its support's edge is a prop, which ends below the band's top: a
  // cluster with pixels beyond the hull that reaches within the clustering tolerance of
  // the band's top ran on into what stands beside the support (a wall, a wardrobe's
  // front beside nyu_basement's upper bin, office1's cupboard behind its desk), and
  // keeps its pixels inside the hull.
  std::vector<std::vector<int>> grown_grids = grow_clusters(f, mask, seeds, stride, params);
  keep_standing_around(f, found, grown_grids, mask, stride, params);
  const auto is_beyond = [&](int i) { return beyond[static_cast<size_t>(i)] != 0; };
  for (std::vector<int>& grid : grown_grids) {
    if (std::none_of(grid.begin(), grid.end(), is_beyond)) continue;
    const PlaneFit& plane = found[static_cast<size_t>(mask[grid.front()] - 1)].plane;
    const bool tall = std::any_of(grid.begin(), grid.end(), [&](int i) {
      return at_band_top(params, plane, to_vec(f.points[static_cast<size_t>(i)]));
    });
    if (tall) grid.erase(std::remove_if(grid.begin(), grid.end(), is_beyond), grid.end());
  }
  // A dark object's fragments, parted by its missing depth, joined (dropout_join.h).
  const std::vector<std::vector<int>> grids = join_dropout_fragments(
      f, mask, std::move(grown_grids), stride, tolerance, least_points,
      DropoutJoinParams{params.dropout_max_gap_px, params.dropout_join_to_floor});
  // Each grid's support, lowest point and extent across the view: what the rule for a
  // body under an unseen top (below) asks of the clusters standing on it, and where
  // each stands (support_from_foot).
  struct Footing {
    int support = 0;
    bool object_sized = false;
    double low_h = 0, x_mid = 0;
    double low_ahead = 0;  // its lowest point's distance ahead of the camera along the plane
    Vec3 low;              // its lowest point
  };
  // Each grid's own item on the scan's threads (the grids are independent).
  std::vector<Footing> footing(grids.size());
  if (params.on_top_noise_factor > 0 || params.support_from_foot)
    parallel_for(grids.size(), [&](size_t g) {
      const std::vector<int>& grid = grids[g];
      Footing& ft = footing[g];
      ft.support = mask[grid.front()] - 1;
      ft.object_sized = static_cast<int>(grid.size()) * stride * stride >= least_points(grid) / 2;
      const PlaneFit& pl = found[static_cast<size_t>(ft.support)].plane;
      const Vec3 view_x = normalized(Vec3{1, 0, 0} - pl.n * pl.n.x);
      const Vec3 ahead = normalized(Vec3{0, 0, 1} - pl.n * pl.n.z);
      double lo = 1e9, hi = -1e9;
      ft.low_h = 1e9;
      for (int i : grid) {
        const Vec3 p = to_vec(f.points[i]);
        const double h = dot(pl.n, p) + pl.d;
        if (h < ft.low_h) ft.low_h = h, ft.low_ahead = dot(ahead, p), ft.low = p;
        lo = std::min(lo, dot(view_x, p));
        hi = std::max(hi, dot(view_x, p));
      }
      ft.x_mid = 0.5 * (lo + hi);
    });
  // A cluster stands on the support its foot is on (support_from_foot). A pixel's owner
  // is the nearest support below it whose hull it stands in, but a board's seen part
  // ends where what stands on it hides the rest, and a table's hull ends at its edge,
  // past which an object across it hangs over the floor (rooms 9569: a ball over the
  // table's edge given to the floor 46 cm below). When the cluster's lowest point lies
  // on a higher support's plane (within its band and the clustering tolerance), within
  // that support's reach and not past its far edge, the cluster is that support's.
  // It runs after the footings: the rule for a body under an unseen top asks what stands
  // at its top's height on the body's own support, and the fragments of a cabinet's top
  // lie on a higher plane too (fresh room 8019's cabinet, reported whole when they moved).
  // The support higher than the grid's own on whose plane its lowest point lies, within
  // that support's reach and not past its far edge; -1 none.
  const auto foot_support = [&](const Footing& ft) {
    const PlaneFit& own = found[static_cast<size_t>(ft.support)].plane;
    // An object's lowest pixels lie in its support's band, which is no cluster's.
    const double band = plane_band(params, ft.low.z);
    const double on = foot_reach(params, ft.low.z);
    int foot = -1;
    double best = 1e9;
    for (size_t o = 0; o < ns; ++o) {
      const Found& fd = found[o];
      if (static_cast<int>(o) == ft.support || fd.plane.d >= own.d - on ||
          dot(fd.plane.n, own.n) < cos_tilt)
        continue;
      const double h = dot(fd.plane.n, ft.low) + fd.plane.d;
      if (h < -band || h > on || std::abs(h) >= best) continue;
      if (!fd.hull.contains(ft.low) && (!fd.reach.contains(ft.low) || beyond_far_edge(fd, ft.low)))
        continue;
      foot = static_cast<int>(o);
      best = std::abs(h);
    }
    return foot;
  };
  if (params.support_from_foot)
    for (size_t g = 0; g < grids.size(); ++g) {
      const int foot = foot_support(footing[g]);
      if (foot >= 0)
        for (int i : grids[g]) mask[static_cast<size_t>(i)] = static_cast<char>(foot + 1);
    }
  // Which supports hold something: a cluster big enough to be an object stands on them
  // (selected or not: the choice of supports does not change what furniture is).
  std::vector<char> holds(ns, 0);
  for (const std::vector<int>& grid : grids)
    if (static_cast<int>(grid.size()) * stride * stride >= least_points(grid) / 2)
      holds[static_cast<size_t>(mask[grid.front()] - 1)] = 1;
  // The clusters kept as objects' candidates, split below.
  struct Accepted {
    const std::vector<int>* grid = nullptr;
    int support = 0, min_points = 0;
    // Its top hidden under a nearer support or object, or it is one upright face: no
    // one sees where it ends (partial).
    bool unseen = false;
  };
  // Each grid's tests and then its split (below) run as one item on a worker thread:
  // the tests read only the frame, the supports and the grids, so the grids are
  // independent; each keeps what it accepts and its parts apart, joined in grid order
  // as one thread would give them. Largest grids first: both tests and split cost
  // about their pixels. The loop of one grid keeps the tests' `continue`s.
  // Per support, the hulls of every support on its plane (its regions) for the far-edge
  // rule; empty where the rule is not asked: on the floor, which runs on unseen, and on a
  // support smaller than furniture, a fragment whose edges are not its surface's.
  std::vector<std::vector<const Hull2*>> surface_hulls(ns);
  for (size_t k = 0; k < ns && params.edge_room_factor > 0; ++k) {
    if (k == lowest || !result.supports[k].furniture) continue;
    for (const Found& o : found)
      if (std::abs(o.plane.d - found[k].plane.d) < params.plane_distance_m &&
          dot(o.plane.n, found[k].plane.n) >= cos_tilt)
        surface_hulls[k].push_back(&o.hull);
  }
  // Each object-sized grid measured once on its support's plane: its width across the
  // view (along the camera's x axis laid on the plane: a box seen face-on shows no depth,
  // but its full width), its top and lowest point above the support.
  struct Extent {
    bool object_sized = false;
    int min_points = 0;
    double x_lo = 1e9, x_hi = -1e9, top_h = -1e9, bottom_h = 1e9, top_z = 0;
    Vec3 low{0, 0, 0};  // its lowest point
  };
  std::vector<Extent> extents(grids.size());
  // Furniture cut by the height band: it reaches down to its support (its lower half is
  // seen) and its top is the band's top, its front running on above it, across most of
  // its width (top_cut_by_band). Found for every grid first: what runs on above it, which
  // a raised support's reach takes, is known by its foot running on into these pixels.
  std::vector<char> band_cut(grids.size(), 0);
  parallel_for(grids.size(), [&](size_t g) {
    const std::vector<int>& grid = grids[g];
    Extent& e = extents[g];
    e.min_points = least_points(grid);
    e.object_sized = static_cast<int>(grid.size()) * stride * stride >= e.min_points / 2;
    if (!e.object_sized) return;
    const PlaneFit& plane = found[static_cast<size_t>(mask[grid.front()] - 1)].plane;
    const Vec3 view_x = normalized(Vec3{1, 0, 0} - plane.n * plane.n.x);
    for (int i : grid) {
      const Vec3 p = to_vec(f.points[i]);
      e.x_lo = std::min(e.x_lo, dot(view_x, p));
      e.x_hi = std::max(e.x_hi, dot(view_x, p));
      const double h = dot(plane.n, p) + plane.d;
      if (h > e.top_h) e.top_h = h, e.top_z = p.z;
      if (h < e.bottom_h) e.bottom_h = h, e.low = p;
    }
    band_cut[g] = e.bottom_h < 0.5 * e.top_h &&
                  top_cut_by_band(f, grid, stride, plane.n, plane.d, params, tolerance);
  });
  std::vector<char> in_band_cut;  // their pixels, when there are any and the rule is on
  if (params.drop_above_band_cut && std::ranges::find(band_cut, 1) != band_cut.end()) {
    in_band_cut.assign(f.points.size(), 0);
    for (size_t g = 0; g < grids.size(); ++g)
      if (band_cut[g])
        for (int i : grids[g]) in_band_cut[static_cast<size_t>(i)] = 1;
  }
  std::vector<std::vector<Accepted>> accepted_of(grids.size());
  std::vector<std::vector<std::vector<int>>> parts_of(grids.size());
  std::vector<size_t> grid_sizes(grids.size());
  for (size_t g = 0; g < grids.size(); ++g) grid_sizes[g] = grids[g].size();
  // One more item, last, sizes the per-pixel flags and labels the clusters get below.
  std::vector<size_t> grid_order = largest_first(grid_sizes);
  grid_order.push_back(grids.size());
  parallel_for(grids.size() + 1, [&](size_t g) {
  if (g == grids.size()) {
    hidden.assign(f.points.size(), 0);
    label.assign(f.points.size(), -1);
    return;
  }
  std::vector<Accepted>& accepted = accepted_of[g];
  for (const std::vector<int>& grid : std::span(&grids[g], 1)) {
    const int k = mask[grid.front()] - 1;
    if (!result.supports[static_cast<size_t>(k)].selected) continue;
    const PlaneFit& plane = found[static_cast<size_t>(k)].plane;
    const Extent& extent = extents[g];
    if (!extent.object_sized) continue;
    const int min_points = extent.min_points;
    const double x_lo = extent.x_lo, x_hi = extent.x_hi, width = x_hi - x_lo;
    const double top_h = extent.top_h, bottom_h = extent.bottom_h, top_z = extent.top_z;
    const Vec3 low = extent.low;
    // It spans down to its support: its lower half is seen.
    const bool reaches_support = bottom_h < 0.5 * top_h;
    if (params.drop_cut_clusters && continues_above(f, grid, stride, plane, params)) continue;
    // Furniture cut by the height band (band_cut).
    if (band_cut[g]) continue;
    // Or the part of such furniture above the band, which a raised support's reach
    // took (a chair's back seen from behind, past the floor's band beside its seat).
    if (!in_band_cut.empty() &&
        foot_on_cut_body(
            f, grid, stride, [&](int j) { return in_band_cut[static_cast<size_t>(j)] != 0; },
            tolerance))
      continue;
    // The body of a support above its own (a cabinet or a shelf under its top, a box
    // whose top is the support): where the cluster reaches that support's height, its
    // pixels are mostly that support's surface, and the surface is a visible share of
    // it (a top seen from above). When something stands on that support, the body is
    // furniture, not a prop: a prop is what stands on it. One with nothing on it (a
    // storage box), or lower than furniture (a box with a can on it), stays an object.
    // Lower, a body is a board (a shelf's lowest, on side panels outside the cluster)
    // when its lower half is unseen and the view passes under it: a box with a can on
    // it shows its front down to its own support.
    // Looked at once per cluster, when a lower support first asks (-1: not yet).
    int board = -1;
    const auto is_board = [&] {
      if (board < 0)
        board = params.board_when_seen_under && !reaches_support &&
                seen_past(foot_view(f, grid, stride, tolerance));
      return board == 1;
    };
    bool body = false;
    for (size_t o = 0; o < ns && !body; ++o) {
      if (static_cast<int>(o) == k || !holds[o] || found[o].plane.d >= plane.d) continue;
      if (plane.d - found[o].plane.d < params.furniture_min_height_m && !is_board()) continue;
      size_t on_top = 0, at_height = 0;
      for (int i : grid) {
        const Vec3 p = to_vec(f.points[i]);
        at_height += std::abs(dot(found[o].plane.n, p) + found[o].plane.d) < plane_band(params, p.z);
        on_top += surface_of[static_cast<size_t>(i)] == static_cast<int>(o);
      }
      body = 2 * on_top >= at_height && 20 * on_top >= grid.size();
    }
    if (body) continue;
    // A piece of its own support's surface, which the support's one plane leaves above it.
    const std::optional<Plane> around =
        params.support_slab_check || params.below_support_sigmas > 0
            ? own_support_around(f, grid, stride, surface_of, k, plane.n, params)
            : std::nullopt;
    if (around && lies_on_own_support(f, grid, *around, params,
                                      [&](double z) { return plane_band(params, z); }))
      continue;
    // The same body when its top is no support found (a cabinet seen level, its top at
    // a grazing angle): a cluster on the same support has its lowest point at this one's
    // top height, within the noise, its middle over this one's width across the view and
    // its foot behind this one's front. It is the top's own fragments or what stands on
    // it; either way this cluster is the front of furniture, not a prop.
    bool pieces_on_top = false;
    // Furniture-sized both ways: a bottle or a tall box as high is narrow, and its top's
    // rim comes apart just as a cabinet's top does.
    if (params.on_top_noise_factor > 0 && top_h >= params.furniture_min_height_m &&
        width >= params.furniture_min_width_m && reaches_support) {
      const double tol = params.on_top_noise_factor * cluster_tolerance(params, top_z);
      // A top at the band's top is where the band cuts the body (the cut-top rule).
      const bool top_inside_band = top_h < params.max_height_m - tol;
      // Its front along the plane: what is on its top lies behind the front (at the front
      // is its own rim: a lip, a handle) by at most about its width (a top is about as
      // deep as it is wide); what is farther stands behind the body, its foot hidden at
      // the top's height by a level view.
      const Vec3 ahead = normalized(Vec3{0, 0, 1} - plane.n * plane.n.z);
      double front = 1e9;
      for (int i : grid) front = std::min(front, dot(ahead, to_vec(f.points[i])));
      const size_t self = static_cast<size_t>(&grid - grids.data());
      for (size_t o = 0; o < grids.size() && top_inside_band && !pieces_on_top; ++o) {
        const Footing& ft = footing[o];
        pieces_on_top = o != self && ft.support == k && ft.object_sized && std::abs(ft.low_h - top_h) <= tol &&
                        ft.x_mid > x_lo && ft.x_mid < x_hi && ft.low_ahead > front + tol &&
                        ft.low_ahead < front + width + tol;
      }
    }
    if (pieces_on_top) continue;
    // Under a support above its own, inside its hull, and spanning only a small share
    // of its width across the view: a table's leg, a chair's base under the table,
    // not an object. A cluster as wide as the support is the body of the object whose
    // top the support is (a storage box, a stool) and is kept. Widths are measured
    // along the camera's x axis laid on the plane: a box seen face-on shows no depth,
    // but its full width.
    // Only on the lowest support (the floor): what stands on a raised one under a
    // higher one is that board's content (a shelf's lower board, a desk under its
    // hutch), not what holds the higher one up.
    bool under = false;
    double over_h = 1e9;  // the height of the nearest support it stands under above its own
    for (size_t o = 0; o < ns && (k == static_cast<int>(lowest) || !params.legs_on_lowest_only);
         ++o) {
      if (static_cast<int>(o) == k) continue;
      const PlaneFit& top = found[o].plane;
      if (top.d >= plane.d || dot(top.n, plane.n) < cos_tilt) continue;  // not above it
      const Vec3 across = normalized(Vec3{1, 0, 0} - top.n * top.n.x);
      double lo = 1e9, hi = -1e9;
      size_t below = 0;
      for (int i : grid) {
        const Vec3 p = to_vec(f.points[i]);
        if (dot(top.n, p) + top.d < 0 && found[o].hull.contains(p)) {
          ++below;
          lo = std::min(lo, dot(across, p));
          hi = std::max(hi, dot(across, p));
        }
      }
      if (below * 2 <= grid.size()) continue;
      double slo = 1e9, shi = -1e9;
      for (const Vec3& q : result.supports[o].hull) {
        slo = std::min(slo, dot(across, q));
        shi = std::max(shi, dot(across, q));
      }
      under = under || hi - lo < params.under_width_share * (shi - slo);
      over_h = std::min(over_h, plane.d - top.d);
    }
    // A leg rises to the support's underside; what is seen ending lower is no leg.
    const auto ends_below = [&] {
      return params.leg_top_reach_m > 0 && over_h - top_h > params.leg_top_reach_m &&
             top_seen_ending(f, grid, stride, tolerance);
    };
    if (under && !ends_below()) continue;
    // A thin member standing on its support and rising to furniture height is no
    // free-standing prop: an upright thing narrower than min_stand_ratio of its height
    // tips over past a few degrees (atan 0.15: 8.5). It is a table's or a chair's leg,
    // a pole, a lamp's stand, held by something above it, whether or not that is seen
    // (a table top seen at a grazing angle keeps only part of itself as a support, and
    // a leg's top 3 m away is a few noisy pixels, fewer than continues_above needs).
    // It spans down to the support (its lower half seen): a thin piece seen only high
    // above the support stands on something else there (an object on a cabinet whose
    // top is no support found, cut by the image border).
    if (top_h >= params.furniture_min_height_m && width < params.min_stand_ratio * top_h &&
        reaches_support)
      continue;
    // Its top hidden under a nearer, higher support: a leg whose top meets the table's
    // underside, the wall or a bin seen under the table. Thin ones are legs (dropped);
    // the others are flagged partial, since no one sees where they end.
    const int over = hidden_under(grid, k);
    if (over >= 0 && width < params.under_width_share * top_h) continue;
    // Its top hidden by anything nearer (a shelf's board, a seat, a nearer object): no
    // one sees where it ends either, so it is flagged partial too.
    const bool top_hidden = over >= 0 || (params.partial_when_top_hidden &&
                                          top_occluded(f, grid, stride, tolerance));
    // Its foot hidden at furniture height: no one sees what holds it up (a seat behind
    // its back).
    const bool foot_hidden = foot_hidden_high(f, grid, stride, bottom_h, params, tolerance);
    // Or, standing off its support's plane, its foot hidden by a higher support's top in
    // front: no one sees where it ends either (asked only when no rule above has).
    const auto foot_behind_higher = [&] {
      return params.partial_when_foot_behind_higher && bottom_h > plane_band(params, low.z) &&
             foot_behind_higher_support(
                 f, grid, stride, surface_of,
                 [&](int o) { return found[static_cast<size_t>(o)].plane.d < plane.d; }, tolerance);
    };
    // One upright flat face whose foot is not on its support (a chair's back rising
    // behind the table, a cabinet's side): neither its depth nor its foot is seen.
    // Or one as wide as the raised support it stands on (a chair's back on its seat).
    const std::optional<Vec3> face = upright_panel(f, grid, plane.n, params);
    const bool panel =
        face && (foot_unseen(f, grid, stride, surface_of, k) ||
                 (params.panel_span_share > 0 && static_cast<size_t>(k) != lowest &&
                  spans_support(f, grid, *face, plane.n, found[static_cast<size_t>(k)].hull,
                                params.panel_span_share)));
    // Standing at a raised support's far edge, not on it (`surface_hulls`): asked only
    // when no rule above has flagged it (a look along the view per column).
    const std::vector<const Hull2*>& surface = surface_hulls[static_cast<size_t>(k)];
    const auto at_far_edge = [&] {
      return !surface.empty() && stands_at_far_edge(f, grid, plane, surface, [&](double z) {
        return params.edge_room_factor * tolerance(z);
      });
    };
    // Seen under, hanging higher than anything of its own hidden beneath it could hold it
    // (a shelf's board on side panels outside the cluster, a lamp's head on its arm).
    const bool hanging =
        params.partial_when_seen_under &&
        (hangs_seen_under(f, grid, stride, plane.n, plane.d, low, bottom_h, width, tolerance) ||
         view_under_meets_raised(f, grid, stride, {plane.n, plane.d},
                                 params.seen_under_raised_bands, tolerance,
                                 [&](double z) { return plane_band(params, z); }));
    // Or its face runs on below its support's surface until that surface's edge, nearer,
    // hides it: it stands lower, behind the edge, its foot unseen (asked only when no rule
    // above has flagged it).
    const bool unseen =
        top_hidden || panel || foot_hidden || hanging || at_far_edge() || foot_behind_higher() ||
        (around && runs_below_support(f, grid, stride, *around, surface_of, k, params));
    accepted.push_back({&grid, k, min_points, unseen});
  }
  // Touching objects apart at the creases and depth steps between them (the parts are
  // kept in cluster order). The regions grow with the tolerance the clustering used at
  // the cluster's farthest point (it widens with depth noise), so a far cluster is not
  // cut where it merely is noisy.
  for (const Accepted& a : accepted) {
    const std::vector<int>& grid = *a.grid;
    double z_far = 0;
    for (int i : grid) z_far = std::max(z_far, static_cast<double>(f.points[i].z));
    const PlaneFit& plane = found[static_cast<size_t>(a.support)].plane;
    const Plane support{plane.n, plane.d};
    for (const std::vector<int>& part : split_cluster(
             f, grid, stride, cluster_tolerance(params, z_far), params.segment, &support)) {
      std::vector<int> full = expand_cluster(f, part, stride, plane, band_scale[a.support], params);
      // A part short of the size floor may be a dark surface whose grid pixels lost
      // their depth: the returned pixels in their blocks are its too (dropout_join.h).
      if (static_cast<int>(full.size()) < a.min_points) {
        const std::vector<int> more = dropout_block_pixels(f, part, stride, [&](int j, int i) {
          const PointXYZRGB& c = f.points[static_cast<size_t>(i)];
          const double tol = cluster_tolerance(params, c.z);
          return expands_to(c, f.points[static_cast<size_t>(j)], tol * tol, plane,
                            band_scale[a.support], params);
        });
        if (!more.empty()) {
          const size_t n = full.size();
          full.insert(full.end(), more.begin(), more.end());
          std::inplace_merge(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n), full.end());
        }
      }
      parts_of[g].push_back(std::move(full));
    }
  }
  }, &grid_order);
  for (size_t g = 0; g < grids.size(); ++g)
    for (const Accepted& a : accepted_of[g])
      for (std::vector<int>& full : parts_of[g]) {
        // The size floor is an image area: pixels without depth the part encloses (a
        // dark surface's dropout) are its area too (dropout_join.h).
        const bool small = static_cast<int>(full.size()) < a.min_points &&
                           silhouette_pixels(f, full, params.dropout_max_gap_px) < a.min_points;
        if (small ||
            static_cast<int>(full.size()) > params.max_cluster_points)
          continue;
        if (a.unseen)
          for (int i : full) hidden[static_cast<size_t>(i)] = 1;
        clusters.push_back({std::move(full), a.support});
      }
  for (size_t c = 0; c < clusters.size(); ++c)
    for (int i : clusters[c].pixels) label[i] = static_cast<int>(c);
  result.stages.push_back({"clusters", ms_since(t0)});

  t0 = Clock::now();
  // Clusters are independent: smoothing and shape fits split over worker threads
  // (each fit seeds its own generator, so the result does not depend on the split).
  std::vector<std::vector<Vec3>> normals(clusters.size());
  result.clusters.resize(clusters.size());
  std::vector<size_t> cluster_sizes(clusters.size());
  for (size_t c = 0; c < clusters.size(); ++c) cluster_sizes[c] = clusters[c].pixels.size();
  const std::vector<size_t> mls_order = largest_first(cluster_sizes);
  parallel_for(clusters.size(), [&](size_t c) {
    ScanCluster& sc = result.clusters[c];
    sc.pixels = clusters[c].pixels;
    sc.support = result.supports[static_cast<size_t>(clusters[c].support)].surface.plane;
    sc.around = support_around(f, sc.pixels, label, sc.support, params);
    smooth_cluster(f, sc.pixels, label, static_cast<int>(c), params, sc.points, normals[c]);
  }, &mls_order);
  result.stages.push_back({"mls", ms_since(t0)});

  t0 = Clock::now();
  // The fits' cost grows with the smoothed points (at most the fit budget each).
  std::vector<size_t> fit_sizes(clusters.size());
  for (size_t c = 0; c < clusters.size(); ++c) fit_sizes[c] = result.clusters[c].points.size();
  const std::vector<size_t> fit_order = largest_first(fit_sizes);
  // The image border as the sensor sees it: the rectangle of rows and columns that
  // hold depth (a Kinect leaves a few invalid rows and columns at its edges).
  int left = 0, right = f.width - 1, top = 0, bottom = f.height - 1;
  {
    const std::vector<int>& rows = valid_rows;
    const std::vector<int>& cols = valid_cols;
    auto first = [](const std::vector<int>& v, int need) {
      for (size_t k = 0; k < v.size(); ++k)
        if (v[k] >= need) return static_cast<int>(k);
      return 0;
    };
    auto last = [](const std::vector<int>& v, int need) {
      for (size_t k = v.size(); k-- > 0;)
        if (v[k] >= need) return static_cast<int>(k);
      return static_cast<int>(v.size()) - 1;
    };
    top = first(rows, gw / 5) * stride, bottom = last(rows, gw / 5) * stride + stride - 1;
    left = first(cols, gh / 5) * stride, right = last(cols, gh / 5) * stride + stride - 1;
  }
  const DepthRect depth_rect{left, top, right, bottom};
  const int border = std::max(0, params.border_px);
  // Cut by the image's border (three pixels or more within border_px of it) or hidden
  // in half under something nearer: what is missing of it no one sees. The objects'
  // partial flag (below), and no cut of touching bodies, whose fit is poor for that.
  // Running into the sensor's near blind zone is a cut too: a pixel that near beside
  // one without depth.
  const double near_limit = params.sensor_min_range_m + params.near_cut_margin_m;
  const auto at_blind_zone = [&](int i, int x, int y) {
    if (params.sensor_min_range_m <= 0 || f.points[static_cast<size_t>(i)].z >= near_limit)
      return false;
    return (x > 0 && !has_depth(f.points[static_cast<size_t>(i - 1)])) ||
           (x + 1 < f.width && !has_depth(f.points[static_cast<size_t>(i + 1)])) ||
           (y > 0 && !has_depth(f.points[static_cast<size_t>(i - f.width)])) ||
           (y + 1 < f.height && !has_depth(f.points[static_cast<size_t>(i + f.width)]));
  };
  const auto cut_or_hidden = [&](const std::vector<int>& pixels) {
    int at_border = 0;
    size_t covered = 0;
    for (int i : pixels) {
      const int x = i % f.width, y = i / f.width;
      at_border += x < left + border || y < top + border || x > right - border ||
                   y > bottom - border || at_blind_zone(i, x, y);
      covered += hidden[static_cast<size_t>(i)];
    }
    return at_border >= 3 || 2 * covered > pixels.size();
  };
  // Touching bodies one primitive explains poorly, in two (touching_split.h): each
  // cluster tried right after its fit, in its own item, so that its refits run beside
  // the other clusters' fits; the cuts kept are applied in cluster order below.
  const auto seen_whole = [&](const ScanCluster& sc) { return !cut_or_hidden(sc.pixels); };
  const auto refit_part = [&](ScanCluster& sc, std::vector<Vec3>& n) {
    smooth_part(f, sc.pixels, params, sc.points, n);
    sc.shape = recognize_object_shape(sc.points, n, sc.support, params.shape, sc.around);
  };
  const TouchingSplitParams touching{.max_whole_coverage = params.touching_max_coverage,
                                     .two_feet_coverage = params.touching_two_feet_coverage,
                                     .gap_evidence = params.touching_gap_evidence,
                                     .depth_noise = params.depth_noise,
                                     .min_part_coverage = params.touching_part_coverage,
                                     .min_part_size_m = params.touching_min_part_size_m,
                                     .waist_share = params.touching_waist_share,
                                     .misfit_cut = params.touching_misfit_cut,
                                     .level_cut = params.touching_level_cut,
                                     .width_step_cut = params.touching_width_step,
                                     .segment = params.segment};
  std::vector<std::optional<TouchingCut>> cuts(clusters.size());
  parallel_for(clusters.size(), [&](size_t c) {
    ScanCluster& sc = result.clusters[c];
    sc.shape = recognize_object_shape(sc.points, normals[c], sc.support, params.shape, sc.around);
    cuts[c] = touching_cut(f, sc, refit_part, seen_whole, params.shape, touching);
  }, &fit_order);
  for (size_t c = 0, count = cuts.size(); c < count; ++c) {
    if (!cuts[c]) continue;
    TouchingCut& cut = *cuts[c];
    const int id = static_cast<int>(result.clusters.size());
    for (int i : cut.b.pixels) label[static_cast<size_t>(i)] = id;
    result.clusters[c] = std::move(cut.a);
    normals[c] = std::move(cut.normals_a);
    clusters.push_back({cut.b.pixels, clusters[c].support});
    result.clusters.push_back(std::move(cut.b));
    normals.push_back(std::move(cut.normals_b));
  }
  for (size_t c = 0; c < clusters.size(); ++c) clusters[c].pixels = result.clusters[c].pixels;
  const std::vector<int> rises_from = restack(result, normals, params);
  if (params.stack_on_objects) {
    // On a support that is another object's top (stacking.h): that object, by the id.
    std::vector<std::vector<int>> tops(ns);
    for (size_t k = 0; k < ns; ++k)
      if (!result.supports[k].furniture) tops[k] = found[k].regions.members;
    const std::vector<int> under = objects_under_supports(tops, label);
    for (size_t c = 0; c < result.clusters.size(); ++c) {
      const int o = under[static_cast<size_t>(clusters[c].support)];
      if (o >= 0 && o != static_cast<int>(c) && result.clusters[c].on_object < 0)
        result.clusters[c].on_object = o;
    }
  }
  // Which object stands on which, by one pixel of each: merging parts and joining
  // occluded pieces below renumber the clusters, and a pixel stays with its object.
  std::vector<std::pair<int, int>> stacked;
  for (ScanCluster& sc : result.clusters) {
    if (sc.on_object >= 0)
      stacked.emplace_back(sc.pixels.front(), result.clusters[sc.on_object].pixels.front());
    sc.on_object = -1;
  }
  std::vector<char> apart(f.points.size(), 0);
  std::vector<GrownObject> grown = merge_parts(
      params, result, label, [&](const ScanCluster& sc) { return cut_or_hidden(sc.pixels); },
      [&](const ScanCluster& sc, size_t owner) {
        // What stands on another object's top is held up by it.
        const bool stands = std::any_of(stacked.begin(), stacked.end(), [&](const auto& s) {
          return s.first == sc.pixels.front();
        });
        return !stands && hangs_from(f, sc, static_cast<int>(owner), label, params, stride);
      },
      rises_from, apart);
  // The grown objects fitted again (each on its own pixels: refit_part) beside what
  // joining occluded pieces reads (the label rebuilt, each object's piece): one pass of
  // independent items, the refits first (the longest).
  size_t kept = result.clusters.size();
  std::vector<OccludedPiece> pieces(params.join_occluded ? kept : 0);
  parallel_for(grown.size() + (params.join_occluded ? 1 + kept : 0), [&](size_t k) {
    if (k < grown.size()) {
      std::vector<Vec3> n;
      refit_part(result.clusters[grown[k].index], n);
    } else if (k == grown.size()) {
      std::fill(label.begin(), label.end(), -1);
      for (size_t c = 0; c < kept; ++c)
        for (int i : result.clusters[c].pixels) label[i] = static_cast<int>(c);
    } else {
      const size_t c = k - grown.size() - 1;
      pieces[c] = describe_piece(f, result.clusters[c]);
    }
  });
  // Parts that spoil their owner's fit given back (restore_spoiled), their pieces anew.
  const std::vector<size_t> restored =
      restore_spoiled(grown, result.clusters, label, params.part_fit_slack);
  kept = result.clusters.size();
  if (params.join_occluded) {
    pieces.resize(kept);
    for (size_t c : restored) pieces[c] = describe_piece(f, result.clusters[c]);
  }
  if (params.join_occluded) {
    // Pieces of one object either side of a nearer one become one (occlusion_join.h).
    join_occluded_pieces(
        f, result.clusters, label, std::move(pieces),
        [&](ScanCluster& sc, int id) {
          std::vector<Vec3> n;
          smooth_cluster(f, sc.pixels, label, id, params, sc.points, n);
          sc.shape = recognize_object_shape(sc.points, n, sc.support, params.shape, sc.around);
        },
        params.shape.min_coverage);
  }
  // Pieces of one object either side of a raised support's plane become one on the
  // lower support (occlusion_join.h), which keeps the label it is given up to date; a
  // stack found for the upper piece is void. The label is current when the occluded
  // pieces' join ran (it is rebuilt for it above, and kept since).
  std::vector<char> joined_across(result.clusters.size(), 0);
  if (params.join_across_supports) {
    if (!params.join_occluded) {
      std::fill(label.begin(), label.end(), -1);
      for (size_t c = 0; c < result.clusters.size(); ++c)
        for (int i : result.clusters[c].pixels) label[i] = static_cast<int>(c);
    }
    join_across_support_plane(
        f, result.clusters, label, stride, [&](double z) { return cluster_tolerance(params, z); },
        [&](double z) { return std::max(params.min_height_m, plane_band(params, z)); },
        [&](ScanCluster& sc, int id) {
          std::vector<Vec3> n;
          smooth_cluster(f, sc.pixels, label, id, params, sc.points, n);
          sc.shape = recognize_object_shape(sc.points, n, sc.support, params.shape, sc.around);
        },
        params.shape.min_coverage, joined_across);
  }
  // The shapes are fitted: the surface around each cluster served its fits alone, and the
  // result does not carry it.
  for (ScanCluster& sc : result.clusters) sc.around = {};
  if (!stacked.empty()) {
    // The label rebuilt above still holds when no pieces joined (a join removes one;
    // a rejected one gives its pixels back).
    if (!params.join_occluded || result.clusters.size() != kept) {
      std::fill(label.begin(), label.end(), -1);
      for (size_t c = 0; c < result.clusters.size(); ++c)
        for (int i : result.clusters[c].pixels) label[i] = static_cast<int>(c);
    }
    for (const auto& [upper, lower] : stacked) {
      const int u = label[upper], l = label[lower];
      if (u < 0 || l < 0 || u == l || joined_across[static_cast<size_t>(u)]) continue;
      // Merged pieces may close a loop (a on b on a): no stack is a loop.
      int at = l;
      for (size_t step = 0; at >= 0 && at != u && step < result.clusters.size(); ++step)
        at = result.clusters[static_cast<size_t>(at)].on_object;
      if (at != u) result.clusters[u].on_object = l;
    }
  }
  const auto band_at = [&](double z) { return plane_band(params, z); };
  // Each object's record reads its cluster alone: one item per object, the biggest
  // first, kept in cluster order.
  const size_t first_object = result.scene.objects.size();
  result.scene.objects.resize(first_object + result.clusters.size());
  std::vector<size_t> object_sizes(result.clusters.size());
  for (size_t c = 0; c < result.clusters.size(); ++c) object_sizes[c] = result.clusters[c].pixels.size();
  const std::vector<size_t> object_order = largest_first(object_sizes);
  parallel_for(result.clusters.size(), [&](size_t c) {
    const ScanCluster& sc = result.clusters[c];
    PhysicalObject& obj = result.scene.objects[first_object + c];
    for (const ShapeFit& fit : sc.shape.primitives) obj.primitives.push_back(fit.primitive);
    obj.point_count = static_cast<int>(sc.pixels.size());
    obj.fit = sc.shape.fit;
    for (const ScanSupport& sp : result.supports)
      if (sp.surface.plane == sc.support) obj.support_id = sp.surface.id;
    // Kept apart from an object cut by the border or hidden, whose piece it may be.
    size_t kept_apart = 0;
    for (int i : sc.pixels) kept_apart += apart[static_cast<size_t>(i)];
    obj.partial =
        cut_or_hidden(sc.pixels) || foot_cut_by_bottom(f, sc.pixels, bottom, params, band_at) ||
        obj.point_count < params.min_whole_points || sc.shape.depth_unseen ||
        2 * kept_apart > sc.pixels.size() ||
        (!sc.shape.primitives.empty() &&
         fitted_foot_off_image(f, sc.shape.primitives[0], sc.support, depth_rect, params, band_at));
  }, &object_order);
  result.stages.push_back({"shapes", ms_since(t0)});
  order_and_name_objects(result);
  if (params.plane_candidates) result.surfaces = find_plane_candidates(f, result, params, params.planes);
  return result;
}

}  // namespace annex
