// IcpTracker: point-to-plane ICP against the target volume, with a small kd-tree.
#include "annex/runtime/icp_tracker.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "eigen_rotation.h"

namespace annex {
namespace {

// A balanced kd-tree over a fixed point set: indices reordered so every subrange's
// median is its splitting node (no per-node allocation).
class KdTree {
 public:
  explicit KdTree(const std::vector<Vec3>& points) : pts_(points), idx_(points.size()) {
    std::iota(idx_.begin(), idx_.end(), 0);
    axis_.assign(points.size(), 0);
    build(0, static_cast<int>(idx_.size()));
  }

  // Index of the nearest point within `max_d`, or -1.
  int nearest(Vec3 q, double max_d) const {
    int best = -1;
    double best_d2 = max_d * max_d;
    search(0, static_cast<int>(idx_.size()), q, best, best_d2);
    return best;
  }

 private:
  static double coord(Vec3 p, int a) { return a == 0 ? p.x : (a == 1 ? p.y : p.z); }

  void build(int lo, int hi) {
    if (hi - lo <= 1) return;
    Vec3 mn{1e9, 1e9, 1e9}, mx{-1e9, -1e9, -1e9};
    for (int i = lo; i < hi; ++i) {
      const Vec3 p = pts_[idx_[i]];
      mn = {std::min(mn.x, p.x), std::min(mn.y, p.y), std::min(mn.z, p.z)};
      mx = {std::max(mx.x, p.x), std::max(mx.y, p.y), std::max(mx.z, p.z)};
    }
    const Vec3 ext = mx - mn;
    const int a = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    const int mid = (lo + hi) / 2;
    std::nth_element(idx_.begin() + lo, idx_.begin() + mid, idx_.begin() + hi,
                     [&](int i, int j) { return coord(pts_[i], a) < coord(pts_[j], a); });
    axis_[mid] = a;
    build(lo, mid);
    build(mid + 1, hi);
  }

  void search(int lo, int hi, Vec3 q, int& best, double& best_d2) const {
    if (lo >= hi) return;
    const int mid = (lo + hi) / 2;
    const Vec3 p = pts_[idx_[mid]];
    const Vec3 d = p - q;
    const double d2 = dot(d, d);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = idx_[mid];
    }
    if (hi - lo == 1) return;
    const int a = axis_[mid];
    const double diff = coord(q, a) - coord(p, a);
    if (diff < 0) {
      search(lo, mid, q, best, best_d2);
      if (diff * diff < best_d2) search(mid + 1, hi, q, best, best_d2);
    } else {
      search(mid + 1, hi, q, best, best_d2);
      if (diff * diff < best_d2) search(lo, mid, q, best, best_d2);
    }
  }

  const std::vector<Vec3>& pts_;
  std::vector<int> idx_;
  std::vector<int> axis_;
};

Eigen::Vector3d ev(Vec3 v) {
  return {v.x, v.y, v.z};
}
Vec3 vv(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

Symmetry symmetry_of(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::sphere:
      return Symmetry::spherical;
    case ShapeKind::cylinder:
    case ShapeKind::cone:
    case ShapeKind::torus:
      return Symmetry::axial;
    case ShapeKind::box:
    case ShapeKind::plane:
      return Symmetry::none;
  }
  return Symmetry::none;
}

Quat quat_from_axes(Vec3 x, Vec3 y, Vec3 z) {
  Eigen::Matrix3d r;
  r.col(0) = ev(x);
  r.col(1) = ev(y);
  r.col(2) = ev(z);
  // Re-orthonormalise: callers pass nearly orthogonal axes.
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d o = svd.matrixU() * svd.matrixV().transpose();
  if (o.determinant() < 0) {
    Eigen::Matrix3d u = svd.matrixU();
    u.col(2) *= -1;
    o = u * svd.matrixV().transpose();
  }
  return to_quat(o);
}

Quat conjugate(Quat q) {
  return {q.w, -q.x, -q.y, -q.z};
}

double rotation_angle_deg(Quat a, Quat b) {
  const Quat d = normalized(conjugate(a) * b);
  const double w = std::min(1.0, std::abs(d.w));
  return 2.0 * std::acos(w) / kDeg;
}

namespace {

// Which model points take part at a pose: facing the camera (with normals) and, with
// the depth image, not hidden behind what the camera saw at their pixel.
class Visibility {
 public:
  Visibility(const TrackingModel& model, const IcpParams& params, const DepthView* view)
      : model_(model), params_(params), view_(view && view->frame && view->frame->organized()
                                                 ? view
                                                 : nullptr) {}

