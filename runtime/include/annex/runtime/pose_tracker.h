#pragma once
// PoseTracker (paper, "Object Tracking"): one pipeline per matched object, chaining
// TargetVolumeSegmenter -> IcpTracker each frame, with the InitialAligner taking over
// after `max_failures` consecutive ICP failures. Pipelines of different objects are
// independent (a track is a value), so the session runs them concurrently.

#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/physical_scene.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/icp_tracker.h"
#include "annex/runtime/initial_aligner.h"
#include "annex/runtime/target_volume_segmenter.h"

namespace annex {

// tracking: ICP succeeded this frame. held: ICP failed, the previous pose is kept
// (retried next frame). reinit: after max_failures held frames the InitialAligner ran
// and found the object again this frame. lost: the InitialAligner failed too; it
// retries every frame until the session releases the object.
enum class TrackingState { tracking, held, reinit, lost };
std::string_view tracking_state_name(TrackingState state);

struct PoseTrackerParams {
  double volume_margin_m = 0.03;  // cube half size = model radius + this
  // ... + this times the predicted move: a fast prop's prediction errs more.
  double volume_growth = 0.5;
  // Weight of the previous motion estimate in the new one (0: the last move alone; the
  // measurement noise is ~0.5 mm, a hand's path changes by centimetres).
  double motion_smoothing = 0.2;
  // Share of the last change of motion carried into the prediction (1: constant
  // acceleration, 0: constant velocity).
  double acceleration_gain = 1.0;
  bool search_near_prediction = true;  // other starts when ICP from the prediction fails
  TargetVolumeParams volume;
  IcpParams icp;
  InitialAlignParams align;
  int max_failures = 5;  // consecutive ICP failures before re-initialising
};

struct ObjectTrack {
  std::shared_ptr<const TrackingModel> model;
  // sensor-from-object: the latest accepted pose (while held or lost, moved with the
  // camera: a prop that cannot be seen is assumed still in the room).
  Pose pose;
  // The prop's motion per frame in the room, in the current sensor frame: its centre's
  // velocity and its turn (applied on the left), and how each changed over the last
  // frame (a hand's path curves and its wrist reverses). The prediction of the next pose
  // (constant acceleration: the next move is the last one plus its last change).
  Vec3 velocity_m_per_frame;
  Vec3 acceleration_m_per_frame2;
  Quat turn_per_frame;
  Vec3 turn_change_per_frame;  // rotation vector (axis times radians) per frame
  TrackingState state = TrackingState::tracking;
  // [0, 1]: the share of the model points facing the camera that the frame explains
  // (IcpResult::confidence; a hand covering the prop lowers it), decayed by 0.7 per
  // held frame, 0 while lost.
  double confidence = 1.0;
  int failures = 0;     // consecutive failed frames
  int lost_frames = 0;  // consecutive frames in state lost
};

// What one frame offers every tracker.
struct TrackingInput {
  const Frame* frame = nullptr;
  std::optional<CameraIntrinsics> camera;
  std::optional<Plane> support;
  // Centres of objects of the track's shape in the latest scan, for re-initialisation.
  std::vector<Vec3> candidates;
  // sensor_now_from_sensor_previous: how the static scene moved in the sensor frame
  // since the previous frame (camera_motion.h); identity for a still camera.
  Pose camera_motion;
};

// Where the track expects its prop `steps` frames after its last accepted pose, in the
// current sensor frame (after `camera_motion`).
Pose predict_pose(const ObjectTrack& track, const Pose& camera_motion, int steps = 1);

struct TrackStepTimes {
  double segment_ms = 0, icp_ms = 0, align_ms = 0;
};

// One frame of one object's pipeline: the track as it stands after this frame.
ObjectTrack track_step(const ObjectTrack& previous, const TrackingInput& input,
                       const PoseTrackerParams& params = {}, TrackStepTimes* times = nullptr);

// A lost prop seen again by the scanner: the InitialAligner seeded at the detected
// primitive (its centre, its axis for the orientation). On success the track continues
// (state reinit, same model, so the session keeps its physical id); otherwise it is
// returned unchanged.
ObjectTrack reanchor_track(const ObjectTrack& track, const PhysicalPrimitive& detection,
                           const TrackingInput& input, const PoseTrackerParams& params = {});

// A track for a freshly matched object: its model from the cluster's points (sensor
// frame) expressed in `object_pose`, subsampled to at most `max_points`, with normals
// from each point's neighbours, oriented towards the sensor; a box's faces the view
// lacks are added unless `complete` is false (track_model_completion.h).
ObjectTrack start_track(ShapeKind kind, const std::vector<Vec3>& cluster_points,
                        const Pose& object_pose, int max_points = 600, bool complete = true);

}  // namespace annex
