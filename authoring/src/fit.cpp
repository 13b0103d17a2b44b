#include "annex/authoring/fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace annex::authoring {

Eigen3 symmetric_eigen(const double m[3][3]) {
  double a[3][3], v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a[i][j] = m[i][j];
  // Cyclic Jacobi: a 3x3 converges to double precision in a handful of sweeps.
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if (off < 1e-30) break;
    for (int p = 0; p < 2; ++p) {
      for (int q = p + 1; q < 3; ++q) {
        if (std::abs(a[p][q]) < 1e-300) continue;
        const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const double t =
            (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; ++k) {  // A <- A J
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // A <- J^T A
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
    }
  }
  int idx[3] = {0, 1, 2};
  std::sort(idx, idx + 3, [&](int x, int y) { return a[x][x] > a[y][y]; });
  Eigen3 e{};
  for (int k = 0; k < 3; ++k) {
    e.values[k] = a[idx[k]][idx[k]];
    e.vectors[k] = normalized(Vec3{v[0][idx[k]], v[1][idx[k]], v[2][idx[k]]});
  }
  return e;
}

Quat quat_from_frame(Vec3 x, Vec3 y, Vec3 z) { return rotation_from_axes(x, y, z); }

namespace {

// Flips a direction so its largest component is positive: fits are deterministic.
Vec3 canonical_sign(Vec3 v) {
  const double ax = std::abs(v.x), ay = std::abs(v.y), az = std::abs(v.z);
  const double big = ax >= ay && ax >= az ? v.x : (ay >= az ? v.y : v.z);
  return big < 0 ? v * -1.0 : v;
}

struct Frame {
  Vec3 centroid;
  Eigen3 eig;
  double lo[3], hi[3];
};

Frame principal_frame(std::span<const Vec3> pts) {
  Frame f{};
  for (const Vec3& p : pts) f.centroid = f.centroid + p;
  f.centroid = f.centroid * (1.0 / static_cast<double>(pts.size()));
  double c[3][3] = {};
  for (const Vec3& p : pts) {
    const Vec3 d = p - f.centroid;
    const double dv[3] = {d.x, d.y, d.z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) c[i][j] += dv[i] * dv[j];
  }
  f.eig = symmetric_eigen(c);
  for (int k = 0; k < 2; ++k) f.eig.vectors[k] = canonical_sign(f.eig.vectors[k]);
  f.eig.vectors[2] = cross(f.eig.vectors[0], f.eig.vectors[1]);
  for (int k = 0; k < 3; ++k) {
    f.lo[k] = std::numeric_limits<double>::infinity();
    f.hi[k] = -f.lo[k];
  }
  for (const Vec3& p : pts)
    for (int k = 0; k < 3; ++k) {
      const double t = dot(p - f.centroid, f.eig.vectors[k]);
      f.lo[k] = std::min(f.lo[k], t);
      f.hi[k] = std::max(f.hi[k], t);
    }
  return f;
}

Vec3 box_center(const Frame& f) {
  Vec3 c = f.centroid;
  for (int k = 0; k < 3; ++k) c = c + f.eig.vectors[k] * (0.5 * (f.lo[k] + f.hi[k]));
  return c;
}

double radial(Vec3 p, Vec3 origin, Vec3 axis) {
  const Vec3 d = p - origin;
  return norm(d - axis * dot(d, axis));
}

// Solves the n x n system a x = b (n <= 4) by Gaussian elimination with partial
// pivoting; false when it is singular at the data's scale.
template <int N>
bool solve_linear(double a[N][N], double b[N], double x[N]) {
  double scale = 0;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) scale = std::max(scale, std::abs(a[i][j]));
  if (!(scale > 0)) return false;
  for (int c = 0; c < N; ++c) {
    int piv = c;
    for (int r = c + 1; r < N; ++r)
      if (std::abs(a[r][c]) > std::abs(a[piv][c])) piv = r;
    if (!(std::abs(a[piv][c]) > 1e-12 * scale)) return false;
    for (int j = 0; j < N; ++j) std::swap(a[c][j], a[piv][j]);
    std::swap(b[c], b[piv]);
    for (int r = c + 1; r < N; ++r) {
      const double f = a[r][c] / a[c][c];
      for (int j = c; j < N; ++j) a[r][j] -= f * a[c][j];
      b[r] -= f * b[c];
    }
  }
  for (int r = N - 1; r >= 0; --r) {
    double v = b[r];
    for (int j = r + 1; j < N; ++j) v -= a[r][j] * x[j];
    x[r] = v / a[r][r];
  }
  return true;
}

// The least-squares circle (Kasa) through the points projected onto the plane across
// `axis` through `origin`: its centre in that plane. Unlike a bounding box's centre it
// is right for part of a circle (a C-shaped handle, the visible half of a bottle).
// `taper`: the radius may change linearly along the axis (a cone, a bottle's neck), so
// points at different heights are not forced onto one circle.
std::optional<Vec3> circle_center(std::span<const Vec3> pts, Vec3 origin, Vec3 axis,
                                  bool taper = false) {
  const Vec3 e0 = normalized(std::abs(axis.x) < 0.9 ? cross(axis, Vec3{1, 0, 0})
                                                    : cross(axis, Vec3{0, 1, 0}));
  const Vec3 e1 = cross(axis, e0);
  // Normal equations of  u^2 + v^2 + D u + E v + F = 0  in the unknowns (D, E, F).
  double m[3][3] = {}, rhs[3] = {}, sol[3];
  for (const Vec3& p : pts) {
    const Vec3 d = p - origin;
    const double u = dot(d, e0), v = dot(d, e1), w = -(u * u + v * v);
    const double row[3] = {u, v, 1};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) m[i][j] += row[i] * row[j];
      rhs[i] += row[i] * w;
    }
  }
  if (!solve_linear<3>(m, rhs, sol)) return std::nullopt;
  double cu = -0.5 * sol[0], cv = -0.5 * sol[1];
  // The algebraic circle leans towards the outer side of a partial ring of tube points;
  // Gauss-Newton on the geometric distances | |q - c| - R | removes the bias.
  double r = 0;
  for (const Vec3& p : pts) {
    const Vec3 d = p - origin;
    r += std::hypot(dot(d, e0) - cu, dot(d, e1) - cv);
  }
  r /= static_cast<double>(pts.size());
  double k = 0;  // radius change per metre along the axis
  for (int it = 0; it < 30; ++it) {
    double jtj[4][4] = {}, jtr[4] = {}, step[4] = {};
    for (const Vec3& p : pts) {
      const Vec3 d = p - origin;
      const double du = dot(d, e0) - cu, dv = dot(d, e1) - cv, len = std::hypot(du, dv);
      if (len < 1e-12) continue;
      const double h = dot(d, axis);
      const double j[4] = {-du / len, -dv / len, -1, -h}, res = len - (r + k * h);
      for (int a = 0; a < 4; ++a) {
        for (int b = 0; b < 4; ++b) jtj[a][b] += j[a] * j[b];
        jtr[a] -= j[a] * res;
      }
    }
    bool solved = false;
    if (taper) {
      solved = solve_linear<4>(jtj, jtr, step);
    } else {
      double j3[3][3], r3[3];
      for (int a = 0; a < 3; ++a) {
        r3[a] = jtr[a];
        for (int b = 0; b < 3; ++b) j3[a][b] = jtj[a][b];
      }
      solved = solve_linear<3>(j3, r3, step);
    }
    if (!solved) break;
    cu += step[0];
    cv += step[1];
    r += step[2];
    k += step[3];
    if (std::abs(step[0]) + std::abs(step[1]) + std::abs(step[2]) + std::abs(step[3]) < 1e-12)
      break;
  }
  if (!std::isfinite(cu) || !std::isfinite(cv)) return std::nullopt;
  return origin + e0 * cu + e1 * cv;
}

