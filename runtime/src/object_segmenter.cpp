// Splitting clusters at concave creases and depth steps (object_segmenter.h).
#include "annex/runtime/object_segmenter.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <type_traits>

#include "annex/runtime/object_shape_recognizer.h"

namespace annex {
namespace {

bool valid(const PointXYZRGB& p) { return std::isfinite(p.z) && p.z > 0; }

// The cluster's grid pixels inside their bounding box, for O(1) membership.
struct LocalGrid {
  int step = 1, gx0 = 0, gy0 = 0, gw = 0, gh = 0, width = 0;
  int shift = -1;         // log2(step) when step is a power of two: a shift, not a division
  std::vector<int> slot;  // index into grid_pixels, -1 outside the cluster
  int at(int x, int y) const {  // full-resolution pixel -> its grid pixel's slot
    if (x < 0 || y < 0) return -1;
    const int gx = (shift >= 0 ? x >> shift : x / step) - gx0;
    const int gy = (shift >= 0 ? y >> shift : y / step) - gy0;
    return local(gx, gy);
  }
  int local(int gx, int gy) const {  // cell of the cluster's box -> slot
    if (gx < 0 || gy < 0 || gx >= gw || gy >= gh) return -1;
    return slot[static_cast<size_t>(gy) * gw + gx];
  }
};

// std::lround for an arm length in pixels (not negative): x + 0.5 is exact below 2^30
// except at 0.49999999999999994, which rounds to 1 instead of 0, and the callers take
// at least 1 pixel anyway. Several times cheaper than the library call.
int round_arm(double x) {
  return x >= 0 && x < 1073741824.0 ? static_cast<int>(x + 0.5) : static_cast<int>(std::lround(x));
}

int find_root(std::vector<int>& parent, int a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}

// The region (root) other than `root` with the grid pixel nearest in the image to one
// of root's; -1 when there is none.
int nearest_region(const std::vector<int>& grid_pixels, const std::vector<int>& region,
                   std::vector<int>& parent, int root, int width) {
  const int n = static_cast<int>(grid_pixels.size());
  std::vector<int> root_of(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) root_of[static_cast<size_t>(k)] = find_root(parent, region[static_cast<size_t>(k)]);
  int best = -1;
  long long least = -1;
  for (int k = 0; k < n; ++k) {
    if (root_of[static_cast<size_t>(k)] != root) continue;
    const int x = grid_pixels[static_cast<size_t>(k)] % width, y = grid_pixels[static_cast<size_t>(k)] / width;
    for (int m = 0; m < n; ++m) {
      if (root_of[static_cast<size_t>(m)] == root) continue;
      const long long dx = grid_pixels[static_cast<size_t>(m)] % width - x, dy = grid_pixels[static_cast<size_t>(m)] / width - y;
      if (least < 0 || dx * dx + dy * dy < least) least = dx * dx + dy * dy, best = root_of[static_cast<size_t>(m)];
    }
  }
  return best;
}

// Fewer crease pixels than this draw no line to cut along (most far clusters have none).
constexpr std::ptrdiff_t kLevelMinCreasePixels = 4;

// The level cut (SegmenterParams::level_cut): grid neighbours within the grid columns
// col_lo..col_hi, one below `height` over the support and one at or above it, are not
// joined.
struct LevelCut {
  double height = 0;
  int col_lo = 0, col_hi = -1;
  bool spans(int column) const { return column >= col_lo && column <= col_hi; }
  bool parts(double h_a, double h_b, int column) const {
    return spans(column) && (h_a < height) != (h_b < height);
  }
  bool above(double h, int column) const { return spans(column) && !(h < height); }
};

// Each grid pixel's height over the support (NaN without depth).
std::vector<double> heights_over(const Frame& f, const std::vector<int>& grid_pixels,
                                 const Plane& support) {
  std::vector<double> h(grid_pixels.size(), std::numeric_limits<double>::quiet_NaN());
  for (size_t k = 0; k < grid_pixels.size(); ++k) {
    const PointXYZRGB& p = f.points[static_cast<size_t>(grid_pixels[k])];
    if (valid(p)) h[k] = dot(support.normal, Vec3{p.x, p.y, p.z}) + support.d;
  }
  return h;
}

// The crease pixels' heights gather in the window of heights that holds most of them:
// one arm wide (a right-angle crease marks pixels up to about half an arm up its wall)
// plus the test's noise either side. What stands on the crease rises level_min_height_m
// or more above that window, in some grid columns; when the crease runs under
// level_min_span of them (less an arm, margin - 1 columns, at either end), and the
// cluster reaches level_min_height_m or more below the
// window, the cut runs one arm below the window's top (above the crease pixels' noise
// over the lower object's top, below the upper object's wall), within the columns where
// the crease runs under it and `margin` columns beyond either end (where the crease
// fades at the upper object's silhouette). A crease pixel on a flat top (a noisy far
// edge) has nothing standing over it.
std::optional<LevelCut> level_crease_cut(const Frame& f, const std::vector<int>& grid_pixels,
                                         const std::vector<double>& height,
                                         const std::vector<char>& crease, int step, int margin,
                                         const SegmenterParams& params) {
  const int n = static_cast<int>(grid_pixels.size());
  std::vector<double> crease_heights;
  std::vector<float> depths;
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(height[static_cast<size_t>(k)])) continue;
    depths.push_back(f.points[static_cast<size_t>(grid_pixels[k])].z);
    if (crease[static_cast<size_t>(k)]) crease_heights.push_back(height[static_cast<size_t>(k)]);
  }
  const auto middle = depths.begin() + static_cast<std::ptrdiff_t>(depths.size() / 2);
  std::nth_element(depths.begin(), middle, depths.end());
  const double window =
      params.arm_m + 2 * params.noise_factor * 0.41 * params.depth_noise.sigma_z(*middle);
  std::sort(crease_heights.begin(), crease_heights.end());
  size_t best = 0, best_count = 0;
  for (size_t a = 0, b = 0; a < crease_heights.size(); ++a) {
    while (b < crease_heights.size() && crease_heights[b] <= crease_heights[a] + window) ++b;
    if (b - a > best_count) best_count = b - a, best = a;
  }
  const double lo = crease_heights[best], hi = lo + window;
  std::vector<int> crease_columns, upper_columns;
  double lowest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) {
    const double h = height[static_cast<size_t>(k)];
    if (!std::isfinite(h)) continue;
    lowest = std::min(lowest, h);
    const int column = (grid_pixels[k] % f.width) / step;
    if (h > hi + params.level_min_height_m)
      upper_columns.push_back(column);
    else if (h >= lo && h <= hi && crease[static_cast<size_t>(k)])
      crease_columns.push_back(column);
  }
  if (upper_columns.empty() || lo - lowest < params.level_min_height_m) return std::nullopt;
  for (std::vector<int>* v : {&crease_columns, &upper_columns}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  std::vector<int> under;  // the crease's columns under what rises above it
  std::set_intersection(crease_columns.begin(), crease_columns.end(), upper_columns.begin(),
                        upper_columns.end(), std::back_inserter(under));
  // Within an arm of the silhouette's ends the crease test's arms along the row leave the
  // cluster: the crease fades there whatever stands on it.
  const double testable =
      std::max(1.0, static_cast<double>(upper_columns.size()) - 2.0 * (margin - 1));
  if (static_cast<double>(under.size()) < params.level_min_span * testable) return std::nullopt;
  return LevelCut{hi - params.arm_m, under.front() - margin, under.back() + margin};
}

