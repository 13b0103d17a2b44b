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
// by side, not round one axis. When what the one primitive leaves out lies above or
// below the rest instead, the cut is level there (one body standing on the other), kept
// by the same criterion when the upper stands over the lower's footprint. An upright
// cluster the one primitive explains well, whose outline across the line of sight steps
// in width at one height, is cut level there too (a far stack that one cone explains
// whole), the outline's evidence added to the criterion's; beyond the segmenter's crease
// test's reach one it explains poorly is tried so too. A cluster its
// one primitive explains nearly well enough is
// tried only when it stands on two feet (stands_on_two_feet): the refits cost as much
// whether the cut is kept or not. Private to the scanner.

#include <functional>
#include <optional>
#include <vector>

#include "annex/runtime/frame.h"
#include "annex/runtime/scanner.h"

namespace annex {

struct TouchingSplitParams {
  // Only a cluster whose shape explains less than this share of its points is tried
  // (ScanParams::touching_max_coverage); 0: none.
  double max_whole_coverage = 0.85;
  // A cluster explained over at least this share (and under max_whole_coverage) is tried
  // only when it stands on two feet (stands_on_two_feet: a foot seen in two, or none
  // seen though the cluster reaches into its lower half;
  // ScanParams::touching_two_feet_coverage).
  double two_feet_coverage = 0.8;
  // Its foot: its pixels in this lowest share of its height above its support.
  double foot_share = 0.25;
  // Its foot's front recedes between the means by more than this many standard
  // deviations of the axial noise at its depth. Each bin's front is the nearest of its
  // points, a minimum of noisy ranges, so one arc wobbles (the milk frame's bottle: 0.7
  // sigma), while two bodies side by side recede by their radii (rooms 5061, 9748, 10092
  // at 2.2 to 2.6 m: 1.8 to 3.1 sigma).
  double notch_sigmas = 1.5;
  // ... or its foot is seen in two pieces: a run of empty bins between the means whose
  // chance under the foot's sampling is below exp(-gap_evidence)
  // (ScanParams::touching_gap_evidence); 0: the notch alone.
  double gap_evidence = 6.9;  // ln(1000)
  // The camera's depth noise (depth_noise.h); the scanner sets it from
  // ScanParams::depth_noise.
  DepthNoise depth_noise;
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
  // ... and when that misfit lies above or below the rest, not beside it, the level cut
  // (one body standing on the other; ScanParams::touching_level_cut), each part at least
  // the segmenter's level_min_height_m tall (segment, below).
  bool level_cut = true;
  // An upright cluster its one primitive explains well (max_whole_coverage or more)
  // whose outline steps in width at one height is cut level there (a far stack one cone
  // explains whole; ScanParams::touching_width_step), kept as the level cut is; one it
  // explains worse too where the segmenter's crease test is blind (crease_test_blind).
  bool width_step_cut = true;
  // The segmenter's (ScanParams::segment): its level cut's least part height, and where
  // its crease test is blind.
  SegmenterParams segment;
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

// Whether the cluster stands on two feet: its foot (its pixels in the lowest
// params.foot_share of its height above its support) narrows between the two means of
// its footprint by waist_share, and the foot's front, its nearest range from the camera
// along the line between the means, recedes between them by notch_sigmas. Two bodies
// side by side stand on two feet, each with its own front; one body's foot is one
// outline, and a handle rising from its side is none of it. A foot seen only as a ring's
// front arc narrows between the means too (the milk frame's detergent bottle) but shows
// one front. The front may also be seen in two pieces (TouchingSplitParams::gap_evidence).
// A cluster no point of whose foot is seen, though it reaches into the lower half of its
// height (bodies seen from above that hide their feet), counts as standing on two feet:
// nothing tells one body from two.
bool stands_on_two_feet(const Frame& frame, const ScanCluster& cluster,
                        const TouchingSplitParams& params = {});

}  // namespace annex