// The least-squares sphere (Kasa) through the points: its centre, right for a cap too.
std::optional<Vec3> sphere_center(std::span<const Vec3> pts, Vec3 origin) {
  double m[4][4] = {}, rhs[4] = {}, sol[4];
  for (const Vec3& p : pts) {
    const Vec3 d = p - origin;
    const double row[4] = {d.x, d.y, d.z, 1}, w = -dot(d, d);
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) m[i][j] += row[i] * row[j];
      rhs[i] += row[i] * w;
    }
  }
  if (!solve_linear<4>(m, rhs, sol)) return std::nullopt;
  return origin + Vec3{-0.5 * sol[0], -0.5 * sol[1], -0.5 * sol[2]};
}

// Whether the points go all the way round `axis` through `center` (every 30-degree
// sector holds some): then the bounding box's centre is exact for a symmetric mesh,
// where a circle fit to a filled disc of vertices (caps, seams) is not.
bool surrounds(std::span<const Vec3> pts, Vec3 center, Vec3 axis) {
  const Vec3 e0 = normalized(std::abs(axis.x) < 0.9 ? cross(axis, Vec3{1, 0, 0})
                                                    : cross(axis, Vec3{0, 1, 0}));
  const Vec3 e1 = cross(axis, e0);
  int count[12] = {};
  for (const Vec3& p : pts) {
    const Vec3 d = p - center;
    const double u = dot(d, e0), v = dot(d, e1);
    if (u == 0 && v == 0) continue;
    const double a = std::atan2(v, u) + 3.14159265358979323846;
    ++count[std::min(11, static_cast<int>(a / (2 * 3.14159265358979323846) * 12))];
  }
  const double need = 0.005 * static_cast<double>(pts.size());
  for (int c : count)
    if (c < need) return false;
  return true;
}

