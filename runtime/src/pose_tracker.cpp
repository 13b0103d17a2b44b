// PoseTracker: segment -> ICP each frame; held on failure; InitialAligner after
// max_failures; lost until the aligner finds the object again.
#include "annex/runtime/pose_tracker.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "annex/runtime/rigid_motion.h"
#include "annex/runtime/track_model_completion.h"

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

namespace {

// Outward normals of the model points: the plane through each one's nearest points of
// the whole cluster (brute force, once per match), turned towards `eye`. Same frame for
// all arguments.
std::vector<Vec3> model_normals(const std::vector<Vec3>& model, const std::vector<Vec3>& cluster,
                                Vec3 eye) {
  constexpr size_t kNeighbours = 12;
  if (cluster.size() < kNeighbours) return {};
  std::vector<Vec3> normals(model.size());
  std::vector<std::pair<double, size_t>> d(cluster.size());
  for (size_t i = 0; i < model.size(); ++i) {
    for (size_t j = 0; j < cluster.size(); ++j) {
      const Vec3 e = cluster[j] - model[i];
      d[j] = {dot(e, e), j};
    }
    std::nth_element(d.begin(), d.begin() + kNeighbours, d.end());
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < kNeighbours; ++k) {
      const Vec3 q = cluster[d[k].second];
      mean += Eigen::Vector3d(q.x, q.y, q.z);
    }
    mean /= static_cast<double>(kNeighbours);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (size_t k = 0; k < kNeighbours; ++k) {
      const Vec3 q = cluster[d[k].second];
      const Eigen::Vector3d e = Eigen::Vector3d(q.x, q.y, q.z) - mean;
      cov += e * e.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    const Eigen::Vector3d n = eig.eigenvectors().col(0);
    Vec3 nv{n.x(), n.y(), n.z()};
    if (dot(nv, eye - model[i]) < 0) nv = nv * -1.0;
    normals[i] = normalized(nv);
  }
  return normals;
}

// The better of two ICP results: accepted first, then the fitter.
bool better(const IcpResult& a, const IcpResult& b) {
  if (a.ok != b.ok) return a.ok;
  if (std::abs(a.fitness - b.fitness) > 0.02) return a.fitness > b.fitness;
  return a.rms_m < b.rms_m;
}

std::optional<DepthView> depth_view(const TrackingInput& input) {
  if (!input.frame || !input.camera || !input.frame->organized() ||
      input.camera->width != input.frame->width || input.camera->height != input.frame->height)
    return std::nullopt;
  return DepthView{input.frame, *input.camera};
}

}  // namespace

ObjectTrack start_track(ShapeKind kind, const std::vector<Vec3>& cluster_points,
                        const Pose& object_pose, int max_points, bool complete) {
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
  // Normals in the sensor frame (the sensor's origin is the side the points were seen
  // from), then into the object frame.
  std::vector<Vec3> sensor_points;
  for (const Vec3& m : model->points)
    sensor_points.push_back(object_pose.position + rotate(object_pose.rotation, m));
  for (const Vec3& n : model_normals(sensor_points, cluster_points, {0, 0, 0}))
    model->normals.push_back(rotate(inv, n));
  // A box's faces the view lacks, from its centre and the offsets of the faces it shows.
  if (complete) complete_tracking_model(*model);
  ObjectTrack track;
  track.model = std::move(model);
  track.pose = object_pose;
  return track;
}

namespace {

// A track's motion carried into the current sensor frame (the camera turned by `cam`).
struct Motion {
  Vec3 velocity, acceleration;
  Vec3 turn, turn_change;  // rotation vectors per frame
};

Motion motion_in(const ObjectTrack& t, const Pose& cam) {
  auto r = [&](Vec3 v) { return rotate(cam.rotation, v); };
  return {r(t.velocity_m_per_frame), r(t.acceleration_m_per_frame2),
          r(rotation_vector(t.turn_per_frame)), r(t.turn_change_per_frame)};
}

Pose predict(const Pose& last, const Motion& m, int steps, double gain) {
  // Constant acceleration over `steps` frames: sum of (v + j a) for j = 1..steps.
  const double s = steps, ss = 0.5 * s * (s + 1) * gain;
  return {last.position + m.velocity * s + m.acceleration * ss,
          normalized(from_rotation_vector(m.turn * s + m.turn_change * ss) * last.rotation)};
}

}  // namespace

