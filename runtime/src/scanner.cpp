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

#include "annex/runtime/object_segmenter.h"
#include "occlusion_join.h"
#include "stacking.h"

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <numeric>
#include <random>
#include <thread>

#include "annex/runtime/params_validation.h"

namespace annex {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

bool valid(const PointXYZRGB& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && p.z > 0;
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
  PointXYZRGB nan;
  nan.x = nan.y = nan.z = std::numeric_limits<float>::quiet_NaN();
  out.points.assign(static_cast<size_t>(k.width) * k.height, nan);
  for (const PointXYZRGB& p : in.points) {
    if (!valid(p)) continue;
    const int u = static_cast<int>(std::lround(k.fx * p.x / p.z + k.cx));
    const int v = static_cast<int>(std::lround(k.fy * p.y / p.z + k.cy));
    if (u < 0 || v < 0 || u >= k.width || v >= k.height) continue;
    PointXYZRGB& q = out.points[static_cast<size_t>(v) * k.width + u];
    if (!valid(q) || p.z < q.z) q = p;
  }
  return out;
}

// The plane's inlier band at depth z: the configured width, or wider where the
// Kinect's axial noise grows (a floor 3 m away is ~1.4 cm noisy).
double plane_band(const ScanParams& params, double z) {
  return std::max(params.plane_distance_m, params.plane_noise_factor * kinect_sigma_z(z));
}

struct PlaneFit {
  Vec3 n;
  double d = 0;
  bool ok = false;
};

// Least-squares plane through points (smallest eigenvector of the covariance).
PlaneFit fit_plane(const std::vector<Vec3>& pts) {
  if (pts.size() < 3) return {};
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Vec3& p : pts) mean += Eigen::Vector3d(p.x, p.y, p.z);
  mean /= static_cast<double>(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& p : pts) {
    const Eigen::Vector3d q = Eigen::Vector3d(p.x, p.y, p.z) - mean;
    cov += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(cov);
  const Eigen::Vector3d n = es.eigenvectors().col(0);
  return {{n.x(), n.y(), n.z()}, -n.dot(mean), true};
}

struct PlaneSearch {
  PlaneFit plane;
  int inliers = 0;  // strided
};

PlaneSearch find_plane(const Frame& f, const ScanParams& params, Vec3 up,
                       std::vector<int>& strided, std::mt19937_64& rng) {
  const int s = std::max(1, params.pixel_stride);
  strided.clear();
  for (int y = 0; y < f.height; y += s)
    for (int x = 0; x < f.width; x += s) {
      const int i = y * f.width + x;
      if (valid(f.points[i]) && f.points[i].z <= params.max_depth_m) strided.push_back(i);
    }
  PlaneSearch best;
  if (strided.size() < 50) return best;
  // Inliers are counted on a fixed subsample per hypothesis; the winner is refined
  // on every strided pixel.
  // The search and the fit use the fixed band: a depth-scaled one would favour big far
  // surfaces (a wall seen obliquely) over the support.
  const double band = params.plane_distance_m;
  std::uniform_int_distribution<size_t> pick(0, strided.size() - 1);
  std::vector<Vec3> probe;
  for (int k = 0; k < 2000; ++k) probe.push_back(to_vec(f.points[strided[pick(rng)]]));
  const double cos_max = std::cos(params.max_plane_angle_deg * 3.14159265358979 / 180.0);
  PlaneFit hyp_best;
  int hyp_count = -1;
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
    if (!valid(f.points[i1]) || !valid(f.points[i2])) continue;
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
    int count = 0;
    for (const Vec3& p : probe) count += std::abs(dot(n, p) + d) < band;
    if (count > hyp_count) {
      hyp_count = count;
      hyp_best = {n, d, true};
    }
  }
  if (!hyp_best.ok) return best;
  PlaneFit plane = hyp_best;
  for (int round = 0; round < 2; ++round) {
    // Every third strided pixel is plenty for a least-squares plane.
    std::vector<Vec3> in;
    in.reserve(strided.size() / 3 + 1);
    for (size_t k = 0; k < strided.size(); k += 3) {
      const Vec3 p = to_vec(f.points[strided[k]]);
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
  for (int i : strided)
    best.inliers += std::abs(dot(plane.n, to_vec(f.points[i])) + plane.d) < band;
  best.plane = plane;
  return best;
}

struct Hull2 {
  Vec3 u, v;
  std::vector<std::array<double, 2>> pts;  // counter-clockwise
  // Binary search of the wedge around pts[0]: O(log n) per point.
  bool contains(Vec3 p) const {
    const size_t n = pts.size();
    if (n < 3) return false;
    const double a = dot(u, p), b = dot(v, p);
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
  return h;
}

// Largest 4-connected region of plane inliers on the strided grid: coplanar clutter
// elsewhere in the room does not stretch the hull.
std::vector<Vec3> largest_plane_region(const Frame& f, const std::vector<int>& strided,
                                       const PlaneFit& plane, const ScanParams& params,
                                       int stride) {
  const int gw = (f.width + stride - 1) / stride, gh = (f.height + stride - 1) / stride;
  std::vector<int> label(static_cast<size_t>(gw) * gh, -2);  // -2 not inlier, -1 unvisited
  for (int i : strided) {
    const Vec3 p = to_vec(f.points[i]);
    if (std::abs(dot(plane.n, p) + plane.d) < plane_band(params, p.z)) {
      const int x = (i % f.width) / stride, y = (i / f.width) / stride;
      label[static_cast<size_t>(y) * gw + x] = -1;
    }
  }
  int best_label = -1, best_size = 0, next = 0;
  std::vector<int> queue;
  for (size_t start = 0; start < label.size(); ++start) {
    if (label[start] != -1) continue;
    queue.assign(1, static_cast<int>(start));
    label[start] = next;
    for (size_t q = 0; q < queue.size(); ++q) {
      const int g = queue[q], x = g % gw, y = g / gw;
      const int nb[4] = {x > 0 ? g - 1 : -1, x + 1 < gw ? g + 1 : -1, y > 0 ? g - gw : -1,
                         y + 1 < gh ? g + gw : -1};
      for (int m : nb)
        if (m >= 0 && label[m] == -1) {
          label[m] = next;
          queue.push_back(m);
        }
    }
    if (static_cast<int>(queue.size()) > best_size) {
      best_size = static_cast<int>(queue.size());
      best_label = next;
    }
    ++next;
  }
  // Only each grid row's outermost region pixels can be hull vertices: an image row
  // seen on a plane is a line, and its inner pixels lie between the outer two.
  std::vector<Vec3> out;
  for (int y = 0; y < gh; ++y) {
    int first = -1, last = -1;
    for (int x = 0; x < gw; ++x)
      if (label[static_cast<size_t>(y) * gw + x] == best_label) {
        if (first < 0) first = x;
        last = x;
      }
    if (first < 0) continue;
    for (int x : {first, last})
      out.push_back(to_vec(f.points[static_cast<size_t>(y) * stride * f.width + x * stride]));
  }
  return out;
}

// Region growing over prism pixels on the strided grid: neighbours within
// +-window grid steps join when closer than the tolerance in 3D (a Euclidean
// clustering that uses the image grid as its neighbour search).
std::vector<std::vector<int>> grow_clusters(const Frame& f, const std::vector<char>& mask,
                                            const std::vector<int>& seeds, int step,
                                            const ScanParams& params) {
  std::vector<int> label(mask.size(), -1);
  std::vector<std::vector<int>> clusters;
  const double tol2 = params.cluster_tolerance_m * params.cluster_tolerance_m;
  const int w = std::max(1, params.cluster_window_px / step);
  std::vector<int> queue;
  for (int start : seeds) {
    if (label[start] >= 0) continue;
    const int id = static_cast<int>(clusters.size());
    queue.assign(1, start);
    label[start] = id;
    for (size_t q = 0; q < queue.size(); ++q) {
      const int i = queue[q], x = i % f.width, y = i / f.width;
      const PointXYZRGB& p = f.points[i];
      for (int dy = -w; dy <= w; ++dy) {
        const int yy = y + dy * step;
        if (yy < 0 || yy >= f.height) continue;
        for (int dx = -w; dx <= w; ++dx) {
          const int xx = x + dx * step;
          if (xx < 0 || xx >= f.width) continue;
          const int j = yy * f.width + xx;
          if (!mask[j] || label[j] >= 0) continue;
          const PointXYZRGB& o = f.points[j];
          const double ddx = p.x - o.x, ddy = p.y - o.y, ddz = p.z - o.z;
          if (ddx * ddx + ddy * ddy + ddz * ddz > tol2) continue;
          label[j] = id;
          queue.push_back(j);
        }
      }
    }
    clusters.push_back(queue);
  }
  return clusters;
}

// Whether a cluster's surface runs on above the height band: grid neighbours of its
// pixels that are above max_height_m yet within the cluster tolerance in 3D. Walls,
// cupboards and people do; an object on the support ends below the band's top.
bool continues_above(const Frame& f, const std::vector<int>& grid_pixels, int step,
                     const PlaneFit& plane, const ScanParams& params) {
  const double tol2 = params.cluster_tolerance_m * params.cluster_tolerance_m;
  size_t joins = 0;
  for (int i : grid_pixels) {
    const int x = i % f.width, y = i / f.width;
    const PointXYZRGB& p = f.points[i];
    const int nb[4][2] = {{x - step, y}, {x + step, y}, {x, y - step}, {x, y + step}};
    for (const auto& xy : nb) {
      if (xy[0] < 0 || xy[1] < 0 || xy[0] >= f.width || xy[1] >= f.height) continue;
      const PointXYZRGB& q = f.points[static_cast<size_t>(xy[1]) * f.width + xy[0]];
      if (!valid(q) || dot(plane.n, to_vec(q)) + plane.d <= params.max_height_m) continue;
      const double dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
      joins += dx * dx + dy * dy + dz * dz <= tol2;
    }
  }
  return joins >= std::max<size_t>(8, grid_pixels.size() / 50);
}

// Full-resolution pixels of a cluster found on the strided grid: each grid pixel's
// block, keeping pixels in the height band and near their grid pixel in 3D.
std::vector<int> expand_cluster(const Frame& f, const std::vector<int>& grid_pixels, int step,
                                const PlaneFit& plane, const ScanParams& params) {
  // Pixels come out in raster order: grid pixels sorted, then each grid row's blocks
  // emitted one image row at a time (blocks do not overlap), so nothing larger than
  // the grid list is sorted.
  std::vector<int> grid = grid_pixels;
  std::sort(grid.begin(), grid.end());
  std::vector<int> out;
  out.reserve(grid.size() * step * step);
  const double tol2 = params.cluster_tolerance_m * params.cluster_tolerance_m;
  for (size_t row = 0; row < grid.size();) {
    const int y = grid[row] / f.width;
    size_t end = row;
    while (end < grid.size() && grid[end] / f.width == y) ++end;
    for (int dy = 0; dy < step && y + dy < f.height; ++dy)
      for (size_t k = row; k < end; ++k) {
        const int x = grid[k] % f.width;
        const PointXYZRGB& c = f.points[grid[k]];
        for (int dx = 0; dx < step && x + dx < f.width; ++dx) {
          const int j = (y + dy) * f.width + x + dx;
          const PointXYZRGB& q = f.points[j];
          if (!valid(q)) continue;
          const double h = dot(plane.n, to_vec(q)) + plane.d;
          if (h < std::max(params.min_height_m, plane_band(params, q.z)) || h > params.max_height_m)
            continue;
          const double ddx = c.x - q.x, ddy = c.y - q.y, ddz = c.z - q.z;
          if (ddx * ddx + ddy * ddy + ddz * ddz > tol2) continue;
          out.push_back(j);
        }
      }
    row = end;
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
  for (size_t k = 0; k < pixels.size(); k += step) {
    const int i = pixels[k], x = i % f.width, y = i / f.width;
    const Vec3 p = to_vec(f.points[i]);
    // Far away, pixels spread and depth steps grow (1.8 cm at 2.5 m): the radius
    // widens to reach the window's pixels and span the noise, else no plane is found.
    const double pixel_m = p.z / CameraIntrinsics{}.fx;  // Kinect pixel spacing at depth
    const double r = std::max({params.mls_radius_m, 3 * kinect_sigma_z(p.z), 1.5 * w * pixel_m});
    const double r2 = r * r;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d sq = Eigen::Matrix3d::Zero();
    int n = 0;
    const int hop = w > 3 ? 2 : 1;  // a sparser window keeps the cost flat
    for (int dy = -w; dy <= w; dy += hop) {
      const int yy = y + dy;
      if (yy < 0 || yy >= f.height) continue;
      for (int dx = -w; dx <= w; dx += hop) {
        const int xx = x + dx;
        if (xx < 0 || xx >= f.width) continue;
        const int j = yy * f.width + xx;
        if (label[j] != id) continue;
        const Vec3 q = to_vec(f.points[j]);
        const Vec3 e = q - p;
        if (dot(e, e) > r2) continue;
        const Eigen::Vector3d v(q.x, q.y, q.z);
        sum += v;
        sq += v * v.transpose();
        ++n;
      }
    }
    if (n < 5 || params.mls_radius_m <= 0) {
      points.push_back(p);
      normals.push_back({0, 0, 0});
      continue;
    }
    const Eigen::Vector3d mean = sum / n;
    const Eigen::Matrix3d cov = sq / n - mean * mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(cov);
    Eigen::Vector3d nn = es.eigenvectors().col(0);
    const Eigen::Vector3d pv(p.x, p.y, p.z);
    if (nn.dot(pv) > 0) nn = -nn;
    // Veil points (mixed pixels along depth edges) lie on surfaces seen edge-on.
    if (-nn.dot(pv) < params.min_view_cos * pv.norm()) continue;
    const Eigen::Vector3d proj = pv - nn * nn.dot(pv - mean);
    points.push_back({proj.x(), proj.y(), proj.z()});
    normals.push_back({nn.x(), nn.y(), nn.z()});
  }
}

// Runs body(0..n-1) on up to `threads` threads, items handed out in order.
template <typename F>
void parallel_for(size_t n, int threads, F body) {
  const size_t workers = std::min<size_t>(n, static_cast<size_t>(std::max(1, threads)));
  if (workers <= 1) {
    for (size_t i = 0; i < n; ++i) body(i);
    return;
  }
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i = next++; i < n; i = next++) body(i);
  };
  std::vector<std::thread> pool;
  for (size_t w = 1; w < workers; ++w) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}

// Two objects on a support cannot interpenetrate: a cluster lying mostly inside a
// bigger object's fitted solid is a part of it that a depth edge cut off (a bottle's
// handle behind its rim). Each such part joins the biggest object that contains it,
// and the grown objects are smoothed and fitted again.
void merge_parts(const Frame& f, const ScanParams& params, ScanResult& result,
                 std::vector<int>& label, std::vector<std::vector<Vec3>>& normals) {
  const size_t n = result.clusters.size();
  if (n < 2 || params.part_margin_m <= 0) return;
  std::vector<size_t> by_size(n);
  std::iota(by_size.begin(), by_size.end(), 0);
  std::stable_sort(by_size.begin(), by_size.end(), [&](size_t a, size_t b) {
    return result.clusters[a].pixels.size() > result.clusters[b].pixels.size();
  });
  std::vector<int> owner(n, -1);
  for (size_t k = 1; k < n; ++k) {
    const ScanCluster& part = result.clusters[by_size[k]];
    for (size_t j = 0; j < k && owner[by_size[k]] < 0; ++j) {
      const size_t big = by_size[j];
      if (owner[big] >= 0 || result.clusters[big].shape.primitives.empty()) continue;
      const ShapeFit& solid = result.clusters[big].shape.primitives.front();
      size_t inside = 0;
      for (const Vec3& p : part.points) inside += within_shape(solid, p, params.part_margin_m);
      if (!part.points.empty() && inside >= params.part_share * part.points.size())
        owner[by_size[k]] = static_cast<int>(big);
    }
  }
  std::vector<char> grown(n, 0);
  for (size_t c = 0; c < n; ++c) {
    if (owner[c] < 0) continue;
    ScanCluster& big = result.clusters[owner[c]];
    for (int i : result.clusters[c].pixels) label[i] = owner[c];
    const auto middle = big.pixels.insert(big.pixels.end(), result.clusters[c].pixels.begin(),
                                          result.clusters[c].pixels.end());
    std::inplace_merge(big.pixels.begin(), middle, big.pixels.end());  // both sorted
    grown[owner[c]] = 1;
  }
  parallel_for(n, params.threads, [&](size_t c) {
    if (!grown[c]) return;
    ScanCluster& sc = result.clusters[c];
    smooth_cluster(f, sc.pixels, label, static_cast<int>(c), params, sc.points, normals[c]);
    sc.shape = recognize_object_shape(sc.points, normals[c], result.plane, params.shape);
  });
  std::vector<ScanCluster> kept;
  for (size_t c = 0; c < n; ++c)
    if (owner[c] < 0) kept.push_back(std::move(result.clusters[c]));
  result.clusters = std::move(kept);
}

// Objects standing on another object's top are fitted on that top (stacking.h).
void restack(ScanResult& result, std::vector<std::vector<Vec3>>& normals, const ScanParams& params) {
  if (!params.stack_on_objects || result.clusters.size() < 2) return;
  std::vector<StackedObject> objects(result.clusters.size());
  for (size_t c = 0; c < objects.size(); ++c) {
    objects[c].points = std::move(result.clusters[c].points);
    objects[c].normals = std::move(normals[c]);
    objects[c].shape = std::move(result.clusters[c].shape);
  }
  fit_stacked_objects(objects, result.plane, params.shape);
  for (size_t c = 0; c < objects.size(); ++c) {
    result.clusters[c].points = std::move(objects[c].points);
    normals[c] = std::move(objects[c].normals);
    result.clusters[c].shape = std::move(objects[c].shape);
  }
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
  result.clusters = std::move(clusters);
  result.scene.objects = std::move(objects);
}

Result<ScanResult> scan_frame(const Frame& input, const ScanParams& params) {
  // Parameters set in code are checked like a config file's (params_validation.h).
  if (Status s = validate_scan_params(params); !s) return s.error();
  if (input.width <= 0 || input.height <= 0 ||
      input.points.size() != static_cast<size_t>(input.width) * input.height)
    return Error{"frame size " + std::to_string(input.width) + "x" + std::to_string(input.height) +
                     " does not match its " + std::to_string(input.points.size()) + " points",
                 {"frame " + std::to_string(input.index), 0, 0}};
  const Frame reorganized = input.organized() ? Frame{} : organize(input);
  const Frame& f = input.organized() ? input : reorganized;
  const Location where{"frame " + std::to_string(input.index), 0, 0};
  ScanResult result;
  std::mt19937_64 rng(params.shape.seed);
  const Vec3 up = effective_up(params);

  auto t0 = Clock::now();
  std::vector<int> strided;
  const PlaneSearch ps = find_plane(f, params, up, strided, rng);
  if (strided.size() < 50) {
    // Valid points that all lie beyond the range are most often a cloud in millimetres.
    std::vector<float> far;
    for (size_t i = 0; i < f.points.size(); i += 97)
      if (valid(f.points[i])) far.push_back(f.points[i].z);
    if (far.size() < 10) return Error{"the frame has no valid depth points", where};
    std::nth_element(far.begin(), far.begin() + far.size() / 2, far.end());
    const double median = far[far.size() / 2];
    char text[160];
    std::snprintf(text, sizeof text, "no depth within max_depth_m (%g m): the median depth is %g%s",
                  params.max_depth_m, median,
                  median > 50 ? "; Annex expects metres (is this cloud in millimetres?)" : "");
    return Error{text, where};
  }
  const int stride = std::max(1, params.pixel_stride);
  if (!ps.plane.ok || ps.inliers * stride * stride < params.min_plane_points)
    return Error{"no horizontal plane found (support must be within " +
                     std::to_string(static_cast<int>(params.max_plane_angle_deg)) +
                     " degrees of the up vector; see max_plane_angle_deg, up, camera_tilt_deg)",
                 where};
  result.plane = {ps.plane.n, ps.plane.d};
  result.scene.support = result.plane;
  result.plane_inliers = ps.inliers * stride * stride;
  result.stages.push_back({"plane", ms_since(t0)});

  t0 = Clock::now();
  const std::vector<Vec3> region =
      largest_plane_region(f, strided, ps.plane, params, stride);
  // The support continues under the camera's view: the floor between the camera
  // and its visible part is hidden by the objects standing on it or out of view, so
  // the camera's foot on the plane joins the hull.
  std::vector<Vec3> hull_points = region;
  if (params.hull_to_camera) hull_points.push_back(ps.plane.n * -ps.plane.d);
  Hull2 hull = convex_hull(hull_points, ps.plane.n);
  if (params.hull_margin_m > 0 && hull.pts.size() >= 3) {
    // The hull grown by the margin (its corners swept by a 16-gon): a support seen
    // only in part, such as a floor behind furniture, still holds what stands beside it.
    std::vector<Vec3> grown;
    for (const auto& q : hull.pts)
      for (int k = 0; k < 16; ++k) {
        const double t = 2 * 3.14159265358979 * k / 16;
        grown.push_back(hull.u * (q[0] + params.hull_margin_m * std::cos(t)) +
                        hull.v * (q[1] + params.hull_margin_m * std::sin(t)));
      }
    hull = convex_hull(grown, ps.plane.n);
  }
  for (const auto& q : hull.pts) {
    Vec3 p = hull.u * q[0] + hull.v * q[1];
    p = p - ps.plane.n * (dot(ps.plane.n, p) + ps.plane.d);
    result.hull.push_back(p);
  }
  // The prism test runs on the strided grid; clusters grow there and are then
  // expanded to full resolution.
  std::vector<char> mask(f.points.size(), 0);
  std::vector<int> seeds;
  for (int i : strided) {
    const PointXYZRGB& q = f.points[i];
    const Vec3 p = to_vec(q);
    const double h = dot(ps.plane.n, p) + ps.plane.d;
    if (h < std::max(params.min_height_m, plane_band(params, p.z)) || h > params.max_height_m)
      continue;
    if (hull.contains(p)) {
      mask[i] = 1;
      seeds.push_back(i);
    }
  }
  result.stages.push_back({"prism", ms_since(t0)});

  t0 = Clock::now();
  std::vector<std::vector<int>> clusters;
  for (const std::vector<int>& whole : grow_clusters(f, mask, seeds, stride, params)) {
    if (static_cast<int>(whole.size()) * stride * stride < params.min_cluster_points / 2) continue;
    if (params.drop_cut_clusters && continues_above(f, whole, stride, ps.plane, params)) continue;
    // Touching objects apart at the creases and depth steps between them.
    for (const std::vector<int>& grid :
         split_cluster(f, whole, stride, params.cluster_tolerance_m, params.segment)) {
      std::vector<int> full = expand_cluster(f, grid, stride, ps.plane, params);
      if (static_cast<int>(full.size()) < params.min_cluster_points ||
          static_cast<int>(full.size()) > params.max_cluster_points)
        continue;
      clusters.push_back(std::move(full));
    }
  }
  std::vector<int> label(f.points.size(), -1);
  for (size_t c = 0; c < clusters.size(); ++c)
    for (int i : clusters[c]) label[i] = static_cast<int>(c);
  result.stages.push_back({"clusters", ms_since(t0)});

  t0 = Clock::now();
  // Clusters are independent: smoothing and shape fits split over worker threads
  // (each fit seeds its own generator, so the result does not depend on the split).
  std::vector<std::vector<Vec3>> normals(clusters.size());
  result.clusters.resize(clusters.size());
  parallel_for(clusters.size(), params.threads, [&](size_t c) {
    ScanCluster& sc = result.clusters[c];
    sc.pixels = clusters[c];
    smooth_cluster(f, clusters[c], label, static_cast<int>(c), params, sc.points, normals[c]);
  });
  result.stages.push_back({"mls", ms_since(t0)});

  t0 = Clock::now();
  parallel_for(clusters.size(), params.threads, [&](size_t c) {
    ScanCluster& sc = result.clusters[c];
    sc.shape = recognize_object_shape(sc.points, normals[c], result.plane, params.shape);
  });
  restack(result, normals, params);
  merge_parts(f, params, result, label, normals);
  if (params.join_occluded) {
    // Pieces of one object either side of a nearer one become one (occlusion_join.h).
    std::fill(label.begin(), label.end(), -1);
    for (size_t c = 0; c < result.clusters.size(); ++c)
      for (int i : result.clusters[c].pixels) label[i] = static_cast<int>(c);
    join_occluded_pieces(
        f, result.clusters, label,
        [&](ScanCluster& sc, int id) {
          std::vector<Vec3> n;
          smooth_cluster(f, sc.pixels, label, id, params, sc.points, n);
          sc.shape = recognize_object_shape(sc.points, n, result.plane, params.shape);
        },
        params.shape.min_coverage);
  }
  for (const ScanCluster& sc : result.clusters) {
    PhysicalObject obj;
    for (const ShapeFit& fit : sc.shape.primitives) obj.primitives.push_back(fit.primitive);
    obj.point_count = static_cast<int>(sc.pixels.size());
    obj.fit = sc.shape.fit;
    result.scene.objects.push_back(std::move(obj));
  }
  result.stages.push_back({"shapes", ms_since(t0)});
  order_and_name_objects(result);
  return result;
}

}  // namespace annex