// A torus around a full ring or a C-shaped part of one (a mug handle): the spine
// circle's centre is circle_center's, so a partial arc finds its true centre, not its
// bounding box's. The major radius is the points' mean distance from that centre in
// the plane and the minor radius their mean distance from the spine circle: both exact
// for points spread evenly round the tube. Local +X points at the middle of the arc
// (the handle's grip).
struct RingFit {
  Pose pose;
  double major_m = 0, minor_m = 0;
};

std::optional<RingFit> fit_ring(std::span<const Vec3> pts, Vec3 origin, Vec3 axis) {
  const std::optional<Vec3> c_plane =
      surrounds(pts, origin, axis) ? std::optional<Vec3>(origin) : circle_center(pts, origin, axis);
  if (!c_plane) return std::nullopt;
  double mean_rho = 0, mean_h = 0;
  Vec3 toward_arc{};
  for (const Vec3& p : pts) {
    const Vec3 d = p - *c_plane;
    const double h = dot(d, axis);
    const Vec3 in_plane = d - axis * h;
    mean_rho += norm(in_plane);
    mean_h += h;
    toward_arc = toward_arc + in_plane;
  }
  const double n = static_cast<double>(pts.size());
  mean_rho /= n;
  mean_h /= n;
  double mean_tube = 0;
  for (const Vec3& p : pts) {
    const Vec3 d = p - *c_plane;
    const double h = dot(d, axis) - mean_h;
    const double rho = norm(d - axis * dot(d, axis));
    mean_tube += std::hypot(rho - mean_rho, h);
  }
  mean_tube /= n;
  if (!(mean_rho > mean_tube)) return std::nullopt;  // not a ring: a disc or a blob
  RingFit ring;
  ring.pose.position = *c_plane + axis * mean_h;
  // A full ring's points average to its centre: no arc to point at.
  const Vec3 e0 = normalized(std::abs(axis.x) < 0.9 ? cross(axis, Vec3{1, 0, 0})
                                                    : cross(axis, Vec3{0, 1, 0}));
  const Vec3 x = norm(toward_arc) / n > 0.05 * mean_rho ? normalized(toward_arc) : e0;
  ring.pose.rotation = quat_from_frame(x, cross(axis, x), axis);
  ring.major_m = mean_rho;
  ring.minor_m = mean_tube;
  return ring;
}

// The principal frame with its third axis fixed to `axis` (a snapped fit): the other
// two are the principal directions of the points projected across it.
Frame frame_about(std::span<const Vec3> pts, Vec3 axis) {
  Frame f = principal_frame(pts);
  const Vec3 a = normalized(axis);
  double c[3][3] = {};
  for (const Vec3& p : pts) {
    Vec3 d = p - f.centroid;
    d = d - a * dot(d, a);
    const double dv[3] = {d.x, d.y, d.z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) c[i][j] += dv[i] * dv[j];
  }
  const Eigen3 e = symmetric_eigen(c);
  // The in-plane eigenvectors are the two largest (the third is `a`, eigenvalue 0).
  Vec3 x = e.vectors[0] - a * dot(e.vectors[0], a);
  x = norm(x) > 1e-9 ? canonical_sign(normalized(x)) : normalized(cross(a, Vec3{1, 0, 0}));
  f.eig.vectors[0] = x;
  f.eig.vectors[1] = cross(a, x);
  f.eig.vectors[2] = a;
  for (int k = 0; k < 3; ++k) {
    f.lo[k] = std::numeric_limits<double>::infinity();
    f.hi[k] = -f.lo[k];
    double var = 0;
    for (const Vec3& p : pts) {
      const double t = dot(p - f.centroid, f.eig.vectors[k]);
      f.lo[k] = std::min(f.lo[k], t);
      f.hi[k] = std::max(f.hi[k], t);
      var += t * t;
    }
    f.eig.values[k] = var;
  }
  return f;
}

