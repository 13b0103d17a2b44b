#pragma once
// InitialAligner (paper, "Object Tracking"): finds an object's source model in the
// current frame when there is no usable previous pose (after 5 failed ICP frames).
// The paper uses FPFH (2.5 cm radius) and RANSAC prerejective with 0.9 similarity;
// that fails often on real data and on symmetric shapes, and PCL's version never
// stops early. So seeds come first: the matched primitive's centre (last pose, the
// latest scan's objects of the same shape) and the support's up axis give a handful of
// poses (yaws about up), each refined by ICP; FPFH + RANSAC with a bounded iteration
// count is the fallback for asymmetric models (docs/tracking.md).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/physical_scene.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/icp_tracker.h"
#include "annex/runtime/target_volume_segmenter.h"

namespace annex {

struct FpfhParams {
  double voxel_m = 0.005;  // both clouds downsampled to this grid first
  double normal_radius_m = 0.015;
  double feature_radius_m = 0.025;  // the paper's 2.5 cm
  int max_iterations = 3000;        // bounded: PCL's prerejective never stops early
  int correspondence_randomness = 3;
  double similarity = 0.9;  // the paper's polygon similarity threshold
  double inlier_fraction = 0.3;
  std::uint64_t seed = 1;
};

struct InitialAlignParams {
  int yaw_hypotheses = 8;         // seeds per position: yaws about the support's up axis
  double search_margin_m = 0.05;  // cube around each seed position: model radius + this
  IcpParams icp;                  // the refinement of every seed
  double min_fitness = 0.6;       // an alignment explaining less of the model is rejected
  bool fpfh_fallback = true;      // only used for Symmetry::none models
  FpfhParams fpfh;
};

struct InitialAlignInput {
  const Frame* frame = nullptr;
  std::optional<CameraIntrinsics> camera;
  std::optional<Plane> support;
  Quat orientation;             // last known orientation (the seeds' yaw 0)
  std::vector<Vec3> positions;  // candidate centres, most likely first
};

struct InitialAlignResult {
  bool ok = false;
  Pose pose;
  double fitness = 0;
  double rms_m = 0;
  std::string method;  // "seed" or "fpfh"; empty when nothing was accepted
  int hypotheses = 0;  // ICP runs tried
};

InitialAlignResult align_initial(const TrackingModel& model, const InitialAlignInput& input,
                                 const InitialAlignParams& params = {});

// FPFH + SampleConsensusPrerejective of the model against a target cloud (PCL), then
// nothing else: the caller refines with ICP. std::nullopt when RANSAC found no pose.
std::optional<Pose> align_fpfh(const TrackingModel& model, const TargetCloud& target,
                               const FpfhParams& params = {});

}  // namespace annex
