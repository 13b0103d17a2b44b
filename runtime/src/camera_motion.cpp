// Camera motion from the static scene: grid samples of the previous frame, ICP onto this one.
#include "annex/runtime/camera_motion.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "annex/runtime/rigid_motion.h"
#include "annex/runtime/target_volume_segmenter.h"

namespace annex {
namespace {

// The whole frustum as one cube (every pixel's rectangle), sampled to about `pixels`.
TargetCloud whole_frame(const Frame& frame, const CameraIntrinsics& camera, int pixels) {
  TargetVolumeParams p;
  p.max_visited_pixels = pixels;
  p.min_height_m = 0;
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
  const TargetCloud cloud = whole_frame(frame, camera, params.model_pixels * 4);
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

CameraMotionResult estimate_camera_motion(const TrackingModel& previous_static, const Frame& frame,
                                          const CameraIntrinsics& camera, const Pose& predicted,
                                          const CameraMotionParams& params) {
  CameraMotionResult out;
  if (previous_static.points.size() < 50 || !frame.organized()) return out;
  const TargetCloud target = whole_frame(frame, camera, params.target_pixels);
  const DepthView view{&frame, camera};
  const IcpResult turn =
      track_icp(previous_static, target, {{0, 0, 0}, predicted.rotation}, params.turn, &view);
  const IcpResult r = track_icp(previous_static, target, turn.pose, params.icp, &view);
  out.fitness = r.fitness;
  out.rms_m = r.rms_m;
  if (!r.ok) return out;
  out.ok = true;
  out.motion = r.pose;
  return out;
}

}  // namespace annex
