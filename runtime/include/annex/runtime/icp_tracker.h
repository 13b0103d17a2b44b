#pragma once
// IcpTracker (paper, "Object Tracking"): refines an object's pose each frame by ICP of
// its source model (the points the scan kept when it was matched) against the points
// of its target volume. Point-to-plane with grid normals, nearest neighbours from a
// small balanced kd-tree of the target; rotations a symmetric primitive cannot show are not
// estimated (docs/tracking.md, "Symmetry").

#include <memory>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/shape.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/target_volume_segmenter.h"

namespace annex {

// Which rotations the shape leaves unobservable.
enum class Symmetry {
  none,       // box, unknown shapes: full 6-DOF pose
  axial,      // cylinder, cone, torus: the angle about the axis (local +Z) is undefined
  spherical,  // sphere: every rotation is undefined, only the centre is tracked
};
Symmetry symmetry_of(ShapeKind kind);

// What a tracked object is matched against each frame. Points are in the object
// frame: the matched primitive's frame at the time of matching (origin its centre,
// +Z its axis pointing away from the support).
struct TrackingModel {
  ShapeKind kind = ShapeKind::box;
  Symmetry symmetry = Symmetry::none;
  std::vector<Vec3> points;   // subsampled source cloud, object frame
  std::vector<Vec3> normals;  // per point, outward (object frame); empty: unknown
  double radius_m = 0.1;      // largest distance of a model point from the origin
};

struct IcpParams {
  double max_correspondence_m = 0.02;     // pairs farther apart are rejected
  double final_correspondence_m = 0.008;  // the rejection distance shrinks to this
  int max_iterations = 20;
  double convergence_m = 2e-4;  // stop when the update moves points less than this
  double inlier_m = 0.008;      // fitness counts model points with a partner this close
  double min_fitness = 0.45;    // share of model points with a partner, else failure
  double max_rms_m = 0.007;     // RMS over inliers, else failure
  double max_step_m = 0.05;     // a larger jump from the initial pose is a failure
  double max_step_deg = 30;
  // Visibility (models with normals): a model point whose normal faces away from the
  // camera by more than this cosine cannot be seen and takes no part.
  double backface_cos = 0.05;
  // With the depth image: a model point behind what the camera saw at its pixel by more
  // than this (or the current correspondence distance, if larger) is hidden by
  // something in front, a hand say, and takes no part either (docs/tracking.md).
  double occlusion_margin_m = 0.01;
  // With the depth image: a model point the camera saw through (the depth at its pixel
  // this much farther) is pulled point-to-point onto the nearest data point.
  double free_space_margin_m = 0.015;
  double normal_cos = 0.5;  // pairs whose normals disagree more than this are rejected
  double min_coverage = 0.25;  // fewer facing points unhidden: too little seen to tell
  bool estimate_translation = true;  // false: only the rotation (about the pose's origin)
};

// The organized frame a target volume was cut from, for the occlusion test.
struct DepthView {
  const Frame* frame = nullptr;
  CameraIntrinsics camera;
};

struct IcpResult {
  Pose pose;           // sensor-from-object
  bool ok = false;     // fitness, rms and step within bounds
  // Share of the model points that should be seen (facing the camera, not hidden) with
  // a partner within inlier_m: what decides acceptance.
  double fitness = 0;
  double rms_m = 0;       // RMS point-to-plane distance of those partners
  double coverage = 1;    // share of the facing model points in the image that are not hidden
  double confidence = 0;  // fitness x coverage: share of the facing points explained
  int iterations = 0;
};

IcpResult track_icp(const TrackingModel& model, const TargetCloud& target, const Pose& initial,
                    const IcpParams& params = {}, const DepthView* view = nullptr);

// Quaternion of a 3x3 rotation matrix given by its columns, and the columns back.
Quat quat_from_axes(Vec3 x, Vec3 y, Vec3 z);
// Angle of the rotation taking a to b, degrees.
double rotation_angle_deg(Quat a, Quat b);
Quat conjugate(Quat q);

}  // namespace annex
