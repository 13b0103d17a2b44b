// Camera motion from the static scene: normal-space samples of the previous frame; a
// still test, the turn by nearest neighbours, then six degrees of freedom paired by pixel.
#include "annex/runtime/camera_motion.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "annex/runtime/object_shape_recognizer.h"
#include "annex/runtime/rigid_motion.h"
#include "annex/runtime/target_volume_segmenter.h"
#include "eigen_rotation.h"

namespace annex {
namespace {

// The whole frustum as one cube (every pixel's rectangle), sampled to about `pixels`.
TargetCloud whole_frame(const Frame& frame, const CameraIntrinsics& camera, int pixels,
                        int normal_step_px) {
  TargetVolumeParams p;
  p.max_visited_pixels = pixels;
  p.min_height_m = 0;
  p.normal_step_px = normal_step_px;
  // Centred 5 m ahead, 10 m wide: every point from 0 to 10 m depth within the frustum.
  return segment_target_volume(frame, camera, {0, 0, 5}, 5, std::nullopt, p);
}

}  // namespace

std::vector<ExcludedVolume> moving_props(const std::vector<ObjectTrack>& tracks,
                                         const CameraMotionParams& params) {
  std::vector<ExcludedVolume> out;
  for (const ObjectTrack& t : tracks) {
    if (!t.model) continue;
    const double speed = norm(t.velocity_m_per_frame) + norm(rotation_vector(t.turn_per_frame)) *
                                                            t.model->radius_m;
    // Unsure tracks (held, lost) may be moving too.
    if (speed < params.still_speed_m_per_frame && t.state == TrackingState::tracking) continue;
    // Radius: the prop, its next move, and a hand's width around it.
    out.push_back({t.pose.position, t.model->radius_m + 2 * speed + 0.1});
  }
  return out;
}

TrackingModel static_scene_model(const Frame& frame, const CameraIntrinsics& camera,
                                 const std::vector<ExcludedVolume>& excluded,
                                 const CameraMotionParams& params) {
  TrackingModel model;
  model.kind = ShapeKind::box;
  model.symmetry = Symmetry::none;
  model.radius_m = params.model_radius_m;
  const TargetCloud cloud = whole_frame(frame, camera, params.model_pixels * 4, params.normal_step_px);
  // Normal-space sampling (Rusinkiewicz and Levoy 2001): a room is mostly a few planes
  // (table, floor, walls) that leave sliding along them free; only the smaller surfaces
  // of other directions (props, edges) pin it. So points are drawn evenly over bins of
  // normal direction, not over pixels.
  constexpr int kBins = 8;
  std::vector<std::vector<size_t>> bins(kBins * kBins);
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const Vec3 p = cloud.points[i];
    // Only points with a grid normal: point-to-plane needs it, and depth edges (where
    // it is missing) move differently from the surfaces either side.
    if (cloud.normals.size() != cloud.points.size() || norm(cloud.normals[i]) < 0.5) continue;
    // Far points: the Kinect's depth noise (7 mm at 2 m) scatters their grid normals.
    if (p.z > params.max_depth_m) continue;
    const bool out = std::any_of(excluded.begin(), excluded.end(), [&](const ExcludedVolume& e) {
      return norm(p - e.center) < e.radius_m;
    });
    if (out) continue;
    const Vec3 n = cloud.normals[i];
    const double azimuth = std::atan2(n.y, n.x);  // -pi..pi
    const int a = std::clamp(static_cast<int>((azimuth + std::numbers::pi) / (2 * std::numbers::pi) * kBins), 0, kBins - 1);
    const int e = std::clamp(static_cast<int>((n.z + 1) * 0.5 * kBins), 0, kBins - 1);
    bins[static_cast<size_t>(a * kBins + e)].push_back(i);
  }
  // Equal shares for the bins (water filling: a bin with fewer points gives its unused
  // share to the others), then evenly spaced points within each bin.
  std::vector<size_t> quota(bins.size(), 0);
  size_t left = static_cast<size_t>(std::max(0, params.model_pixels));
  for (bool grew = true; grew && left > 0;) {
    grew = false;
    size_t open = 0;
    for (size_t b = 0; b < bins.size(); ++b) open += quota[b] < bins[b].size();
    if (open == 0) break;
    const size_t share = std::max<size_t>(1, left / open);
    for (size_t b = 0; b < bins.size() && left > 0; ++b) {
      const size_t add = std::min({share, bins[b].size() - quota[b], left});
      if (add == 0) continue;
      quota[b] += add;
      left -= add;
      grew = true;
    }
  }
  for (size_t b = 0; b < bins.size(); ++b)
    for (size_t k = 0; k < quota[b]; ++k) {
      const size_t idx = bins[b][k * bins[b].size() / quota[b]];
      model.points.push_back(cloud.points[idx]);
      model.normals.push_back(cloud.normals[idx]);
    }
  return model;
}

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