Pose predict_pose(const ObjectTrack& track, const Pose& camera_motion, int steps) {
  const PoseTrackerParams defaults;
  return predict(compose(camera_motion, track.pose), motion_in(track, camera_motion), steps,
                 defaults.acceleration_gain);
}

ObjectTrack track_step(const ObjectTrack& previous, const TrackingInput& input,
                       const PoseTrackerParams& params, TrackStepTimes* times) {
  ObjectTrack next = previous;
  if (!previous.model || input.frame == nullptr) return next;
  const TrackingModel& model = *previous.model;
  TrackStepTimes local;
  const std::optional<DepthView> view = depth_view(input);
  const DepthView* view_ptr = view ? &*view : nullptr;
  const Pose& cam = input.camera_motion;

  // Everything in this frame's sensor coordinates: the last pose moved with the camera
  // (a prop that is not seen is assumed still in the room), the motion turned with it.
  const Pose last = compose(cam, previous.pose);
  const Motion motion = motion_in(previous, cam);
  const Vec3 velocity = motion.velocity;
  const Quat turn = from_rotation_vector(motion.turn);
  next.pose = last;
  next.velocity_m_per_frame = motion.velocity;
  next.acceleration_m_per_frame2 = motion.acceleration;
  next.turn_per_frame = turn;
  next.turn_change_per_frame = motion.turn_change;

  const bool try_icp =
      previous.state != TrackingState::lost && previous.failures < params.max_failures;
  const int steps = previous.failures + 1;  // frames since the last accepted pose
  const Pose predicted = predict(last, motion, steps, params.acceleration_gain);
  if (try_icp) {
    auto t0 = Clock::now();
    const double move = norm(predicted.position - last.position);
    // The cube follows the prediction and grows with it; while held, a little more
    // each frame.
    const double half = model.radius_m + params.volume_margin_m + params.volume_growth * move +
                        0.01 * previous.failures;
    const TargetCloud target = segment_target_volume(*input.frame, input.camera, predicted.position,
                                                     half, input.support, params.volume);
    local.segment_ms = ms_since(t0);
    t0 = Clock::now();
    IcpResult r = track_icp(model, target, predicted, params.icp, view_ptr);
    // Search near the prediction: the prop stopped, kept its velocity, did not turn, or
    // moved half as far.
    if (!r.ok && params.search_near_prediction && (move > 0.002 || norm(rotation_vector(turn)) > 0.01)) {
      const double search_half = model.radius_m + params.volume_margin_m + 0.5 * move +
                                 0.01 * previous.failures;
      const Vec3 middle = (last.position + predicted.position) * 0.5;
      const auto ts = Clock::now();
      const TargetCloud wide = segment_target_volume(*input.frame, input.camera, middle,
                                                     search_half, input.support, params.volume);
      local.segment_ms += ms_since(ts);
      const Pose starts[] = {
          last,
          previous.pose,  // where it was in the sensor frame: the camera motion was wrong
          compose({{0, 0, 0}, cam.rotation}, previous.pose),  // the head only turned
          predict(last, motion, steps, 0.0),  // constant velocity
          {predicted.position, last.rotation},
          {(last.position + predicted.position) * 0.5,
           normalized(scaled_turn(turn, 0.5 * steps) * last.rotation)},
      };
      for (const Pose& start : starts) {
        const IcpResult h = track_icp(model, wide, start, params.icp, view_ptr);
        if (better(h, r)) r = h;
      }
    }
    local.icp_ms = ms_since(t0);
    if (r.ok) {
      // The move since the last accepted pose, per frame.
      const Vec3 moved = (r.pose.position - last.position) * (1.0 / steps);
      const Quat turned = model.symmetry == Symmetry::spherical
                              ? Quat{}
                              : scaled_turn(normalized(r.pose.rotation * conjugate(last.rotation)),
                                            1.0 / steps);
      // Two accepted frames in a row measure a velocity; three, its change.
      const bool had_motion = previous.state == TrackingState::tracking;
      const double keep = had_motion ? params.motion_smoothing : 0.0;
      const Vec3 v = moved * (1 - keep) + velocity * keep;
      const Vec3 w = rotation_vector(turned) * (1 - keep) + motion.turn * keep;
      next.acceleration_m_per_frame2 = had_motion && steps == 1 ? v - velocity : Vec3{};
      next.turn_change_per_frame = had_motion && steps == 1 ? w - motion.turn : Vec3{};
      // A change larger than the motion itself is noise or a lock-on, not a hand.
      if (norm(next.acceleration_m_per_frame2) > norm(v)) next.acceleration_m_per_frame2 = {};
      if (norm(next.turn_change_per_frame) > norm(w)) next.turn_change_per_frame = {};
      next.velocity_m_per_frame = v;
      next.turn_per_frame = from_rotation_vector(w);
      next.pose = r.pose;
      next.state = TrackingState::tracking;
      next.confidence = r.confidence;
      next.failures = 0;
      next.lost_frames = 0;
      if (times) *times = local;
      return next;
    }
    next.failures = previous.failures + 1;
    if (next.failures < params.max_failures) {
      next.state = TrackingState::held;
      next.confidence = previous.confidence * 0.7;
      if (times) *times = local;
      return next;
    }
  }

  // Re-initialise: the InitialAligner around the prediction, the last pose and the
  // scan's candidates.
  const auto t0 = Clock::now();
  InitialAlignInput in;
  in.frame = input.frame;
  in.camera = input.camera;
  in.support = input.support;
  in.orientation = last.rotation;
  in.positions.push_back(last.position);
  if (norm(predicted.position - last.position) > 0.01) in.positions.push_back(predicted.position);
  std::vector<Vec3> candidates = input.candidates;
  std::sort(candidates.begin(), candidates.end(), [&](Vec3 a, Vec3 b) {
    return norm(a - last.position) < norm(b - last.position);
  });
  in.positions.insert(in.positions.end(), candidates.begin(), candidates.end());
  const InitialAlignResult a = align_initial(model, in, params.align);
  local.align_ms = ms_since(t0);
  next.velocity_m_per_frame = {};
  next.acceleration_m_per_frame2 = {};
  next.turn_per_frame = {};
  next.turn_change_per_frame = {};
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

ObjectTrack reanchor_track(const ObjectTrack& track, const PhysicalPrimitive& detection,
                           const TrackingInput& input, const PoseTrackerParams& params) {
  if (!track.model || input.frame == nullptr || detection.kind != track.model->kind) return track;
  InitialAlignInput in;
  in.frame = input.frame;
  in.camera = input.camera;
  in.support = input.support;
  // The track's orientation with its axis turned onto the detected one.
  const Pose last = compose(input.camera_motion, track.pose);
  const Vec3 from = last.axis(), to = normalized(detection.axis);
  const Vec3 c = cross(from, to);
  const Quat tilt = normalized(Quat{1.0 + dot(from, to), c.x, c.y, c.z});
  in.orientation = dot(from, to) < -1.0 + 1e-9 ? last.rotation : normalized(tilt * last.rotation);
  in.positions = {detection.center};
  const InitialAlignResult a = align_initial(*track.model, in, params.align);
  if (!a.ok) return track;
  ObjectTrack next = track;
  next.pose = a.pose;
  next.velocity_m_per_frame = {};
  next.acceleration_m_per_frame2 = {};
  next.turn_per_frame = {};
  next.turn_change_per_frame = {};
  next.state = TrackingState::reinit;
  next.confidence = a.fitness;
  next.failures = 0;
  next.lost_frames = 0;
  return next;
}

}  // namespace annex
