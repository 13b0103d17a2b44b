#pragma once
// Splitting a cluster into the objects it holds (docs/perception.md, Clutter). Objects
// that touch (a cup against a box, a box standing on a box) are one Euclidean cluster;
// between them the surface folds inwards. Household objects are convex, or convex
// up to smooth hollows (a bowl's inside), so a sharp concave crease, and a depth step
// where one object hides another, mark where one object ends.
//   crease test  per grid pixel p and each of 4 image directions, the points a, b one
//                arm length either side on the same cluster: a plane through a and b
//                has 1/z linear in the image, so p's depth behind the plane's
//                prediction, z_p - 2 / (1/z_a + 1/z_b), is 0 on a plane, negative on
//                a convex surface and positive in a valley or behind a depth step.
//                Above max(min_crease_depth_m, noise_factor * its depth noise) p is
//                a crease pixel;
//   level cut    where the crease pixels gather at one height over the support under
//                what rises above them (one object's top under another standing on
//                it), no region grows across that height there, though the crease
//                fades at the silhouette;
//   regions      grow over non-crease pixels; crease pixels then join the nearest
//                region; regions too small to be an object join the neighbour they
//                share most border with (a mug's handle, a pot's handles).

#include <vector>

#include "annex/common/physical_scene.h"
#include "annex/runtime/depth_noise.h"
#include "annex/runtime/frame.h"

namespace annex {

// Every field is a scan config key `segment_<name>` (samples/config/scan.conf).
struct SegmenterParams {
  bool enabled = true;
  // Half-width of the crease test: wide enough to see a crease's two flanks above the
  // sensor noise, narrow enough that a bowl's curvature (depth k r^2 / 2) stays small.
  double arm_m = 0.01;
  // Far away the arm spans few pixels and the 3x3 means overlap: at least this many.
  double min_arm_px = 4;
  // Directions where the surface is seen within atan(1 / max_chord_slope) of the ray
  // (11 degrees; the scanner's min_view_cos of 0.2 likewise leaves such points out of
  // the fits) are not tested.
  double max_chord_slope = 5;
  // A right-angle crease is about this share of the arm deep (0.7 seen head-on, less
  // obliquely); pixels whose threshold exceeds it are not tested.
  double right_angle_depth_share = 0.5;
  // A crease is at least this deep, and noise_factor times the noise of the test's
  // depth (each of the three depths a 3x3 mean) at that range.
  double min_crease_depth_m = 0.003;
  double noise_factor = 3.0;
  // The camera's depth noise (depth_noise.h); the scanner sets it from
  // ScanParams::depth_noise.
  DepthNoise depth_noise;
  // A region with fewer full-resolution points than this (or this share of its
  // cluster) is a part, not an object: it joins its biggest neighbour.
  int min_object_points = 600;
  double min_object_share = 0.08;
  // Level cut (an object standing on another: a tin on a tin, a box on a box). Where
  // the crease pixels gather at one height over the support and run across at least
  // level_min_span of the cluster's width there, the cluster is cut at that height:
  // the crease between a lower object's top and the upper one's side is level, and
  // where it fades at the silhouette (the upper object's side meets the lower's edge
  // with no valley between) the regions would join around its ends. Both parts must be
  // level_min_height_m tall or more (a laptop's 2 cm base stays one with its screen).
  bool level_cut = true;
  double level_min_span = 0.75;
  double level_min_height_m = 0.03;
  // A part standing on the level cut is an object with as few full-resolution points
  // at 1 m as one standing alone (fewer farther, with the square of depth); not a key:
  // the scanner sets it from ScanParams::min_cluster_points.
  int level_min_part_points = 300;
};

// Whether the crease test cannot see a right-angle crease at depth z (its threshold,
// noise_factor times the noise of its depths, above right_angle_depth_share of the arm):
// beyond about 2 m on a Kinect. `focal_px`: the camera's.
bool crease_test_blind(double z, double focal_px, const SegmenterParams& params);

// One cluster on the strided grid (pixel indices into frame.points, every `step`-th
// row and column) split into its objects; returns the cluster itself when it holds
// one. `tolerance_m`: grid neighbours farther apart than this in 3D never join.
// `support`: the plane the cluster stands on, for the level cut (none without it).
std::vector<std::vector<int>> split_cluster(const Frame& frame, const std::vector<int>& grid_pixels,
                                            int step, double tolerance_m,
                                            const SegmenterParams& params = {},
                                            const Plane* support = nullptr);

}  // namespace annex
