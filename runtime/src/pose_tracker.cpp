// PoseTracker: segment -> ICP each frame; held on failure; InitialAligner after
// max_failures; lost until the aligner finds the object again.
#include "annex/runtime/pose_tracker.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace annex {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

std::string_view tracking_state_name(TrackingState state) {
  switch (state) {
    case TrackingState::tracking:
      return "tracking";
    case TrackingState::held:
      return "held";
    case TrackingState::reinit:
      return "reinit";
    case TrackingState::lost:
      return "lost";
  }
  return "lost";
}

ObjectTrack start_track(ShapeKind kind, const std::vector<Vec3>& cluster_points,
                        const Pose& object_pose, int max_points) {
  auto model = std::make_shared<TrackingModel>();
  model->kind = kind;
  model->symmetry = symmetry_of(kind);
  const Quat inv = conjugate(object_pose.rotation);
  const size_t n = cluster_points.size();
  const size_t keep = std::max<size_t>(1, std::min<size_t>(n, static_cast<size_t>(max_points)));
  double radius = 0;
  // Evenly spaced subsample: deterministic and spread over the whole cluster.
  for (size_t k = 0; k < keep && n > 0; ++k) {
    const Vec3 p = cluster_points[k * n / keep];
    const Vec3 local = rotate(inv, p - object_pose.position);
    model->points.push_back(local);
    radius = std::max(radius, norm(local));
  }
  model->radius_m = std::max(radius, 0.02);
  ObjectTrack track;
  track.model = std::move(model);
  track.pose = object_pose;
  return track;
}

ObjectTrack track_step(const ObjectTrack& previous, const TrackingInput& input,
                       const PoseTrackerParams& params, TrackStepTimes* times) {
  ObjectTrack next = previous;
  if (!previous.model || input.frame == nullptr) return next;
  const TrackingModel& model = *previous.model;
  TrackStepTimes local;

  const bool try_icp =
      previous.state != TrackingState::lost && previous.failures < params.max_failures;
  if (try_icp) {
    auto t0 = Clock::now();
    Pose predicted = previous.pose;
    predicted.position = predicted.position + previous.velocity_m_per_frame;
    // While held the object may have kept moving: look a little wider each frame.
    const double half = model.radius_m + params.volume_margin_m + 0.01 * previous.failures;
    const TargetCloud target = segment_target_volume(*input.frame, input.camera, predicted.position,
                                                     half, input.support, params.volume);
    local.segment_ms = ms_since(t0);
    t0 = Clock::now();
    const IcpResult r = track_icp(model, target, predicted, params.icp);
    local.icp_ms = ms_since(t0);
    if (r.ok) {
      const Vec3 moved = r.pose.position - previous.pose.position;
      next.velocity_m_per_frame =
          previous.state == TrackingState::tracking || previous.state == TrackingState::reinit
              ? previous.velocity_m_per_frame * 0.5 + moved * 0.5
              : Vec3{};
      next.pose = r.pose;
      next.state = TrackingState::tracking;
      next.confidence = r.fitness;
      next.failures = 0;
      next.lost_frames = 0;
      if (times) *times = local;
      return next;
    }
    next.failures = previous.failures + 1;
    next.velocity_m_per_frame = {};
    if (next.failures < params.max_failures) {
      next.state = TrackingState::held;
      next.confidence = previous.confidence * 0.7;
      if (times) *times = local;
      return next;
    }
  }

  // Re-initialise: the InitialAligner around the last pose and the scan's candidates.
  const auto t0 = Clock::now();
  InitialAlignInput in;
  in.frame = input.frame;
  in.camera = input.camera;
  in.support = input.support;
  in.orientation = previous.pose.rotation;
  in.positions.push_back(previous.pose.position);
  std::vector<Vec3> candidates = input.candidates;
  std::sort(candidates.begin(), candidates.end(), [&](Vec3 a, Vec3 b) {
    return norm(a - previous.pose.position) < norm(b - previous.pose.position);
  });
  in.positions.insert(in.positions.end(), candidates.begin(), candidates.end());
  const InitialAlignResult a = align_initial(model, in, params.align);
  local.align_ms = ms_since(t0);
  next.velocity_m_per_frame = {};
  if (a.ok) {
    next.pose = a.pose;
    next.state = TrackingState::reinit;
    next.confidence = a.fitness;
    next.failures = 0;
    next.lost_frames = 0;
  } else {
    next.state = TrackingState::lost;
    next.confidence = 0;
    next.failures = std::max(next.failures, params.max_failures);
    next.lost_frames = previous.state == TrackingState::lost ? previous.lost_frames + 1 : 1;
  }
  if (times) *times = local;
  return next;
}

}  // namespace annex
