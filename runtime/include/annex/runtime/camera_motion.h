#pragma once
// The head-worn camera's motion between two frames, from the static scene: the previous
// frame's points (supports, walls, still props; not the props that move) registered
// onto the current frame by point-to-plane ICP. The trackers then
// predict in the room's frame: a still prop stays where the camera motion puts it, a
// moving one adds its own motion (docs/tracking.md, "Camera motion").

#include <optional>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/runtime/depth_noise.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/icp_tracker.h"
#include "annex/runtime/pose_tracker.h"

namespace annex {

// The six-degree-of-freedom stage: each static point paired with the point seen at its
// pixel in the current frame (projective association, as KinectFusion does: no search,
// O(1) per point), residual along that point's grid normal, weighted by the camera's
// depth noise at its depth.
struct ProjectiveIcpParams {
  double max_correspondence_m = 0.03;     // pairs farther along the normal are rejected
  double final_correspondence_m = 0.01;   // the rejection distance shrinks to this
  double noise_sigmas = 3;                // ... but never below this many noise sigmas
  int max_iterations = 8;
  // The update's move (translation + turn at model_radius_m). Pairs by pixel jump a
  // pixel at a time, so the estimate jitters by about a millimetre at 1.5 m (0.04
  // degree): iterating below that buys nothing.
  double convergence_m = 7e-4;
  double huber_sigmas = 2;      // Huber weights beyond this many noise sigmas
  double normal_cos = 0.5;      // pairs whose normals disagree more (60 degrees) are rejected
  double inlier_m = 0.01;       // fitness counts pairs this close
  double min_fitness = 0.35;    // new surfaces enter the view, the hand moves
  double max_rms_m = 0.008;
  double max_step_m = 0.05;     // from the rotation stage's result
  double max_step_deg = 3;
  // A head turns far more than it steps: the translation per frame gets a prior, zero
  // with this sigma (a brisk step is 1 cm per frame). It decides only what the data
  // leave open: in a room of planes a small turn and a sideways step look alike.
  double translation_sigma_m = 0.01;
};

// Is the camera still? The static points paired by pixel at the identity: if their
// residuals are the depth noise alone, the least-squares decrease a Gauss-Newton step
// would bring, in units of the noise variance, is chi-square with 6 degrees of freedom.
struct StillTestParams {
  bool enabled = true;
  double inlier_sigmas = 3;   // a pair within this many sigmas is consistent with stillness
  double min_inlier_share = 0.85;  // ... and this share of the pairs must be
  double max_chi2 = 16.81;    // the 99 % point of chi-square with 6 degrees of freedom
};

struct CameraMotionParams {
  int model_pixels = 800;  // points of the previous frame kept for the static model
  int turn_points = 250;    // of those, the ones the rotation stage registers (kd-tree)
  int turn_target_pixels = 1500;  // grid pixels of the current frame it pairs them with
  // A head turns about 100 degrees/s: 3 degrees per frame moves a point 1 m away by
  // 5 cm, so the search starts wide. It turns far more than it steps (a step of 1 cm
  // per frame is brisk), and in a room of planes a sideways step is barely constrained,
  // so first the rotation alone (about the sensor, nearest neighbours: pixels moved too
  // far for pairing by pixel), then all six degrees of freedom from there by pixel.
  IcpParams turn{.max_correspondence_m = 0.08,
                 .final_correspondence_m = 0.015,
                 .max_iterations = 8,
                 .convergence_m = 7e-4,
                 .inlier_m = 0.015,
                 .min_fitness = 0,
                 .max_rms_m = 1,
                 .max_step_m = 1,
                 .max_step_deg = 12,
                 .estimate_translation = false};
  ProjectiveIcpParams icp;
  StillTestParams still;
  int normal_step_px = 2;       // the grid normals' neighbour offset
  // The depth camera's noise (depth_noise.h), which the pairing gates count in; a
  // session gives it its scan's (SessionParams).
  DepthNoise depth_noise;
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
  bool still = false;  // the still test passed: no registration, the motion is identity
  Pose motion;         // sensor_now_from_sensor_previous (identity when not ok)
  double fitness = 0;
  double rms_m = 0;
  double still_chi2 = 0;  // the still test's statistic (see StillTestParams)
};

// The previous frame's static scene registered onto `frame`: first the still test at
// the identity; then the rotation from `predicted` (the last motion: a head turns
// smoothly) with no translation, then the full motion from there, paired by pixel.
CameraMotionResult estimate_camera_motion(const TrackingModel& previous_static, const Frame& frame,
                                          const CameraIntrinsics& camera, const Pose& predicted,
                                          const CameraMotionParams& params = {});

}  // namespace annex