  bool facing(size_t i, const Eigen::Matrix3d& rot, const Eigen::Vector3d& p) const {
    if (model_.normals.size() != model_.points.size()) return true;
    const Eigen::Vector3d n = rot * ev(model_.normals[i]);
    return -n.dot(p) >= params_.backface_cos * p.norm();
  }

  // Something nearer than `margin` in front of p at its pixel.
  bool hidden(const Eigen::Vector3d& p, double margin) const {
    const float z = observed(p);
    return std::isfinite(z) && z < p.z() - margin;
  }
  // p projects outside the image: the camera cannot tell whether it is there.
  bool outside(const Eigen::Vector3d& p) const {
    if (!view_) return false;
    if (p.z() <= 0.05) return true;
    const CameraIntrinsics& k = view_->camera;
    const long u = std::lround(k.fx * p.x() / p.z() + k.cx);
    const long v = std::lround(k.fy * p.y() / p.z() + k.cy);
    return u < 0 || v < 0 || u >= view_->frame->width || v >= view_->frame->height;
  }
  // The camera saw through p: what it saw at p's pixel is farther than `margin` behind.
  bool in_free_space(const Eigen::Vector3d& p, double margin) const {
    const float z = observed(p);
    return std::isfinite(z) && z > p.z() + margin;
  }

 private:
  // Depth the camera saw at p's pixel; NaN when unknown.
  float observed(const Eigen::Vector3d& p) const {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    if (!view_ || p.z() <= 0.05) return nan;
    const Frame& f = *view_->frame;
    const CameraIntrinsics& k = view_->camera;
    const int u = static_cast<int>(std::lround(k.fx * p.x() / p.z() + k.cx));
    const int v = static_cast<int>(std::lround(k.fy * p.y() / p.z() + k.cy));
    if (u < 0 || v < 0 || u >= f.width || v >= f.height) return nan;
    const PointXYZRGB& q = f.points[static_cast<size_t>(v) * f.width + u];
    return std::isfinite(q.z) && q.z > 0 ? q.z : nan;
  }

