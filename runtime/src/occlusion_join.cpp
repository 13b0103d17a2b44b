// Joining the pieces of an occluded object (occlusion_join.h).
#include "occlusion_join.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace annex {

OccludedPiece describe_piece(const Frame& f, const ScanCluster& c) {
  OccludedPiece p;
  std::vector<float> z;
  z.reserve(c.pixels.size());
  // A pixel's row by one division only when it leaves the last one's row (the pixels
  // are in raster order, so once per row): the same columns and rows, summed in order.
  int row = 0, row_start = -2 * f.width;
  for (int i : c.pixels) {
    if (i < row_start || i >= row_start + f.width) row = i / f.width, row_start = row * f.width;
    p.u += i - row_start;
    p.v += row;
    z.push_back(f.points[i].z);
  }
  if (c.pixels.empty()) return p;
  p.u /= c.pixels.size();
  p.v /= c.pixels.size();
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  p.z = z[z.size() / 2];
  return p;
}

namespace {

// The support's surface seen around two pieces of one object on it: each point once (the
// pieces stand near each other, so their surroundings overlap), and the object's pixels
// both pieces' (the foot's seen share is a share of the whole object).
SupportAround joint_around(const SupportAround& a, const SupportAround& b) {
  SupportAround out = a;
  out.points.insert(out.points.end(), b.points.begin(), b.points.end());
  const auto before = [](const Vec3& p, const Vec3& q) {
    return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
  };
  std::sort(out.points.begin(), out.points.end(), before);
  out.points.erase(std::unique(out.points.begin(), out.points.end()), out.points.end());
  out.object_pixels = a.object_pixels + b.object_pixels;
  return out;
}

// Each image column's lowest pixel of a cluster.
std::vector<int> lowest_per_column(const Frame& f, const ScanCluster& c) {
  std::map<int, int> lowest;  // column -> the lowest pixel there
  for (int i : c.pixels) {
    int& l = lowest.try_emplace(i % f.width, i).first->second;
    l = std::max(l, i);
  }
  std::vector<int> out;
  out.reserve(lowest.size());
  for (const auto& [col, i] : lowest) out.push_back(i);
  return out;
}

// The cluster `b` (by label) lies right under the cluster whose lowest pixel per column
// is `lowest`, standing on `plane`: in more than half of those columns (three at least)
// the first pixel below with depth and out of the plane's band (`band`: no cluster's
// pixels, some rows tall a metre away) is b's, within the tolerance plus the band's
// height of it in depth.
bool right_under(const Frame& f, const std::vector<int>& lowest, int b,
                 const std::vector<int>& label, int step, const Plane& plane,
                 const std::function<double(double z)>& tolerance,
                 const std::function<double(double z)>& band) {
  const int count = static_cast<int>(f.points.size());
  const double fy = grid_intrinsics(f).fy;
  int under = 0;
  for (int i : lowest) {
    const double z = f.points[static_cast<size_t>(i)].z, band_m = band(z);
    // Grid rows down: the band's two sides seen face-on, and three more.
    const int rows = 3 + static_cast<int>(std::ceil(2 * band_m * fy / std::max(z, 0.1) / step));
    for (int r = 1; r <= rows; ++r) {
      const int j = i + r * step * f.width;
      if (j >= count) break;
      const PointXYZRGB& q = f.points[static_cast<size_t>(j)];
      if (!(q.z > 0)) continue;  // a dropout: look one row on
      if (std::abs(dot(plane.normal, Vec3{q.x, q.y, q.z}) + plane.d) < band_m) continue;
      under += label[static_cast<size_t>(j)] == b && std::abs(q.z - z) <= tolerance(z) + 2 * band_m;
      break;
    }
  }
  return lowest.size() >= 3 && 2 * static_cast<size_t>(under) > lowest.size();
}

// Drops the clusters marked `gone` and renumbers `label` (and `joined`) to match.
void drop_gone(std::vector<ScanCluster>& clusters, std::vector<int>& label,
               const std::vector<char>& gone, std::vector<char>* joined) {
  const size_t n = clusters.size();
  std::vector<ScanCluster> kept;
  std::vector<char> kept_joined;
  std::vector<int> new_id(n, -1);
  for (size_t k = 0; k < n; ++k)
    if (!gone[k]) {
      new_id[k] = static_cast<int>(kept.size());
      kept.push_back(std::move(clusters[k]));
      if (joined) kept_joined.push_back((*joined)[k]);
    }
  // Nothing joined: every index is its own.
  if (kept.size() < n)
    for (int& l : label)
      if (l >= 0) l = new_id[static_cast<size_t>(l)];
  clusters = std::move(kept);
  if (joined) *joined = std::move(kept_joined);
}

}  // namespace

