// A cylinder in any orientation (cylinder_any_axis.h).
#include "cylinder_any_axis.h"
#include "quantile.h"
#include "shape_residuals.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

namespace annex {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Algebraic circle (Kasa) through 2D points with weights.
bool kasa(const std::vector<Eigen::Vector2d>& q, const std::vector<double>& w, Eigen::Vector2d& c,
          double& r) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < q.size(); ++i) {
    if (w[i] <= 0) continue;
    const Eigen::Vector3d row(q[i].x(), q[i].y(), 1.0);
    A += w[i] * row * row.transpose();
    b += w[i] * row * q[i].squaredNorm();
  }
  const Eigen::Vector3d x = A.ldlt().solve(b);
  if (!x.allFinite()) return false;
  c = Eigen::Vector2d(x(0) / 2, x(1) / 2);
  const double r2 = x(2) + c.squaredNorm();
  if (r2 <= 0) return false;
  r = std::sqrt(r2);
  return true;
}

// Length, coverage and score of the cylinder with this axis and cross-section.
AxisCylinderFit finish(const std::vector<Vec3>& points, const std::vector<Eigen::Vector2d>& q,
                       const std::vector<double>& s, const std::vector<double>& tol,
                       const ShapeRecognizerParams& params, const Eigen::Vector3d& axis,
                       const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
                       const Eigen::Vector2d& c, double r, AxisCylinderFit out,
                       std::optional<double> lid_end = std::nullopt) {
  const size_t n = points.size();
  if (r < params.min_radius_m || r > params.max_radius_m) return out;
  const double s0 = quantile(s, 0.01), s1 = lid_end ? *lid_end : quantile(s, 0.99);
  const double half = (s1 - s0) / 2, mid = (s0 + s1) / 2;
  if (half <= 0) return out;
  double score = 0, covered = 0, sq = 0;
  for (size_t i = 0; i < n; ++i) {
    const double rho = (q[i] - c).norm();
    const double over = std::max(std::abs(s[i] - mid) - half, 0.0);
    const double d_side = std::hypot(rho - r, over);
    const double d_cap = std::hypot(std::max(0.0, rho - r), std::abs(s[i] - mid) - half);
    const double d = std::min(d_side, d_cap);
    if (d < tol[i]) {
      const double e = d / tol[i];
      score += 1 - e * e;
      covered += 1;
      sq += d * d;
    }
  }
  const Eigen::Vector3d centre = e1 * c.x() + e2 * c.y() + axis * mid;
  out.fit.primitive.kind = ShapeKind::cylinder;
  out.fit.primitive.dimensions_m = {r, 2 * half};
  out.fit.primitive.center = {centre.x(), centre.y(), centre.z()};
  out.fit.primitive.axis = {axis.x(), axis.y(), axis.z()};
  out.fit.x_axis = {e1.x(), e1.y(), e1.z()};
  out.fit.coverage = covered / static_cast<double>(n);
  out.fit.primitive.fit = out.fit.coverage;
  out.fit.rms_m = covered > 0 ? std::sqrt(sq / covered) : 0;
  out.score = score / static_cast<double>(n);
  out.valid = true;
  return out;
}

// A starting axis refined as the least eigenvector of the side normals' scatter
// (normals within 66 degrees of the axis are caps and left out), and the points seen
// across it: what the circle fit (circle_from) needs, and what decides before it whether
// the fit could win (its axis, its facetedness).
struct AxisStart {
  bool valid = false;
  Eigen::Vector3d axis, e1, e2;
  std::vector<char> side;
  std::vector<Eigen::Vector2d> q;
  std::vector<double> s, w;
  double facetedness = 1;
};

// The normals as Eigen vectors, and whether each is known (norm above 0.5), computed
// once for both starts and every round.
struct KnownNormals {
  std::vector<Eigen::Vector3d> v;
  std::vector<char> known;
  explicit KnownNormals(const std::vector<Vec3>& normals) : v(normals.size()), known(normals.size()) {
    for (size_t i = 0; i < normals.size(); ++i) {
      v[i] = Eigen::Vector3d(normals[i].x, normals[i].y, normals[i].z);
      known[i] = v[i].norm() > 0.5;
    }
  }
};

// m's lower triangle += v v^T: SelfAdjointEigenSolver reads the lower triangle only.
void add_outer_lower(Eigen::Matrix3d& m, const Eigen::Vector3d& v) {
  m(0, 0) += v.x() * v.x();
  m(1, 0) += v.y() * v.x();
  m(2, 0) += v.z() * v.x();
  m(1, 1) += v.y() * v.y();
  m(2, 1) += v.z() * v.y();
  m(2, 2) += v.z() * v.z();
}

