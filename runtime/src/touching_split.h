#pragma once
// Two convex bodies that touch (a ball against a tin, two tins side by side) are one
// cluster when no crease between them stands above the depth noise (far away, or where
// they meet along a line the camera looks down on); one primitive then explains their
// points poorly. Such a cluster is cut in two where its footprint on the support holds
// two blobs (two means along its long axis); when what the one primitive leaves out lies
// on one side of that cut (one body explained, the other not), each part is fitted
// again, and the two are kept when they explain the points better than the one by the
// information criterion: the residuals in units of the Kinect's axial noise at their
// depth, a point the fit leaves out costing as much as one at the fit's tolerance,
// against ln(n) per parameter (each part's shape and the cut's two) over the
// independent points. When that cut is not kept (the means halve the larger of two
// bodies that differ in size), the cluster is cut along what the one primitive leaves
// out, when that lies beside it. Either cut is kept only when the two parts stand side
// by side, not round one axis. Private to the scanner.

#include <functional>
#include <optional>
#include <vector>

#include "annex/runtime/frame.h"
#include "annex/runtime/scanner.h"

namespace annex {

struct TouchingSplitParams {
  // Only a cluster whose shape explains less than this share of its points is tried
  // (ScanParams::touching_max_coverage); 0: none.
  double max_whole_coverage = 0.8;
  // Each part's shape explains at least this share of its points
  // (ScanParams::touching_part_coverage).
  double min_part_coverage = 0.8;
  // Each part holds at least this share of the cluster's pixels (the segmenter's
  // min_object_share: smaller is a part of one object, not an object).
  double min_part_share = 0.08;
  // ... and at least the pixels a body this wide shows at the cluster's depth (the
  // disc it spans; ScanParams::touching_min_part_size_m): smaller is no object the
  // scanner reports whole, and the pixels of a body fall with the square of its depth,
  // so a fixed count kept two far bodies as one.
  double min_part_size_m = 0.05;
  // The cut is refitted when what the one primitive leaves out lies on one side of it,
  // or when the footprint narrows between the two means to under this share of its
  // width at the narrower one (ScanParams::touching_waist_share; a convex body's
  // footprint never narrows between two of its points); 0: the one-side test alone.
  double waist_share = 0.7;
  // When the means' cut is not kept, the cut along what the cluster's one primitive
  // leaves out is tried (ScanParams::touching_misfit_cut): the means halve the larger of
  // two bodies that differ in size.
  bool misfit_cut = true;
};

// The cut of one cluster, when it is worth it: its two parts, fitted, and their normals.
struct TouchingCut {
  ScanCluster a, b;
  std::vector<Vec3> normals_a, normals_b;
};

// refit(part, normals): smooths the part (its own pixels its only neighbours) and fits
// its shape, filling its normals. Only a cluster seen_whole() is tried: one cut by the
// image border or hidden in part fits poorly for what is missing of it. Reads only this
// cluster (clusters are independent: the scanner tries each beside the others' fits);
// the scanner keeps the first part at the cluster's index and appends the second.
std::optional<TouchingCut> touching_cut(
    const Frame& frame, const ScanCluster& cluster,
    const std::function<void(ScanCluster&, std::vector<Vec3>&)>& refit,
    const std::function<bool(const ScanCluster&)>& seen_whole, const ShapeRecognizerParams& shape,
    const TouchingSplitParams& params = {});

}  // namespace annex