// The axis of a cylinder or cone from its normals. A side's normals all make the same
// angle with the axis (90 degrees for a cylinder), so n . axis is constant: the axis is
// the direction in which the normals do not vary (the least eigenvector of their
// covariance), exact for any part of the round, where their plain second moment leans
// towards the viewer for the visible side of a cone. Normals of other surfaces (a cap,
// a shoulder) vary there: a second pass keeps the normals whose n . axis is near the
// median. Normals nearly all alike are a flat face, a cap, whose normal is the axis.
std::optional<Vec3> axis_from_normals(std::span<const Vec3> normals) {
  auto least_varying = [](const std::vector<Vec3>& ns, int which) -> std::optional<Vec3> {
    if (ns.size() < 3) return std::nullopt;
    Vec3 mean{};
    for (const Vec3& n : ns) mean = mean + n;
    mean = mean * (1.0 / static_cast<double>(ns.size()));
    double m[3][3] = {}, c[3][3] = {};
    for (const Vec3& n : ns) {
      const double v[3] = {n.x, n.y, n.z}, d[3] = {n.x - mean.x, n.y - mean.y, n.z - mean.z};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          m[i][j] += v[i] * v[j];
          c[i][j] += d[i] * d[j];
        }
    }
    const Eigen3 second = symmetric_eigen(m);
    if (!(second.values[0] > 0)) return std::nullopt;
    // which < 0: decide between a flat face (its normal) and a side.
    if (which < 0 && second.values[1] < 0.15 * second.values[0])
      return canonical_sign(second.vectors[0]);
    return canonical_sign(symmetric_eigen(c).vectors[2]);
  };
  std::vector<Vec3> all(normals.begin(), normals.end());
  const std::optional<Vec3> first = least_varying(all, -1);
  if (!first) return std::nullopt;
  std::vector<double> along;
  for (const Vec3& n : all) along.push_back(dot(n, *first));
  std::vector<double> sorted = along;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                   sorted.end());
  const double median = sorted[sorted.size() / 2];
  if (median > 0.95 || median < -0.95) return first;  // a flat face
  std::vector<Vec3> side;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (std::abs(along[i] - median) < 0.25) side.push_back(all[i]);
  const std::optional<Vec3> refined = least_varying(side, 0);
  return refined ? refined : first;
}

// A surface of revolution's normal lines all meet its axis (a bottle's curved neck as
// much as a cylinder or a cone): the axis is the line (direction a through c) that
// minimises sum ((p - c) . (n x a))^2, relative to sum |n x a|^2 so that directions along
// many normals gain nothing. For each direction c is a 2x2 least-squares solve; the
// direction is searched within 40 degrees of `start` (2-degree steps, then 0.2).
std::optional<Vec3> revolution_axis(std::span<const Vec3> points, std::span<const Vec3> normals,
                                    Vec3 start) {
  const std::size_t stride = std::max<std::size_t>(1, points.size() / 3000);
  Vec3 centroid{};
  std::size_t n = 0;
  for (std::size_t i = 0; i < points.size(); i += stride, ++n) centroid = centroid + points[i];
  if (n < 10) return std::nullopt;
  centroid = centroid * (1.0 / static_cast<double>(n));
  auto cost = [&](Vec3 a) {
    const Vec3 e0 = normalized(std::abs(a.x) < 0.9 ? cross(a, Vec3{1, 0, 0}) : cross(a, Vec3{0, 1, 0}));
    const Vec3 e1 = cross(a, e0);
    double s00 = 0, s01 = 0, s11 = 0, b0 = 0, b1 = 0, bb = 0, mm = 0;
    for (std::size_t i = 0; i < points.size(); i += stride) {
      const Vec3 m = cross(normals[i], a);
      const double r = dot(points[i] - centroid, m), g0 = dot(e0, m), g1 = dot(e1, m);
      s00 += g0 * g0;
      s01 += g0 * g1;
      s11 += g1 * g1;
      b0 += g0 * r;
      b1 += g1 * r;
      bb += r * r;
      mm += dot(m, m);
    }
    const double det = s00 * s11 - s01 * s01;
    if (!(mm > 0) || !(std::abs(det) > 1e-18)) return std::numeric_limits<double>::infinity();
    const double u = (b0 * s11 - b1 * s01) / det, v = (s00 * b1 - s01 * b0) / det;
    // The residual sum of squares at the best c, relative to the normals' leverage.
    return (bb - u * b0 - v * b1) / mm;
  };
  auto search = [&](Vec3 centre, double radius_deg, double step_deg) {
    const Vec3 a0 = normalized(centre);
    const Vec3 e0 =
        normalized(std::abs(a0.x) < 0.9 ? cross(a0, Vec3{1, 0, 0}) : cross(a0, Vec3{0, 1, 0}));
    const Vec3 e1 = cross(a0, e0);
    Vec3 best = a0;
    double best_cost = cost(a0);
    const double to_rad = 3.14159265358979323846 / 180;
    for (double x = -radius_deg; x <= radius_deg + 1e-9; x += step_deg)
      for (double y = -radius_deg; y <= radius_deg + 1e-9; y += step_deg) {
        if (x * x + y * y > radius_deg * radius_deg) continue;
        const Vec3 a = normalized(a0 + e0 * std::tan(x * to_rad) + e1 * std::tan(y * to_rad));
        const double c = cost(a);
        if (c < best_cost) {
          best_cost = c;
          best = a;
        }
      }
    return best;
  };
  Vec3 a = search(start, 40, 2);
  a = search(a, 2.2, 0.2);
  return canonical_sign(a);
}

}  // namespace

