#include "annex/authoring/fit.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

Quat quat_from_frame(Vec3 x, Vec3 y, Vec3 z) {
  // Columns x, y, z form the rotation matrix R; standard branch on the largest term.
  const double m00 = x.x, m10 = x.y, m20 = x.z;
  const double m01 = y.x, m11 = y.y, m21 = y.z;
  const double m02 = z.x, m12 = z.y, m22 = z.z;
  const double tr = m00 + m11 + m22;
  Quat q;
  if (tr > 0) {
    const double s = std::sqrt(tr + 1.0) * 2;
    q = {0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s};
  } else if (m00 > m11 && m00 > m22) {
    const double s = std::sqrt(1.0 + m00 - m11 - m22) * 2;
    q = {(m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s};
  } else if (m11 > m22) {
    const double s = std::sqrt(1.0 + m11 - m00 - m22) * 2;
    q = {(m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s};
  } else {
    const double s = std::sqrt(1.0 + m22 - m00 - m11) * 2;
    q = {(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s};
  }
  if (q.w < 0) q = {-q.w, -q.x, -q.y, -q.z};
  return normalized(q);
}

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

}  // namespace

Result<FitResult> fit_primitive(std::span<const Vec3> points, ShapeKind kind) {
  if (points.size() < 4)
    return Error{"fit to selection needs at least 4 mesh vertices; the selection has " +
                     std::to_string(points.size()),
                 {}};
  const Frame f = principal_frame(points);
  const Vec3 center = box_center(f);
  FitResult out;
  out.pose.position = center;
  const double* ev = f.eig.values;

  switch (kind) {
    case ShapeKind::sphere: {
      double r = 0;
      for (int k = 0; k < 3; ++k) r = std::max(r, 0.5 * (f.hi[k] - f.lo[k]));
      out.dimensions = {r};
      break;
    }
    case ShapeKind::box: {
      out.pose.rotation = quat_from_frame(f.eig.vectors[0], f.eig.vectors[1], f.eig.vectors[2]);
      out.dimensions = {f.hi[0] - f.lo[0], f.hi[1] - f.lo[1], f.hi[2] - f.lo[2]};
      break;
    }
    case ShapeKind::torus: {
      const Vec3 axis = canonical_sign(f.eig.vectors[2]);
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
      int best = 0;
      double best_score = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        const double l1 = ev[(a + 1) % 3], l2 = ev[(a + 2) % 3];
        const double score = std::abs(l1 - l2) / std::max({l1, l2, 1e-30});
        if (score < best_score - 1e-9) {
          best_score = score;
          best = a;
        }
      }
      Vec3 axis = canonical_sign(f.eig.vectors[best]);
      const double height = f.hi[best] - f.lo[best];
      double rmax = 0;
      for (const Vec3& p : points) rmax = std::max(rmax, radial(p, center, axis));
      if (kind == ShapeKind::cone) {
        // The base is the end where the vertices spread widest; +Z points to the apex.
        double r_neg = 0, r_pos = 0;
        for (const Vec3& p : points) {
          const double t = dot(p - center, axis);
          const double r = radial(p, center, axis);
          if (t < -0.3 * height) r_neg = std::max(r_neg, r);
          if (t > 0.3 * height) r_pos = std::max(r_pos, r);
        }
        if (r_pos > r_neg) axis = axis * -1.0;
      }
      out.pose.rotation = rotation_from_z(axis);
      out.dimensions = {rmax, height};
      break;
    }
  }
  for (double& d : out.dimensions) d = std::max(d, 1e-4);  // a flat selection still fits
  return out;
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