Eigen::Vector3d ev(Vec3 v) { return {v.x, v.y, v.z}; }

// Normal equations of the static points moved by (rot, t), each paired with the point
// seen at its pixel, the residual along that point's grid normal. Rows are in the
// sensor frame: a move d = omega x p + tau changes the residual by
// omega . (p x n) + tau . n.
struct PixelPairs {
  Mat6 h = Mat6::Zero();
  Vec6 g = Vec6::Zero();
  double chi2 = 0;  // sum of w r^2 over the pairs (w = 1 / sigma^2, no robust weight)
  int candidates = 0;  // points with a valid pixel, normal and agreeing orientation
  int pairs = 0;       // of those within the gate
  int inliers = 0;     // within inlier_m
  double inlier_sum2 = 0;
};

struct PairingGate {
  double distance_m = 0;  // pairs farther along the normal are left out...
  double sigmas = 3;      // ... unless within this many noise sigmas
  double huber_sigmas = 0;  // 0: plain 1 / sigma^2 weights
  double inlier_m = 0.01;
  double normal_cos = 0.5;
  int normal_step_px = 2;
  DepthNoise noise;
};

PixelPairs pair_by_pixel(const TrackingModel& model, const Frame& frame, const CameraIntrinsics& k,
                         const Eigen::Matrix3d& rot, const Eigen::Vector3d& t,
                         const PairingGate& gate) {
  PixelPairs out;
  const bool normals = model.normals.size() == model.points.size();
  for (size_t i = 0; i < model.points.size(); ++i) {
    const Eigen::Vector3d p = rot * ev(model.points[i]) + t;
    if (p.z() <= 0.05) continue;
    const long u = std::lround(k.fx * p.x() / p.z() + k.cx);
    const long v = std::lround(k.fy * p.y() / p.z() + k.cy);
    if (u < 0 || v < 0 || u >= frame.width || v >= frame.height) continue;
    const PointXYZRGB& seen = frame.points[static_cast<size_t>(v) * frame.width + u];
    if (!std::isfinite(seen.z) || seen.z <= 0) continue;
    const Vec3 nv = grid_normal_at(frame, static_cast<int>(u), static_cast<int>(v), gate.normal_step_px);
    if (norm(nv) < 0.5) continue;  // a depth edge: the surfaces either side move apart
    const Eigen::Vector3d n = ev(nv);
    if (normals && (rot * ev(model.normals[i])).dot(n) < gate.normal_cos) continue;
    ++out.candidates;
    const Eigen::Vector3d q{seen.x, seen.y, seen.z};
    const double r = n.dot(p - q);
    // Both frames carry the depth noise at about this depth.
    const double sigma = std::numbers::sqrt2 * gate.noise.sigma_z(seen.z);
    if (std::abs(r) > std::max(gate.distance_m, gate.sigmas * sigma)) continue;
    ++out.pairs;
    if (std::abs(r) <= gate.inlier_m) {
      ++out.inliers;
      out.inlier_sum2 += r * r;
    }
    double w = 1 / (sigma * sigma);
    out.chi2 += w * r * r;
    if (gate.huber_sigmas > 0 && std::abs(r) > gate.huber_sigmas * sigma)
      w *= gate.huber_sigmas * sigma / std::abs(r);
    Vec6 row;
    row.head<3>() = p.cross(n);
    row.tail<3>() = n;
    out.h.noalias() += w * row * row.transpose();
    out.g.noalias() += w * r * row;
  }
  return out;
}

// The Gauss-Newton step of the normal equations (a little damping: in a room of planes
// some directions are barely constrained).
Vec6 solve_step(const PixelPairs& s) {
  Mat6 h = s.h;
  h.diagonal().array() += 1e-9 * std::max(1.0, h.diagonal().maxCoeff());
  return h.ldlt().solve(-s.g);
}

// Every `n`-th point of the model (the normal-space bins keep their shares).
TrackingModel every_nth(const TrackingModel& model, int wanted) {
  if (wanted <= 0 || static_cast<size_t>(wanted) >= model.points.size()) return model;
  TrackingModel out = model;
  out.points.clear();
  out.normals.clear();
  const size_t n = model.points.size();
  for (size_t k = 0; k < static_cast<size_t>(wanted); ++k) {
    const size_t i = k * n / static_cast<size_t>(wanted);
    out.points.push_back(model.points[i]);
    if (model.normals.size() == n) out.normals.push_back(model.normals[i]);
  }
  return out;
}

}  // namespace

