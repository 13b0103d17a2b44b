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
  TargetVolumeParams volume;
  IcpParams icp;
  InitialAlignParams align;
  int max_failures = 5;  // consecutive ICP failures before re-initialising
};

struct ObjectTrack {
  std::shared_ptr<const TrackingModel> model;
  Pose pose;                  // sensor-from-object, the latest accepted pose
  Vec3 velocity_m_per_frame;  // constant-velocity prediction of the next centre
  TrackingState state = TrackingState::tracking;
  double confidence = 1.0;  // [0, 1]: the last ICP fitness, decayed while held or lost
  int failures = 0;         // consecutive failed frames
  int lost_frames = 0;      // consecutive frames in state lost
};

// What one frame offers every tracker.
struct TrackingInput {
  const Frame* frame = nullptr;
  std::optional<CameraIntrinsics> camera;
  std::optional<Plane> support;
  // Centres of objects of the track's shape in the latest scan, for re-initialisation.
  std::vector<Vec3> candidates;
};

struct TrackStepTimes {
  double segment_ms = 0, icp_ms = 0, align_ms = 0;
};

// One frame of one object's pipeline: the track as it stands after this frame.
ObjectTrack track_step(const ObjectTrack& previous, const TrackingInput& input,
                       const PoseTrackerParams& params = {}, TrackStepTimes* times = nullptr);

// A track for a freshly matched object: its model from the cluster's points (sensor
// frame) expressed in `object_pose`, subsampled to at most `max_points`.
ObjectTrack start_track(ShapeKind kind, const std::vector<Vec3>& cluster_points,
                        const Pose& object_pose, int max_points = 600);

}  // namespace annex