Result<FitResult> fit_primitive(std::span<const Vec3> points, ShapeKind kind,
                                const FitOptions& options) {
  if (points.size() < 4)
    return Error{"fit to selection needs at least 4 mesh vertices; the selection has " +
                     std::to_string(points.size()),
                 {}};
  const bool snapped = options.axis && norm(*options.axis) > 1e-9;
  std::optional<Vec3> fixed_axis = snapped ? options.axis : std::nullopt;
  const bool axial = kind == ShapeKind::cylinder || kind == ShapeKind::cone;
  if (!snapped && axial && options.normals.size() == points.size())
    if ((fixed_axis = axis_from_normals(options.normals)))
      if (auto rev = revolution_axis(points, options.normals, *fixed_axis)) fixed_axis = rev;
  const Frame f = fixed_axis ? frame_about(points, *fixed_axis) : principal_frame(points);
  const Vec3 center = box_center(f);
  FitResult out;
  out.pose.position = center;
  const double* ev = f.eig.values;

  switch (kind) {
    case ShapeKind::sphere: {
      double r = 0;
      for (int k = 0; k < 3; ++k) r = std::max(r, 0.5 * (f.hi[k] - f.lo[k]));
      // A cap (the visible side of a ball) has its centre behind it: fit the sphere.
      const bool whole = surrounds(points, center, f.eig.vectors[0]) &&
                         surrounds(points, center, f.eig.vectors[1]) &&
                         surrounds(points, center, f.eig.vectors[2]);
      if (auto c = whole ? std::nullopt : sphere_center(points, center);
          c && norm(*c - center) < r) {
        double mean = 0;
        for (const Vec3& p : points) mean += norm(p - *c);
        out.pose.position = *c;
        r = mean / static_cast<double>(points.size());
      }
      out.dimensions = {r};
      break;
    }
    case ShapeKind::box: {
      out.pose.rotation = quat_from_frame(f.eig.vectors[0], f.eig.vectors[1], f.eig.vectors[2]);
      out.dimensions = {f.hi[0] - f.lo[0], f.hi[1] - f.lo[1], f.hi[2] - f.lo[2]};
      break;
    }
    // A panel: the rectangle across the two widest directions, its normal the thinnest
    // (the snapped axis when one is given), through the middle of the points.
    case ShapeKind::plane: {
      out.pose.rotation = quat_from_frame(f.eig.vectors[0], f.eig.vectors[1], f.eig.vectors[2]);
      out.dimensions = {f.hi[0] - f.lo[0], f.hi[1] - f.lo[1]};
      break;
    }
    case ShapeKind::torus: {
      const Vec3 axis = snapped ? f.eig.vectors[2] : canonical_sign(f.eig.vectors[2]);
      if (auto ring = fit_ring(points, f.centroid, axis)) {
        out.pose = ring->pose;
        out.dimensions = {ring->major_m, ring->minor_m};
        break;
      }
      // Points on a line in the ring's plane: no circle, size the bounding ring.
      double rmax = 0;
      for (const Vec3& p : points) rmax = std::max(rmax, radial(p, center, axis));
      const double minor = 0.5 * (f.hi[2] - f.lo[2]);
      out.pose.rotation = rotation_from_z(axis);
      out.dimensions = {std::max(rmax - minor, minor), minor};
      break;
    }
    case ShapeKind::cylinder:
    case ShapeKind::cone: {
      // The axis is the principal direction whose cross-section is the roundest.
      int best = 2;
      if (!fixed_axis) {
        double best_score = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a) {
          const double l1 = ev[(a + 1) % 3], l2 = ev[(a + 2) % 3];
          const double score = std::abs(l1 - l2) / std::max({l1, l2, 1e-30});
          if (score < best_score - 1e-9) {
            best_score = score;
            best = a;
          }
        }
      }
      Vec3 axis = fixed_axis ? f.eig.vectors[2] : canonical_sign(f.eig.vectors[best]);
      const double height = f.hi[best] - f.lo[best];
      // Across the axis, the centre of the circle through the points: the bounding
      // box's centre is off for a part of the round (the side a box selection sees).
      Vec3 c = center;
      double rbox = 0;
      for (const Vec3& p : points) rbox = std::max(rbox, radial(p, center, axis));
      if (!surrounds(points, center, axis))
        if (auto cc = circle_center(points, center, axis, kind == ShapeKind::cone);
            cc && norm(*cc - center) < rbox)
          c = *cc;
      double rmax = 0;
      for (const Vec3& p : points) rmax = std::max(rmax, radial(p, c, axis));
      if (kind == ShapeKind::cone) {
        // The base is the end where the vertices spread widest; +Z points to the apex.
        double r_neg = 0, r_pos = 0;
        for (const Vec3& p : points) {
          const double t = dot(p - c, axis);
          const double r = radial(p, c, axis);
          if (t < -0.3 * height) r_neg = std::max(r_neg, r);
          if (t > 0.3 * height) r_pos = std::max(r_pos, r);
        }
        if (r_pos > r_neg) axis = axis * -1.0;
      }
      out.pose.position = c;
      out.pose.rotation = rotation_from_z(axis);
      out.dimensions = {rmax, height};
      break;
    }
  }
  for (double& d : out.dimensions) d = std::max(d, 1e-4);  // a flat selection still fits
  return out;
}

