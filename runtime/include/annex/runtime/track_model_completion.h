#pragma once
// A track's model is the view of its prop at match time: for a box, two or three faces.
// A prop turned in the hand by 60 degrees or more shows faces that view lacks, and ICP
// then has nothing to pair them with (fitness 0.06 at 85 degrees in the hand-speed
// sequence). The matched primitive says what the rest looks like: the box's other faces
// are planes at known offsets from its centre. Completion adds points on the parts of
// the primitive's surface the view did not cover, with their exact normals; the
// tracker's visibility test then uses whichever faces face the camera
// (docs/tracking.md, "Model completion").

#include "annex/runtime/icp_tracker.h"

namespace annex {

struct ModelCompletionParams {
  // Points of the whole primitive surface at the fill spacing: the spacing is chosen so
  // that the complete surface would hold about this many.
  int surface_points = 600;
  // Half extents from the view: this quantile of |coordinate| along each box axis
  // (every face of a box lies at +-half extent from its centre, so any seen face gives
  // its offset; the quantile leaves out the noise's tail).
  double extent_quantile = 0.98;
  // A cell of the surface counts as seen when a view point lies within this many
  // spacings of its centre.
  double covered_spacings = 1.0;
};

// What completion added, for tests and the docs.
struct ModelCompletion {
  Vec3 half_extents_m;  // box: along the object frame's x, y, z
  int added_points = 0;
};

// Adds points (and normals) on the parts of a box model's surface its points do not
// cover; models of other shapes are left unchanged. The model's points must be in the
// object frame with its origin at the box's centre and its axes along the sides (the
// object frame start_track builds).
ModelCompletion complete_tracking_model(TrackingModel& model, const ModelCompletionParams& params = {});

}  // namespace annex