CameraMotionResult estimate_camera_motion(const TrackingModel& previous_static, const Frame& frame,
                                          const CameraIntrinsics& camera, const Pose& predicted,
                                          const CameraMotionParams& params) {
  CameraMotionResult out;
  if (previous_static.points.size() < 50 || !frame.organized() || camera.width != frame.width ||
      camera.height != frame.height)
    return out;

  // Still test: the residuals at the identity are the noise, and a step would gain no
  // more than noise does.
  if (params.still.enabled) {
    const PairingGate gate{.distance_m = 0,
                           .sigmas = params.still.inlier_sigmas,
                           .inlier_m = params.icp.inlier_m,
                           .normal_cos = params.icp.normal_cos,
                           .normal_step_px = params.normal_step_px,
                           .noise = params.depth_noise};
    const PixelPairs s = pair_by_pixel(previous_static, frame, camera, Eigen::Matrix3d::Identity(),
                                       Eigen::Vector3d::Zero(), gate);
    if (s.pairs >= 50) {
      out.still_chi2 = -solve_step(s).dot(s.g);  // g^T H^-1 g
      const double share = static_cast<double>(s.pairs) / s.candidates;
      if (share >= params.still.min_inlier_share && out.still_chi2 <= params.still.max_chi2) {
        out.ok = out.still = true;
        out.fitness = static_cast<double>(s.inliers) / s.candidates;
        out.rms_m = s.inliers > 0 ? std::sqrt(s.inlier_sum2 / s.inliers) : 0;
        return out;
      }
    }
  }

  // The turn alone, by nearest neighbours on a sparse grid of this frame.
  const TargetCloud target = whole_frame(frame, camera, params.turn_target_pixels, params.normal_step_px);
  const DepthView view{&frame, camera};
  const IcpResult turn = track_icp(every_nth(previous_static, params.turn_points), target,
                                   {{0, 0, 0}, predicted.rotation}, params.turn, &view);

  // Then all six degrees of freedom, paired by pixel.
  const ProjectiveIcpParams& ip = params.icp;
  const Eigen::Matrix3d rot0 = to_matrix(turn.pose.rotation);
  const Eigen::Vector3d t0 = ev(turn.pose.position);
  Eigen::Matrix3d rot = rot0;
  Eigen::Vector3d t = t0;
  PairingGate gate{.distance_m = ip.max_correspondence_m,
                   .sigmas = ip.noise_sigmas,
                   .huber_sigmas = ip.huber_sigmas,
                   .inlier_m = ip.inlier_m,
                   .normal_cos = ip.normal_cos,
                   .normal_step_px = params.normal_step_px,
                   .noise = params.depth_noise};
  for (int it = 0; it < ip.max_iterations; ++it) {
    PixelPairs s = pair_by_pixel(previous_static, frame, camera, rot, t, gate);
    if (s.pairs < 50) break;
    if (ip.translation_sigma_m > 0) {
      // The prior's residual t / sigma; t + tau after the step (omega x t is negligible).
      const double w = 1 / (ip.translation_sigma_m * ip.translation_sigma_m);
      s.h.block<3, 3>(3, 3).diagonal().array() += w;
      s.g.tail<3>() += w * t;
    }
    const Vec6 x = solve_step(s);
    const Eigen::Vector3d omega = x.head<3>(), tau = x.tail<3>();
    const double angle = omega.norm();
    const Eigen::Matrix3d d =
        angle > 1e-12 ? Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix()
                      : Eigen::Matrix3d::Identity();
    rot = d * rot;
    t = d * t + tau;
    const double moved = tau.norm() + angle * params.model_radius_m;
    gate.distance_m = std::max(ip.final_correspondence_m, gate.distance_m * 0.75);
    if (moved < ip.convergence_m && gate.distance_m <= ip.final_correspondence_m) break;
  }
  gate.distance_m = ip.final_correspondence_m;
  const PixelPairs fin = pair_by_pixel(previous_static, frame, camera, rot, t, gate);
  out.fitness = fin.candidates > 0 ? static_cast<double>(fin.inliers) / fin.candidates : 0;
  out.rms_m = fin.inliers > 0 ? std::sqrt(fin.inlier_sum2 / fin.inliers) : 0;
  const Pose motion{{t.x(), t.y(), t.z()}, to_quat(rot)};
  const double step = (t - t0).norm();
  const double turned = rotation_angle_deg(turn.pose.rotation, motion.rotation);
  if (fin.candidates < 50 || out.fitness < ip.min_fitness || out.rms_m > ip.max_rms_m ||
      step > ip.max_step_m || turned > ip.max_step_deg)
    return out;
  out.ok = true;
  out.motion = motion;
  return out;
}

}  // namespace annex