std::optional<Vec3> snap_axis(AxisSnap snap, const MeshData& mesh) {
  switch (snap) {
    case AxisSnap::none: return std::nullopt;
    case AxisSnap::object_up: return Vec3{0, 1, 0};
    case AxisSnap::mesh_principal: {
      const std::vector<Vec3> pts = mesh_points(mesh);
      if (auto fit = fit_primitive(pts, ShapeKind::cylinder)) return fit->pose.axis();
      return std::nullopt;
    }
  }
  return std::nullopt;
}

std::vector<Vec3> mesh_points(const MeshData& mesh, const Box3* box) {
  std::vector<Vec3> pts;
  pts.reserve(mesh.vertex_count());
  for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
    const Vec3 v = mesh.vertex(i);
    if (box == nullptr || box->contains(v)) pts.push_back(v);
  }
  return pts;
}

namespace {

// Fits are measured from float meshes: 0.01 mm and 1e-9 in a quaternion are below
// their precision, and rounding keeps saved specs readable (no 1e-20 noise).
// Dividing by the integer scale (not multiplying by a step) gives the double nearest to
// the decimal, so 0.08968 prints as 0.08968.
double round_to(double v, double step) {
  const double scale = std::round(1.0 / step);
  return std::round(v * scale) / scale + 0.0;
}

}  // namespace

Primitive with_fit(Primitive p, const FitResult& fit) {
  p.pose.position = {round_to(fit.pose.position.x, 1e-5), round_to(fit.pose.position.y, 1e-5),
                     round_to(fit.pose.position.z, 1e-5)};
  const Quat q = fit.pose.rotation;
  p.pose.rotation = normalized(
      Quat{round_to(q.w, 1e-9), round_to(q.x, 1e-9), round_to(q.y, 1e-9), round_to(q.z, 1e-9)});
  p.dimensions.resize(fit.dimensions.size());
  for (std::size_t i = 0; i < fit.dimensions.size(); ++i)
    p.dimensions[i].value_m = std::max(1e-5, round_to(fit.dimensions[i], 1e-5));
  return p;
}

}  // namespace annex::authoring