// The crease test's threshold at depth z: min_crease_depth_m, or noise_factor times the
// noise of its depth combination (each depth a mean of up to 9 pixels: z_p -
// harmonic(z_a, z_b) has about sqrt(1.5) / 3 of one pixel's noise).
double crease_threshold(double z, const SegmenterParams& params) {
  return std::max(params.min_crease_depth_m,
                  params.noise_factor * 0.41 * params.depth_noise.sigma_z(z));
}

// Whether a right-angle crease (right_angle_depth_share of the arm, arm_px pixels at
// depth z) stays under the test's threshold.
bool blind_at(double threshold, double arm_px, double z, double focal_px,
              const SegmenterParams& params) {
  return threshold > params.right_angle_depth_share * arm_px * z / focal_px;
}

}  // namespace

bool crease_test_blind(double z, double focal_px, const SegmenterParams& params) {
  const double arm_px = std::max(params.min_arm_px, params.arm_m * focal_px / z);
  return blind_at(crease_threshold(z, params), arm_px, z, focal_px, params);
}

std::vector<std::vector<int>> split_cluster(const Frame& f, const std::vector<int>& grid_pixels,
                                            int step, double tolerance_m,
                                            const SegmenterParams& params, const Plane* support) {
  if (!params.enabled || grid_pixels.size() < 8 || !f.organized()) return {grid_pixels};
  step = std::max(1, step);
  LocalGrid g;
  g.step = step;
  g.width = f.width;
  if ((step & (step - 1)) == 0) g.shift = std::countr_zero(static_cast<unsigned>(step));
  int gx1 = 0, gy1 = 0;
  g.gx0 = g.gy0 = 1 << 30;
  for (int i : grid_pixels) {
    const int gx = (i % f.width) / step, gy = (i / f.width) / step;
    g.gx0 = std::min(g.gx0, gx);
    g.gy0 = std::min(g.gy0, gy);
    gx1 = std::max(gx1, gx);
    gy1 = std::max(gy1, gy);
  }
  g.gw = gx1 - g.gx0 + 1;
  g.gh = gy1 - g.gy0 + 1;
  g.slot.assign(static_cast<size_t>(g.gw) * g.gh, -1);
  const int n = static_cast<int>(grid_pixels.size());
  for (int k = 0; k < n; ++k) {
    const int i = grid_pixels[k];
    g.slot[static_cast<size_t>((i / f.width) / step - g.gy0) * g.gw + (i % f.width) / step - g.gx0] = k;
  }

  // Mean inverse depth over the 3x3 pixels around a pixel of the cluster's box on the
  // same surface (within 2 cm of the centre), 0 where the centre is not usable. The
  // crease test reads it at each grid pixel and at its arms' ends, up to 9 times per
  // grid pixel, mostly at pixels other grid pixels read too: each pixel's mean is
  // computed on first use and kept (box pixels no test reads are never computed).
  const int bx0 = g.gx0 * step, by0 = g.gy0 * step;
  const int bw = std::min(f.width - bx0, g.gw * step), bh = std::min(f.height - by0, g.gh * step);
  constexpr float kUnknown = -1.0f;
  std::vector<float> mean_inv(static_cast<size_t>(bw) * bh, kUnknown);
  // (x, y) lies in the cluster's box here, so its grid cell is a cell of the box.
  auto mean_inverse_depth = [&](int x, int y) -> float {
    if (x < 1 || y < 1 || x >= f.width - 1 || y >= f.height - 1) return 0.0f;
    const int gx = (g.shift >= 0 ? x >> g.shift : x / step) - g.gx0;
    const int gy = (g.shift >= 0 ? y >> g.shift : y / step) - g.gy0;
    if (g.slot[static_cast<size_t>(gy) * g.gw + gx] < 0) return 0.0f;
    const PointXYZRGB& c = f.points[static_cast<size_t>(y) * f.width + x];
    if (!valid(c)) return 0.0f;
    // valid(q) and within 2 cm of c in one test: a NaN or infinite depth fails the <=
    // (c.z is finite), and q.z > 0 is tested apart as valid() does, unless c is farther
    // than 4 cm: then a depth of 0 or less is more than 4 cm from it, after rounding too.
    auto mean = [&](auto test_positive) {
      double sum = 0;
      int count = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        const PointXYZRGB* row = &f.points[static_cast<size_t>(y + dy) * f.width + x];
        for (int dx = -1; dx <= 1; ++dx) {
          const float qz = row[dx].z;
          if (!(std::abs(qz - c.z) <= 0.02f) || (test_positive && !(qz > 0))) continue;
          sum += 1.0 / qz;
          ++count;
        }
      }
      return static_cast<float>(sum / count);
    };
    return c.z > 0.04f ? mean(std::false_type{}) : mean(std::true_type{});
  };
  auto inv_depth = [&](int x, int y) -> double {
    // One unsigned compare per axis tests both ends of the box.
    const unsigned lx = static_cast<unsigned>(x - bx0), ly = static_cast<unsigned>(y - by0);
    if (lx >= static_cast<unsigned>(bw) || ly >= static_cast<unsigned>(bh)) return 0;
    float& m = mean_inv[static_cast<size_t>(ly) * bw + lx];
    if (m == kUnknown) m = mean_inverse_depth(x, y);
    return m;
  };

  // Crease pixels.
  const double fx = focal_px(f);
  std::vector<char> crease(n, 0);
  const int dirs[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
  // The directions' lengths, hypot(d) (1 along rows and columns), computed once.
  const double diagonal_length = std::hypot(1.0, 1.0);
  for (int k = 0; k < n; ++k) {
    const int i = grid_pixels[k], x = i % f.width, y = i / f.width;
    const double ip = inv_depth(x, y);
    if (ip <= 0) continue;
    const double z = 1.0 / ip;
    const double arm_px = std::max(params.min_arm_px, params.arm_m * fx / z);
    const double threshold = crease_threshold(z, params);
    // Where even a right-angle crease would not stand out of the noise (beyond about
    // 2 m on a Kinect) the test cannot tell: such pixels are never creases.
    if (blind_at(threshold, arm_px, z, fx, params)) continue;
    // Arm lengths in pixels along the rows and columns and along the diagonals.
    const int r_axis = std::max(1, round_arm(arm_px));
    const int r_diagonal = std::max(1, round_arm(arm_px / std::sqrt(2.0)));
    for (const auto& d : dirs) {
      const bool diagonal = d[0] != 0 && d[1] != 0;
      const int r = diagonal ? r_diagonal : r_axis;
      // The far arm's mean only when the near one is usable (the means do not depend on
      // the order they are computed in).
      const double ia = inv_depth(x - d[0] * r, y - d[1] * r);
      if (ia <= 0) continue;
      const double ib = inv_depth(x + d[0] * r, y + d[1] * r);
      if (ib <= 0) continue;
      // A surface seen edge-on (depth changing several times faster than the image
      // position) is too noisy for the test; steps that steep exceed the tolerance.
      const double span_m = 2 * r * (diagonal ? diagonal_length : 1.0) * z / fx;
      if (std::abs(1.0 / ia - 1.0 / ib) > params.max_chord_slope * span_m) continue;
      if (z - 2.0 / (ia + ib) > threshold) {
        crease[k] = 1;
        break;
      }
    }
  }

  // The level cut (level_crease_cut), its margin the arm at the cluster's nearest (the
  // crease fades within about an arm of the silhouette).
  std::vector<double> height;
  std::optional<LevelCut> level;
  if (support && params.level_cut &&
      std::count(crease.begin(), crease.end(), 1) >= kLevelMinCreasePixels) {
    height = heights_over(f, grid_pixels, *support);
    float nearest = std::numeric_limits<float>::infinity();
    for (int i : grid_pixels) nearest = std::min(nearest, f.points[static_cast<size_t>(i)].z);
    const int margin = 1 + static_cast<int>(std::ceil(
                               std::max(params.min_arm_px, params.arm_m * fx / nearest) / step));
    level = level_crease_cut(f, grid_pixels, height, crease, step, margin, params);
  }

  // Grid neighbours within the 3D tolerance: the 8 neighbours, as the scanner's
  // clustering joins them (its +-1 grid window), found once and kept per pixel in a
  // fixed order (left, right, up, down, then the diagonals; -1 where none joins): the
  // region passes below walk them up to four times. Each pair is tested once, from the
  // pixel whose neighbour lies right or below (the squared distance is symmetric).
  const double tol2 = tolerance_m * tolerance_m;
  constexpr int kOffsets[8][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}, {-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
  constexpr int kForward[4] = {1, 3, 6, 7};  // (1, 0), (0, 1), (-1, 1), (1, 1)
  constexpr int kOpposite[8] = {1, 0, 3, 2, 7, 6, 5, 4};
  std::vector<std::array<int, 8>> adjacent(static_cast<size_t>(n));
  for (auto& a : adjacent) a.fill(-1);
  // Grid pixels lie on multiples of step, so a neighbour one step away is the next cell
  // of the box (outside it, or off the image, no cell of the cluster).
  for (int k = 0; k < n; ++k) {
    const int i = grid_pixels[k], x = i % f.width, y = i / f.width;
    const int gx = (g.shift >= 0 ? x >> g.shift : x / step) - g.gx0;
    const int gy = (g.shift >= 0 ? y >> g.shift : y / step) - g.gy0;
    const PointXYZRGB& p = f.points[i];
    for (int d : kForward) {
      const int m = g.local(gx + kOffsets[d][0], gy + kOffsets[d][1]);
      if (m < 0) continue;
      const PointXYZRGB& o = f.points[grid_pixels[m]];
      const double dx = p.x - o.x, dy = p.y - o.y, dz = p.z - o.z;
      if (dx * dx + dy * dy + dz * dz > tol2) continue;
      if (level &&
          level->parts(height[static_cast<size_t>(k)], height[static_cast<size_t>(m)], gx + g.gx0))
        continue;
      adjacent[static_cast<size_t>(k)][d] = m;
      adjacent[static_cast<size_t>(m)][kOpposite[d]] = k;
    }
  }
  auto neighbours = [&](int k, auto&& visit) {
    for (int m : adjacent[static_cast<size_t>(k)])
      if (m >= 0) visit(m);
  };

  // Regions over non-crease pixels.
  std::vector<int> region(n, -1);
  int regions = 0;
  std::vector<int> queue;
  for (int s = 0; s < n; ++s) {
    if (crease[s] || region[s] >= 0) continue;
    queue.assign(1, s);
    region[s] = regions;
    for (size_t q = 0; q < queue.size(); ++q)
      neighbours(queue[q], [&](int m) {
        if (crease[m] || region[m] >= 0) return;
        region[m] = regions;
        queue.push_back(m);
      });
    ++regions;
  }
  // Crease pixels join the region that reaches them first (breadth first from every
  // region at once); crease pixels no region reaches form regions of their own.
  // (Without crease pixels every pixel has its region already.)
  queue.clear();
  const bool unassigned = std::any_of(region.begin(), region.end(), [](int r) { return r < 0; });
  for (int k = 0; k < n && unassigned; ++k)
    if (region[k] >= 0) queue.push_back(k);
  for (size_t q = 0; q < queue.size(); ++q)
    neighbours(queue[q], [&](int m) {
      if (region[m] >= 0) return;
      region[m] = region[queue[q]];
      queue.push_back(m);
    });
  for (int s = 0; s < n; ++s) {
    if (region[s] >= 0) continue;
    queue.assign(1, s);
    region[s] = regions;
    for (size_t q = 0; q < queue.size(); ++q)
      neighbours(queue[q], [&](int m) {
        if (region[m] >= 0) return;
        region[m] = regions;
        queue.push_back(m);
      });
    ++regions;
  }
  if (regions <= 1) return {grid_pixels};

  // Border lengths between regions, then small regions join their longest-bordering
  // neighbour, smallest first.
  std::vector<int> size(regions, 0);
  for (int k = 0; k < n; ++k) ++size[region[k]];
  std::map<std::pair<int, int>, int> border;
  for (int k = 0; k < n; ++k)
    neighbours(k, [&](int m) {
      if (region[m] != region[k]) ++border[{region[k], region[m]}];
    });
  const double min_grid =
      std::max(static_cast<double>(params.min_object_points),
               params.min_object_share * n * step * step) /
      (step * step);
  // A region standing on the level cut (most of its pixels above it, in its columns) is
  // an object once it holds as many points as one standing alone would
  // (level_min_part_points at 1 m, falling with the square of its depth): the cut
  // found what it stands on.
  std::vector<int> above(regions, 0);
  std::vector<double> depth_sum(regions, 0);
  if (level)
    for (int k = 0; k < n; ++k) {
      const int i = grid_pixels[k];
      above[region[k]] += level->above(height[static_cast<size_t>(k)], (i % f.width) / step);
      depth_sum[region[k]] += f.points[static_cast<size_t>(i)].z;
    }
  const auto stands_on_cut = [&](int root) {
    if (2 * above[root] <= size[root]) return false;
    const double z = depth_sum[root] / size[root];
    return size[root] * step * step >= params.level_min_part_points / std::max(1.0, z * z);
  };
  std::vector<int> parent(regions);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<int> order(regions);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return size[a] < size[b]; });
  for (int r : order) {
    const int root = find_root(parent, r);
    if (size[root] >= min_grid || stands_on_cut(root)) continue;
    std::map<int, int> touching;
    for (const auto& [pair, count] : border)
      if (find_root(parent, pair.first) == root) {
        const int other = find_root(parent, pair.second);
        if (other != root) touching[other] += count;
      }
    // A small region that borders no other is parted from the rest by missing depth
    // alone (no crease, no depth step between: the scanner joined it across a dark
    // surface's dropout, dropout_join.h); it joins the region nearest in the image.
    const int into = touching.empty()
                         ? nearest_region(grid_pixels, region, parent, root, f.width)
                         : std::max_element(touching.begin(), touching.end(), [](const auto& a, const auto& b) {
                             return a.second < b.second;
                           })->first;
    if (into < 0) continue;
    parent[root] = into;
    size[into] += size[root];
    above[into] += above[root];
    depth_sum[into] += depth_sum[root];
  }
  std::map<int, std::vector<int>> groups;
  for (int k = 0; k < n; ++k) groups[find_root(parent, region[k])].push_back(grid_pixels[k]);
  std::vector<std::vector<int>> out;
  for (auto& [root, pixels] : groups) out.push_back(std::move(pixels));
  return out;
}

}  // namespace annex
