// Fragments of a dark surface parted by missing depth, joined (dropout_join.h).
#include "dropout_join.h"

#include <algorithm>
#include <cmath>
#include <numeric>

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

std::vector<std::vector<int>> join_dropout_fragments(
    const Frame& f, const std::vector<char>& mask, std::vector<std::vector<int>> grids, int step,
    const std::function<double(double)>& tolerance,
    const std::function<int(const std::vector<int>&)>& floor, const DropoutJoinParams& params) {
  const int cell = std::max(params.max_gap_px, 1);
  std::vector<int> small;
  for (size_t g = 0; g < grids.size(); ++g)
    if (!grids[g].empty() && static_cast<int>(grids[g].size()) * step * step < floor(grids[g]) / 2)
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
  const double fx = CameraIntrinsics{}.fx;
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
