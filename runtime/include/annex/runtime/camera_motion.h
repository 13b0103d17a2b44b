#pragma once
// The head-worn camera's motion between two frames, from the static scene: the previous
// frame's points (supports, walls, still props; not the props that move) registered
// onto the current frame by the same point-to-plane ICP as the props. The trackers then
// predict in the room's frame: a still prop stays where the camera motion puts it, a
// moving one adds its own motion (docs/tracking.md, "Camera motion").

#include <optional>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/icp_tracker.h"
#include "annex/runtime/pose_tracker.h"

namespace annex {

struct CameraMotionParams {
  int model_pixels = 1200;   // points of the previous frame kept for the static model
  int target_pixels = 7000;  // pixels of the current frame it is registered onto
  // A head turns about 100 degrees/s: 3 degrees per frame moves a point 1 m away by
  // 5 cm, so the search starts wide. It turns far more than it steps (a step of 1 cm
  // per frame is brisk), and in a room of planes a sideways step is barely constrained,
  // so first the rotation alone (about the sensor), then all six degrees of freedom
  // from there with a narrower search.
  IcpParams turn{.max_correspondence_m = 0.08,
                 .final_correspondence_m = 0.015,
                 .max_iterations = 10,
                 .convergence_m = 2e-4,
                 .inlier_m = 0.015,
                 .min_fitness = 0,
                 .max_rms_m = 1,
                 .max_step_m = 1,
                 .max_step_deg = 12,
                 .estimate_translation = false};
  IcpParams icp{.max_correspondence_m = 0.03,
                .final_correspondence_m = 0.01,
                .max_iterations = 12,
                .convergence_m = 1e-4,
                .inlier_m = 0.01,
                .min_fitness = 0.35,
                .max_rms_m = 0.008,
                .max_step_m = 0.05,
                .max_step_deg = 3};
  double model_radius_m = 1.5;  // the lever arm of a turn in the convergence test
  // Static points farther than this are left out: the Kinect's depth noise (about 7 mm
  // at 2 m, Nguyen et al. 2012) scatters their grid normals into every direction.
  double max_depth_m = 1.8;
  // A prop moving less than this per frame counts as part of the static scene.
  double still_speed_m_per_frame = 0.004;
};

// A region of the frame to leave out of the static scene: a moving prop and what
// holds it.
struct ExcludedVolume {
  Vec3 center;
  double radius_m = 0.1;
};

// The props that move (and a margin for the hand around them), from their tracks.
std::vector<ExcludedVolume> moving_props(const std::vector<ObjectTrack>& tracks,
                                         const CameraMotionParams& params = {});

// The static scene of a frame, in its sensor frame: grid-sampled points with grid
// normals, the excluded volumes left out. The model the next frame is registered to.
TrackingModel static_scene_model(const Frame& frame, const CameraIntrinsics& camera,
                                 const std::vector<ExcludedVolume>& excluded,
                                 const CameraMotionParams& params = {});

struct CameraMotionResult {
  bool ok = false;
  Pose motion;  // sensor_now_from_sensor_previous (identity when not ok)
  double fitness = 0;
  double rms_m = 0;
};

// The previous frame's static scene registered onto `frame`: the rotation from
// `predicted` (the last motion: a head turns smoothly) with no translation, then the
// full motion from there.
CameraMotionResult estimate_camera_motion(const TrackingModel& previous_static, const Frame& frame,
                                          const CameraIntrinsics& camera, const Pose& predicted,
                                          const CameraMotionParams& params = {});

}  // namespace annex