AxisStart start_from(const std::vector<Vec3>& points, const KnownNormals& normals,
                     Eigen::Vector3d axis) {
  AxisStart out;
  const size_t n = points.size();
  std::vector<char>& side = out.side;
  side.assign(n, 0);
  for (int round = 0; round < 3; ++round) {
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    int used = 0;
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d& v = normals.v[i];
      side[i] = normals.known[i] && std::abs(v.dot(axis)) < 0.4;
      if (!side[i]) continue;
      add_outer_lower(m, v);
      ++used;
    }
    if (used < 30) return out;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m);
    // Side normals confined to one direction (a flat face) leave the axis undetermined.
    if (es.eigenvalues()(1) < 0.05 * es.eigenvalues()(2)) return out;
    axis = es.eigenvectors().col(0);
  }
  for (size_t i = 0; i < n; ++i) side[i] = normals.known[i] && std::abs(normals.v[i].dot(axis)) < 0.4;
  // Cross-section: points projected on the plane across the axis.
  const Eigen::Vector3d seed = std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = axis.cross(seed).normalized(), e2 = axis.cross(e1);
  out.q.resize(n);
  out.s.resize(n);
  out.w.resize(n);
  double c4 = 0, s4 = 0;
  int sides = 0;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p(points[i].x, points[i].y, points[i].z);
    out.q[i] = Eigen::Vector2d(p.dot(e1), p.dot(e2));
    out.s[i] = p.dot(axis);
    out.w[i] = side[i] ? 1.0 : 0.0;
    if (side[i]) {
      const Eigen::Vector3d& v = normals.v[i];
      const auto [cos4, sin4] = shape_residuals::fourfold(v.dot(e1), v.dot(e2));
      c4 += cos4;
      s4 += sin4;
      ++sides;
    }
  }
  if (sides < 30) return out;
  out.facetedness = std::sqrt(c4 * c4 + s4 * s4) / sides;
  out.axis = axis;
  out.e1 = e1;
  out.e2 = e2;
  out.valid = true;
  return out;
}

// The cross-section's circle from a valid start: an algebraic circle on the side points,
// reweighted, then the cylinder's length, coverage and score (finish).
AxisCylinderFit circle_from(const std::vector<Vec3>& points, const std::vector<double>& tol,
                            const ShapeRecognizerParams& params, AxisStart& st) {
  AxisCylinderFit out;
  out.facetedness = st.facetedness;
  const size_t n = points.size();
  const std::vector<Eigen::Vector2d>& q = st.q;
  std::vector<double>& w = st.w;
  Eigen::Vector2d c;
  double r = 0;
  if (!kasa(q, w, c, r)) return out;
  // Reweighted: points far from the circle (a label's edge, a neighbour's sliver) drop.
  for (int round = 0; round < 4; ++round) {
    for (size_t i = 0; i < n; ++i) {
      if (!st.side[i]) continue;
      const double e = ((q[i] - c).norm() - r) / (2 * tol[i]);
      w[i] = std::abs(e) < 1 ? (1 - e * e) * (1 - e * e) : 0.0;
    }
    if (!kasa(q, w, c, r)) return out;
  }
  return finish(points, q, st.s, tol, params, st.axis, st.e1, st.e2, c, r, out);
}

// The least direction of the scatter of points (all of them, or those marked).
Eigen::Vector3d flattest_direction(const std::vector<Vec3>& points, const std::vector<char>& use) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  int n = 0;
  for (size_t i = 0; i < points.size(); ++i)
    if (use[i]) {
      mean += Eigen::Vector3d(points[i].x, points[i].y, points[i].z);
      ++n;
    }
  if (n < 3) return Eigen::Vector3d::Zero();
  mean /= n;
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < points.size(); ++i)
    if (use[i]) {
      const Eigen::Vector3d q = Eigen::Vector3d(points[i].x, points[i].y, points[i].z) - mean;
      add_outer_lower(m, q);
    }
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m).eigenvectors().col(0);
}

}  // namespace

