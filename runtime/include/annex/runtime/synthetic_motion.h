#pragma once
// Hand-speed tracking sequences with exact ground truth: props on a table, some of
// them grabbed, moved and turned (up to 60 mm and 20 degrees per frame, as a prop in
// the hand moves at 30 Hz), a hand-like occluder gripping the first held prop, and a
// head-worn camera that turns and translates. Unlike synthetic_scene.h, props take any
// orientation and the camera any pose, so this file has its own ray caster; the Kinect
// sensor model (SensorNoiseParams, kinect_axial_sigma_m) and the labels are shared.
//
// Motion profiles (docs/tracking.md, "Hand-speed sequences"): a held prop's centre runs
// at constant speed round a vertical loop of `path_radius_m` that starts at its resting
// place, comes towards the camera and rises (pick up, show, put down); it turns about a tilted local
// axis at `spin_deg_per_frame`, reversing smoothly every half `spin_period_frames`
// (the rate is the peak, held for about half of each cycle; a wrist twists back and
// forth, it does not spin). The head's yaw and translation follow the same profile.

#include <array>
#include <cstdint>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/physical_scene.h"
#include "annex/common/result.h"
#include "annex/common/shape.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/synthetic_scene.h"

namespace annex {

struct MotionSceneParams {
  std::uint64_t seed = 1;
  std::vector<ShapeKind> kinds{ShapeKind::cylinder, ShapeKind::box, ShapeKind::sphere};
  int held = 1;  // the first `held` props are moved by hand; the others stay still
  double speed_m_per_frame = 0.04;  // held props: speed of the centre
  double path_radius_m = 0.12;
  double spin_deg_per_frame = 15;  // held props: peak turn rate
  double spin_period_frames = 16;  // one twist back and forth
  int still_frames = 0;  // held props rest this many frames before the hand moves them
  int ramp_frames = 3;   // then their speed grows linearly to full over this many frames
  bool hand = false;               // a hand grips the first held prop
  double camera_yaw_deg_per_frame = 0;  // head turn, peak rate about the room's up axis
  Vec3 camera_velocity_m_per_frame;     // head translation, peak (room frame)
  double camera_period_frames = 16;     // head motion back and forth (about +-9 degrees at 3)
  CameraIntrinsics camera;
};

// A solid in the room frame (table frame of synthetic_scene.h: origin on the table top,
// +Z up): its shape's centre and axis as the `.scene` convention has them (local +Z the
// axis; box sides along local x, y, z).
struct MotionSolid {
  ShapeKind kind = ShapeKind::box;
  std::vector<double> dimensions_m;  // dimension_names(kind) order
  Pose pose;                         // room_from_solid
};

struct MotionProp {
  ShapeKind kind = ShapeKind::box;
  std::vector<double> dimensions_m;
  std::array<std::uint8_t, 3> color{200, 60, 60};
  Pose rest;           // room_from_prop while it rests on the table (frame 0)
  bool held = false;   // moved by hand
  Vec3 path_forward;   // room frame: the loop's direction at its start (horizontal, to the camera)
  Vec3 path_up;        // room frame: towards the loop's centre (up)
  Vec3 spin_axis;      // prop frame: the axis it is turned about
};

struct MotionScene {
  MotionSceneParams params;
  CameraIntrinsics camera;
  Pose camera_rest;  // room_from_camera at frame 0 (x right, y down, z forward)
  double table_half_x_m = 0.7;
  double table_half_y_m = 0.45;
  double table_thickness_m = 0.03;
  double floor_depth_m = 0.75;
  double wall_y_m = 1.2;
  std::vector<MotionProp> props;
  // The hand's parts in the frame of prop 0 (when params.hand and prop 0 is held).
  std::vector<MotionSolid> hand;
};

// A scene: one prop per `kinds` entry, household sizes, resting apart near the middle of
// the view; the camera 0.8-1.0 m from them looking down 35-50 degrees. Errors for
// parameters out of range (speeds above 0.1 m or 45 degrees per frame, no props).
Result<MotionScene> generate_motion_scene(const MotionSceneParams& params);

// Ground truth at `frame`: room_from_camera, room_from_prop, and the prop in the camera
// frame (sensor_from_object, the object frame being the prop's: centre, +Z axis).
Pose motion_camera_pose(const MotionScene& scene, int frame);
Pose motion_prop_pose(const MotionScene& scene, int prop, int frame);
Pose motion_prop_in_camera(const MotionScene& scene, int prop, int frame);
// The hand's parts in the room frame at `frame` (empty without a hand).
std::vector<MotionSolid> motion_hand(const MotionScene& scene, int frame);

// Frame `frame` as the Kinect sees it: labels are prop indices, kLabelTable, kLabelFloor,
// kLabelWall, kLabelOccluder (the hand); truth in the camera frame (support plane and
// one object "o1", "o2", ... per prop).
SyntheticFrame render_motion_frame(const MotionScene& scene, int frame,
                                   const SensorNoiseParams& noise = {});

}  // namespace annex