  const TrackingModel& model_;
  const IcpParams& params_;
  const DepthView* view_;
};

}  // namespace

IcpResult track_icp(const TrackingModel& model, const TargetCloud& target, const Pose& initial,
                    const IcpParams& params, const DepthView* view) {
  IcpResult result;
  result.pose = initial;
  if (model.points.empty() || target.points.size() < 10) return result;
  const KdTree tree(target.points);
  const bool have_normals = target.normals.size() == target.points.size();
  const bool model_normals = model.normals.size() == model.points.size();
  const Visibility visibility(model, params, view);

  Eigen::Matrix3d rot = to_matrix(initial.rotation);
  Eigen::Vector3d t = ev(initial.position);
  // Rotation directions the shape lets us observe (columns), in the sensor frame.
  auto rotation_basis = [&]() {
    switch (model.symmetry) {
      case Symmetry::spherical:
        return Eigen::MatrixXd(3, 0);
      case Symmetry::axial: {
        Eigen::MatrixXd b(3, 2);
        b.col(0) = rot.col(0);
        b.col(1) = rot.col(1);
        return b;
      }
      case Symmetry::none:
        break;
    }
    return Eigen::MatrixXd(Eigen::Matrix3d::Identity());
  };

  double max_d = params.max_correspondence_m;
  const double huber = 0.005;
  for (int it = 0; it < params.max_iterations; ++it) {
    result.iterations = it + 1;
    const Eigen::MatrixXd basis = rotation_basis();
    const int nr = static_cast<int>(basis.cols());
    const int nt = params.estimate_translation ? 3 : 0;
    const int n = nr + nt;
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
    int pairs = 0;
    Eigen::VectorXd row(n);
    auto add_row = [&](const Eigen::Vector3d& arm, const Eigen::Vector3d& dir, double r) {
      // Residual r along `dir`; derivative by rotation about the centre and translation.
      const Eigen::Vector3d c = arm.cross(dir);
      for (int k = 0; k < nr; ++k) row(k) = c.dot(basis.col(k));
      if (nt) row.tail<3>() = dir;
      const double w = std::abs(r) <= huber ? 1.0 : huber / std::abs(r);
      h.noalias() += w * row * row.transpose();
      g.noalias() += w * r * row;
    };
    const double hide_margin = std::max(params.occlusion_margin_m, max_d);
    for (size_t i = 0; i < model.points.size(); ++i) {
      const Eigen::Vector3d p = rot * ev(model.points[i]) + t;
      if (visibility.outside(p) || visibility.hidden(p, hide_margin)) continue;
      // A model point where the camera saw through (past the prop's end, say) is pulled
      // back onto the nearest data point-to-point, from the full starting distance:
      // point-to-plane alone lets a partial view slide along its surface.
      if (visibility.in_free_space(p, params.free_space_margin_m)) {
        const int j = tree.nearest(vv(p), params.max_correspondence_m);
        if (j < 0) continue;
        const Eigen::Vector3d q = ev(target.points[j]);
        ++pairs;
        for (int a = 0; a < 3; ++a) add_row(p - t, Eigen::Vector3d::Unit(a), p(a) - q(a));
        continue;
      }
      const int j = tree.nearest(vv(p), max_d);
      if (j < 0) continue;
      const Eigen::Vector3d q = ev(target.points[j]);
      const Eigen::Vector3d arm = p - t;
      const bool target_normal = have_normals && norm(target.normals[j]) > 0.5;
      if (target_normal && model_normals &&
          (rot * ev(model.normals[i])).dot(ev(target.normals[j])) < params.normal_cos)
        continue;
      ++pairs;
      if (target_normal) {
        const Eigen::Vector3d nrm = ev(target.normals[j]);
        add_row(arm, nrm, nrm.dot(p - q));
      } else {
        for (int a = 0; a < 3; ++a) add_row(arm, Eigen::Vector3d::Unit(a), p(a) - q(a));
      }
    }
    if (pairs < 6 || n == 0) break;
    h.diagonal().array() += 1e-6 * static_cast<double>(pairs);
    const Eigen::VectorXd x = h.ldlt().solve(-g);
    Eigen::Vector3d omega = Eigen::Vector3d::Zero();
    for (int k = 0; k < nr; ++k) omega += x(k) * basis.col(k);
    const Eigen::Vector3d tau = nt ? Eigen::Vector3d(x.tail<3>()) : Eigen::Vector3d::Zero();
    const double angle = omega.norm();
    if (angle > 1e-12) rot = Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix() * rot;
    t += tau;
    const double moved = tau.norm() + angle * model.radius_m;
    max_d = std::max(params.final_correspondence_m, max_d * 0.75);
    if (moved < params.convergence_m && max_d <= params.final_correspondence_m) break;
  }

  // Fitness, coverage and RMS at the final pose. Points outside the image are neither
  // seen nor hidden: a prop leaving the view is judged on its part still in it (the
  // confidence, over all facing points, drops with what left).
  int facing = 0, outside = 0, seen = 0, inliers = 0;
  double sum2 = 0;
  const double hide_margin = std::max(params.occlusion_margin_m, params.inlier_m);
  for (size_t i = 0; i < model.points.size(); ++i) {
    const Eigen::Vector3d p = rot * ev(model.points[i]) + t;
    if (!visibility.facing(i, rot, p)) continue;
    ++facing;
    if (visibility.outside(p)) {
      ++outside;
      continue;
    }
    if (visibility.hidden(p, hide_margin)) continue;
    ++seen;
    const int j = tree.nearest(vv(p), params.inlier_m);
    if (j < 0) continue;
    ++inliers;
    const Eigen::Vector3d q = ev(target.points[j]);
    double r2 = (p - q).squaredNorm();
    if (have_normals && norm(target.normals[j]) > 0.5) {
      const double r = ev(target.normals[j]).dot(p - q);
      r2 = r * r;
    }
    sum2 += r2;
  }
  result.pose = {vv(t), to_quat(rot)};
  result.fitness = seen > 0 ? static_cast<double>(inliers) / seen : 0;
  result.coverage = facing > outside ? static_cast<double>(seen) / (facing - outside) : 0;
  result.confidence = facing > 0 ? static_cast<double>(inliers) / facing : 0;
  result.rms_m = inliers > 0 ? std::sqrt(sum2 / inliers) : 0;
  const double step = norm(result.pose.position - initial.position);
  const double turn = rotation_angle_deg(initial.rotation, result.pose.rotation);
  // Too few points facing the camera (a model turned edge-on) tells nothing either.
  const int least = std::min<int>(30, static_cast<int>(model.points.size()) / 4 + 1);
  const bool enough = facing >= least && seen >= least;
  result.ok = enough && result.fitness >= params.min_fitness &&
              result.coverage >= params.min_coverage && result.rms_m <= params.max_rms_m &&
              step <= params.max_step_m && turn <= params.max_step_deg;
  return result;
}

}  // namespace annex