DiscCylinderFit fit_cylinder_on_rim(const std::vector<Vec3>& points, const std::vector<double>& tol,
                                    const ShapeRecognizerParams& params, const AxisGate& could_win) {
  DiscCylinderFit out;
  const size_t n = points.size();
  if (n < 60 || tol.size() != n) return out;
  // The lid: the plane of the flattest direction, refitted twice on the points within
  // the tolerance of it (the rim and a neighbour's stray points leave).
  std::vector<char> use(n, 1);
  Eigen::Vector3d axis = flattest_direction(points, use);
  for (int round = 0; round < 2 && axis.norm() > 0.5; ++round) {
    std::vector<double> s(n);
    for (size_t i = 0; i < n; ++i) s[i] = axis.dot(Eigen::Vector3d(points[i].x, points[i].y, points[i].z));
    // The lid is the end of the points nearest the camera along the axis.
    const Eigen::Vector3d to_eye = -Eigen::Vector3d(points[0].x, points[0].y, points[0].z);
    if (axis.dot(to_eye) < 0) {
      axis = -axis;
      for (double& v : s) v = -v;
    }
    const double lid = quantile(s, 0.9);
    int kept = 0;
    for (size_t i = 0; i < n; ++i) kept += use[i] = std::abs(s[i] - lid) < 2 * tol[i];
    if (kept < 30) return out;
    axis = flattest_direction(points, use);
  }
  if (axis.norm() < 0.5) return out;
  if (axis.dot(-Eigen::Vector3d(points[0].x, points[0].y, points[0].z)) < 0) axis = -axis;
  if (could_win && !could_win(Vec3{axis.x(), axis.y(), axis.z()})) return out;
  const Eigen::Vector3d seed = std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = axis.cross(seed).normalized(), e2 = axis.cross(e1);
  std::vector<Eigen::Vector2d> q(n);
  std::vector<double> s(n);
  Eigen::Vector2d mid = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p(points[i].x, points[i].y, points[i].z);
    q[i] = Eigen::Vector2d(p.dot(e1), p.dot(e2));
    s[i] = p.dot(axis);
    mid += q[i];
  }
  mid /= static_cast<double>(n);
  // The outline seen along the axis: per direction from the middle, the farthest point.
  constexpr int kBins = 72;
  std::vector<int> far(kBins, -1);
  std::vector<double> far_r(kBins, 0);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d d = q[i] - mid;
    const int b = std::clamp(static_cast<int>((std::atan2(d.y(), d.x()) + kPi) / (2 * kPi) * kBins), 0, kBins - 1);
    if (d.norm() > far_r[b]) {
      far_r[b] = d.norm();
      far[b] = static_cast<int>(i);
    }
  }
  std::vector<Eigen::Vector2d> rim;
  std::vector<double> rim_tol;
  for (int b = 0; b < kBins; ++b)
    if (far[b] >= 0) {
      rim.push_back(q[far[b]]);
      // The outline is where depth ends: a silhouette pixel is off by about a pixel.
      const double pixel = std::abs(points[far[b]].z) / params.focal_px;
      rim_tol.push_back(std::max(tol[far[b]], 2 * pixel));
    }
  if (rim.size() < kBins / 2) return out;
  std::vector<double> w(rim.size(), 1.0);
  Eigen::Vector2d c;
  double r = 0;
  if (!kasa(rim, w, c, r)) return out;
  for (int round = 0; round < 4; ++round) {
    for (size_t k = 0; k < rim.size(); ++k) {
      const double e = ((rim[k] - c).norm() - r) / (3 * rim_tol[k]);
      w[k] = std::abs(e) < 1 ? (1 - e * e) * (1 - e * e) : 0.0;
    }
    if (!kasa(rim, w, c, r)) return out;
  }
  int on = 0;
  for (size_t k = 0; k < rim.size(); ++k) on += std::abs((rim[k] - c).norm() - r) < rim_tol[k];
  out.round_outline = static_cast<double>(on) / kBins;
  if (could_win && out.round_outline < params.min_round_outline) return out;
  // The lid sits at the median of its points (an embossed lid spreads them over
  // millimetres), the far end at the last points seen along the axis.
  std::vector<double> lid_s;
  for (size_t i = 0; i < n; ++i)
    if (use[i]) lid_s.push_back(s[i]);
  out.cylinder = finish(points, q, s, tol, params, axis, e1, e2, c, r, AxisCylinderFit{},
                        quantile(lid_s, 0.5));
  if (out.cylinder.valid) {
    // Side normals are not used: the rim seen is often a thin strip.
    out.cylinder.facetedness = 0;
  }
  return out;
}

AxisCylinderFit fit_cylinder_any_axis(const std::vector<Vec3>& points,
                                      const std::vector<Vec3>& normals,
                                      const std::vector<double>& tol,
                                      const ShapeRecognizerParams& params, const AxisGate& could_win) {
  const size_t n = points.size();
  if (n < 30 || normals.size() != n || tol.size() != n) return {};
  // Two starting axes from the scatter of all normals: its least direction when the
  // side dominates what is seen (a can lying across the view), its main direction when
  // a cap does (a tin standing on its edge, lid to the camera).
  const KnownNormals known(normals);
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i)
    if (known.known[i]) add_outer_lower(m, known.v[i]);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m);
  // Both starts' axes first: the better scoring start is the fit, so the circles are
  // fitted unless neither start could be used (then neither fit could win).
  std::array<AxisStart, 2> starts{start_from(points, known, es.eigenvectors().col(0)),
                                  start_from(points, known, es.eigenvectors().col(2))};
  if (could_win) {
    bool any = false;
    for (const AxisStart& st : starts)
      any = any || (st.valid && st.facetedness < params.max_round_facetedness &&
                    could_win(Vec3{st.axis.x(), st.axis.y(), st.axis.z()}));
    if (!any) return {};
  }
  AxisCylinderFit best;
  for (AxisStart& st : starts) {
    if (!st.valid) continue;
    AxisCylinderFit f = circle_from(points, tol, params, st);
    if (f.valid && (!best.valid || f.score > best.score)) best = f;
  }

  return best;
}

}  // namespace annex
