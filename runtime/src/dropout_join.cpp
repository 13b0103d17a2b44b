// Fragments of a dark surface parted by missing depth, joined (dropout_join.h).
#include "dropout_join.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

#include "annex/runtime/frame.h"

namespace annex {
namespace {

int find_root(std::vector<int>& parent, int a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}

// Whether the pixels strictly between a and b (image positions) are missing depth or
// lie on the straight line between the two points within tol (the same surface seen
// between them), with at least one missing: the gap is dropout, not another surface.
bool gap_is_dropout(const Frame& f, int a, int b, double tol) {
  const int ax = a % f.width, ay = a / f.width, bx = b % f.width, by = b / f.width;
  const int n = std::max(std::abs(bx - ax), std::abs(by - ay));
  const PointXYZRGB& pa = f.points[static_cast<size_t>(a)];
  const PointXYZRGB& pb = f.points[static_cast<size_t>(b)];
  int missing = 0;
  for (int k = 1; k < n; ++k) {
    const double t = static_cast<double>(k) / n;
    const int x = static_cast<int>(std::lround(ax + t * (bx - ax)));
    const int y = static_cast<int>(std::lround(ay + t * (by - ay)));
    const PointXYZRGB& q = f.points[static_cast<size_t>(y) * f.width + x];
    if (!has_depth(q)) {
      ++missing;
      continue;
    }
    if (std::abs(q.z - (pa.z + t * (pb.z - pa.z))) > tol) return false;
  }
  return missing > 0;
}

}  // namespace

int silhouette_pixels(const Frame& f, const std::vector<int>& pixels, int max_gap_px) {
  if (pixels.empty() || f.width <= 0) return 0;
  int x0 = f.width, x1 = -1, y0 = f.height, y1 = -1;
  for (int i : pixels) {
    x0 = std::min(x0, i % f.width), x1 = std::max(x1, i % f.width);
    y0 = std::min(y0, i / f.width), y1 = std::max(y1, i / f.width);
  }
  const int w = x1 - x0 + 1, h = y1 - y0 + 1;
  // 1: one of `pixels`; bit 2: enclosed along its row; bit 4: along its column.
  std::vector<unsigned char> at(static_cast<size_t>(w) * h, 0);
  for (int i : pixels) at[static_cast<size_t>(i / f.width - y0) * w + (i % f.width - x0)] = 1;
  const auto missing = [&](int x, int y) {
    return !has_depth(f.points[static_cast<size_t>(y + y0) * f.width + x + x0]);
  };
  // Marks each run of missing pixels between two of `pixels` along a line of n cells,
  // cell(k) giving the k-th cell's index in `at` and (x, y).
  const auto enclose = [&](int n, auto cell, unsigned char bit) {
    int last = -1;
    for (int k = 0; k < n; ++k) {
      const auto [idx, x, y] = cell(k);
      if (at[idx] & 1) {
        if (last >= 0 && k - last - 1 <= max_gap_px)
          for (int m = last + 1; m < k; ++m) at[std::get<0>(cell(m))] |= bit;
        last = k;
      } else if (!missing(x, y)) {
        last = -1;  // depth of something else: the run is not this object's dropout
      }
    }
  };
  for (int y = 0; y < h; ++y)
    enclose(w, [&](int k) { return std::tuple<size_t, int, int>{static_cast<size_t>(y) * w + k, k, y}; }, 2);
  for (int x = 0; x < w; ++x)
    enclose(h, [&](int k) { return std::tuple<size_t, int, int>{static_cast<size_t>(k) * w + x, x, k}; }, 4);
  int n = 0;
  for (unsigned char c : at) n += (c & 1) || (c & 6) == 6;
  return n;
}

std::vector<int> dropout_block_pixels(const Frame& f, const std::vector<int>& grid, int step,
                                      const std::function<bool(int, int)>& accept) {
  std::vector<int> out;
  if (step <= 1 || f.width <= 0) return out;
  // The blocks beside the grid whose grid pixel has no depth, each with the grid pixel
  // beside it that is looked at first (the least index), once.
  std::vector<std::pair<int, int>> blocks;
  for (int i : grid) {
    const int x = i % f.width, y = i / f.width;
    for (int dy = -step; dy <= step; dy += step)
      for (int dx = -step; dx <= step; dx += step) {
        const int bx = x + dx, by = y + dy;
        if ((dx == 0 && dy == 0) || bx < 0 || by < 0 || bx >= f.width || by >= f.height) continue;
        const int b = by * f.width + bx;
        if (!has_depth(f.points[static_cast<size_t>(b)])) blocks.emplace_back(b, i);
      }
  }
  std::sort(blocks.begin(), blocks.end());
  for (size_t k = 0; k < blocks.size(); ++k) {
    if (k > 0 && blocks[k].first == blocks[k - 1].first) continue;
    const auto [b, i] = blocks[k];
    const int bx = b % f.width, by = b / f.width;
    for (int ey = 0; ey < step && by + ey < f.height; ++ey)
      for (int ex = 0; ex < step && bx + ex < f.width; ++ex) {
        const int j = b + ey * f.width + ex;
        if (has_depth(f.points[static_cast<size_t>(j)]) && accept(j, i)) out.push_back(j);
      }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::vector<int>> join_dropout_fragments(
    const Frame& f, const std::vector<char>& mask, std::vector<std::vector<int>> grids, int step,
    const std::function<double(double)>& tolerance,
    const std::function<int(const std::vector<int>&)>& floor, const DropoutJoinParams& params) {
  const int cell = std::max(params.max_gap_px, 1);
  // Every fragment under the floor, not only those under the coarse half the scanner
  // drops at once: a grid pixel stands for step^2 pixels, but on a dark surface few of
  // them return, so a fragment of half the floor or more still falls under it later
  // (a dark torus 2.1 m away in four such fragments was missed).
  const int share = params.to_floor ? 1 : 2;
  std::vector<int> small;
  for (size_t g = 0; g < grids.size(); ++g)
    if (!grids[g].empty() &&
        static_cast<int>(grids[g].size()) * step * step < floor(grids[g]) / share)
      small.push_back(static_cast<int>(g));
  if (small.size() < 2 || f.width <= 0) return grids;
  // The small fragments' pixels in image cells as wide as the widest gap.
  const int cw = (f.width + cell - 1) / cell, ch = (f.height + cell - 1) / cell;
  std::vector<std::vector<std::pair<int, int>>> cells(static_cast<size_t>(cw) * ch);
  for (size_t s = 0; s < small.size(); ++s)
    for (int i : grids[static_cast<size_t>(small[s])])
      cells[static_cast<size_t>((i / f.width) / cell) * cw + (i % f.width) / cell].push_back({i, static_cast<int>(s)});
  std::vector<int> parent(small.size());
  std::iota(parent.begin(), parent.end(), 0);
  const double fx = focal_px(f);
  for (size_t c = 0; c < cells.size(); ++c) {
    const int cx = static_cast<int>(c) % cw, cy = static_cast<int>(c) / cw;
    for (const auto& [i, s] : cells[c]) {
      const int x = i % f.width, y = i / f.width;
      const PointXYZRGB& p = f.points[static_cast<size_t>(i)];
      for (int ny = std::max(0, cy - 1); ny <= std::min(ch - 1, cy + 1); ++ny)
        for (int nx = std::max(0, cx - 1); nx <= std::min(cw - 1, cx + 1); ++nx)
          for (const auto& [j, t] : cells[static_cast<size_t>(ny) * cw + nx]) {
            if (t <= s || mask[static_cast<size_t>(i)] != mask[static_cast<size_t>(j)]) continue;
            if (find_root(parent, s) == find_root(parent, t)) continue;
            const int gap = std::max(std::abs(j % f.width - x), std::abs(j / f.width - y));
            if (gap > params.max_gap_px) continue;
            // As close as one surface across the gap: within the clustering tolerance
            // plus the gap's width at that depth, in depth as across. A weak return
            // leaves the faces turned to the camera (the return falls with the
            // incidence's cosine); a face seen obliquely, whose depth runs away faster
            // than the image position, drops out by its angle, and its pieces are the
            // sides of furniture, not a dark object's.
            const PointXYZRGB& q = f.points[static_cast<size_t>(j)];
            const double tol = tolerance(p.z), span = gap * p.z / fx;
            const double dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
            if (std::abs(dz) > tol + span || dx * dx + dy * dy > (tol + span) * (tol + span) ||
                !gap_is_dropout(f, i, j, tol))
              continue;
            parent[static_cast<size_t>(find_root(parent, t))] = find_root(parent, s);
          }
    }
  }
  // Groups of two or more that reach the floor together replace their fragments.
  std::vector<std::vector<int>> members(small.size());
  for (size_t s = 0; s < small.size(); ++s) members[static_cast<size_t>(find_root(parent, static_cast<int>(s)))].push_back(static_cast<int>(s));
  std::vector<char> removed(grids.size(), 0);
  for (const std::vector<int>& group : members) {
    if (group.size() < 2) continue;
    std::vector<int> joined;
    for (int s : group) {
      const std::vector<int>& g = grids[static_cast<size_t>(small[static_cast<size_t>(s)])];
      joined.insert(joined.end(), g.begin(), g.end());
    }
    if (static_cast<int>(joined.size()) * step * step < floor(joined) / 2) continue;
    grids[static_cast<size_t>(small[static_cast<size_t>(group[0])])] = std::move(joined);
    for (size_t k = 1; k < group.size(); ++k) removed[static_cast<size_t>(small[static_cast<size_t>(group[k])])] = 1;
  }
  std::vector<std::vector<int>> out;
  out.reserve(grids.size());
  for (size_t g = 0; g < grids.size(); ++g)
    if (!removed[g]) out.push_back(std::move(grids[g]));
  return out;
}

}  // namespace annex