void join_occluded_pieces(const Frame& f, std::vector<ScanCluster>& clusters,
                          std::vector<int>& label, std::vector<OccludedPiece> pieces,
                          const std::function<void(ScanCluster&, int)>& refit,
                          double min_coverage, const OcclusionJoinParams& params) {
  const size_t n = clusters.size();
  if (n < 3 || !f.organized()) return;
  std::vector<char> gone(n, 0);
  for (size_t a = 0; a < n; ++a) {
    for (size_t b = a + 1; b < n; ++b) {
      if (gone[a] || gone[b]) continue;
      const ScanCluster& A = clusters[a];
      const ScanCluster& B = clusters[b];
      if (A.shape.primitives.empty() || B.shape.primitives.empty()) continue;
      if (A.shape.primitives[0].primitive.kind != B.shape.primitives[0].primitive.kind) continue;
      // Pieces of one object stand on one support: a box on the table in front of a
      // shelf is no piece of the shelf's side behind it (fresh rooms 9929).
      if (!(A.support == B.support)) continue;
      // Along the image segment between the pieces' centres, every pixel that is
      // neither piece must be nearer than both (the occluder), have no depth (the
      // occluder's shadow on the structured light) or be a pixel of no object, above
      // the table and not behind the pieces (the hidden object's own edge and crease
      // pixels, which no cluster kept); a pixel of the table or of a farther object
      // shows the gap, and they are two objects.
      const double du = pieces[b].u - pieces[a].u, dv = pieces[b].v - pieces[a].v;
      const int steps = std::max(2, static_cast<int>(std::hypot(du, dv)));
      const double far_z = std::min(pieces[a].z, pieces[b].z) - params.min_occluder_gap_m;
      const double back_z = std::max(pieces[a].z, pieces[b].z) + params.min_occluder_gap_m;
      const Vec3 up = normalized(A.support.normal);
      const double up_d = A.support.d / norm(A.support.normal);
      bool covered = true, occluder = false;
      int unclaimed = 0;
      for (int s = 1; s < steps && covered; ++s) {
        const int u = static_cast<int>(std::lround(pieces[a].u + du * s / steps));
        const int v = static_cast<int>(std::lround(pieces[a].v + dv * s / steps));
        const size_t i = static_cast<size_t>(v) * f.width + u;
        const int l = label[i];
        if (l == static_cast<int>(a) || l == static_cast<int>(b)) continue;
        const PointXYZRGB& q = f.points[i];
        if (!std::isfinite(q.z) || q.z <= 0) continue;  // no depth: the occluder's shadow
        if (q.z < far_z) {
          occluder = true;
          continue;
        }
        const double h = dot(up, Vec3{q.x, q.y, q.z}) + up_d;
        if (l < 0 && q.z < back_z && h > params.support_band_m) {
          ++unclaimed;
          continue;
        }
        covered = false;
      }
      // Edge pixels are a few along the segment; a long run of pixels of no object is
      // something the scan dropped (a wall, a cupboard), not the hidden object's rim.
      covered = covered && unclaimed <= params.max_unclaimed_share * steps;
      if (!covered || !occluder) continue;
      // One primitive of the same kind must explain both pieces together.
      ScanCluster joint;
      joint.support = A.support;
      joint.around = joint_around(A.around, B.around);
      joint.pixels = A.pixels;
      joint.pixels.insert(joint.pixels.end(), B.pixels.begin(), B.pixels.end());
      std::sort(joint.pixels.begin(), joint.pixels.end());
      for (int i : B.pixels) label[i] = static_cast<int>(a);
      refit(joint, static_cast<int>(a));
      const double worse = std::min(A.shape.fit, B.shape.fit);
      const bool same = !joint.shape.primitives.empty() &&
                        joint.shape.primitives[0].primitive.kind == A.shape.primitives[0].primitive.kind;
      if (same && joint.shape.fit >= min_coverage && joint.shape.fit >= worse - params.coverage_slack) {
        clusters[a] = std::move(joint);
        pieces[a] = describe_piece(f, clusters[a]);
        gone[b] = 1;
      } else {
        for (int i : B.pixels) label[i] = static_cast<int>(b);
      }
    }
  }
  drop_gone(clusters, label, gone, nullptr);
}

void join_across_support_plane(const Frame& f, std::vector<ScanCluster>& clusters,
                               std::vector<int>& label, int step,
                               const std::function<double(double z)>& tolerance,
                               const std::function<double(double z)>& band,
                               const std::function<void(ScanCluster&, int)>& refit,
                               double min_coverage, std::vector<char>& joined,
                               const OcclusionJoinParams& params) {
  const size_t n = clusters.size();
  joined.assign(n, 0);
  if (n < 2 || !f.organized()) return;
  std::vector<char> gone(n, 0);
  for (size_t a = 0; a < n; ++a) {
    if (gone[a] || clusters[a].shape.primitives.empty()) continue;
    std::vector<int> lowest;  // a's, found once a pair asks
    for (size_t b = 0; b < n; ++b) {
      if (b == a || gone[b] || gone[a]) continue;
      const ScanCluster& A = clusters[a];
      const ScanCluster& B = clusters[b];
      if (B.shape.primitives.empty() ||
          A.shape.primitives[0].primitive.kind != B.shape.primitives[0].primitive.kind)
        continue;
      // A on a raised support (the camera stands less high above it), B on a lower one.
      if (!(A.support.d < B.support.d) || A.support == B.support) continue;
      if (lowest.empty()) lowest = lowest_per_column(f, A);
      if (!right_under(f, lowest, static_cast<int>(b), label, step, A.support, tolerance, band))
        continue;
      ScanCluster joint;
      joint.support = B.support;
      joint.around = B.around;
      joint.pixels = A.pixels;
      joint.pixels.insert(joint.pixels.end(), B.pixels.begin(), B.pixels.end());
      std::sort(joint.pixels.begin(), joint.pixels.end());
      for (int i : A.pixels) label[static_cast<size_t>(i)] = static_cast<int>(b);
      refit(joint, static_cast<int>(b));
      const double worse = std::min(A.shape.fit, B.shape.fit);
      const bool same =
          !joint.shape.primitives.empty() &&
          joint.shape.primitives[0].primitive.kind == B.shape.primitives[0].primitive.kind;
      if (same && joint.shape.fit >= min_coverage &&
          joint.shape.fit >= worse - params.coverage_slack) {
        clusters[b] = std::move(joint);
        joined[b] = 1;
        gone[a] = 1;
      } else {
        for (int i : A.pixels) label[static_cast<size_t>(i)] = static_cast<int>(a);
      }
    }
  }
  drop_gone(clusters, label, gone, &joined);
}

}  // namespace annex
