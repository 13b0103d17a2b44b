#pragma once
// ObjectShapeRecognizer (paper: "Object Shape Recognition"): fits the primitives of
// one segmented object resting on a known support plane. The salient primitive is
// chosen among sphere, cylinder, cone, torus and box by coverage and residuals, not by
// inlier count alone; a secondary primitive is added when a second shape explains a
// large share of the points (a bottle's neck above its body). docs/perception.md.

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/physical_scene.h"
#include "annex/runtime/depth_noise.h"
#include "annex/runtime/frame.h"

namespace annex {

struct ShapeRecognizerParams {
  // The depth camera's focal length in pixels, not a threshold: a pixel's footprint at
  // depth z is z / focal_px. The scanner sets it from each frame's intrinsics.
  double focal_px = CameraIntrinsics{}.fx;
  // The camera's depth noise (depth_noise.h), which every tolerance given in sigmas
  // scales with; the scanner sets it from ScanParams::depth_noise.
  DepthNoise depth_noise;
  // Residual tolerance: a point is explained by a shape when its distance to the
  // shape's surface is below max(min_tolerance_m, noise_factor * sigma_z(depth)).
  double min_tolerance_m = 0.004;
  double noise_factor = 2.5;
  // The salient shape must explain at least this share of the object's points,
  // otherwise the object is reported as unknown.
  double min_coverage = 0.6;
  // A more complex shape (cone over cylinder) must explain this much more.
  double complexity_margin = 0.04;
  // Sanity bounds on household objects.
  double min_radius_m = 0.01;
  double max_radius_m = 0.5;
  // A cone must narrow by at least this share of its base radius, else it is a cylinder.
  double min_cone_taper = 0.25;
  // ... or short of it by at most this many standard errors of the measured narrowing
  // (the slope of radius against height over the side's independent points, each of
  // sigma_z): a frustum tapering by min_cone_taper measures under it half the time.
  double cone_taper_doubt = 2.0;
  // A cone's side is fitted on the points that face sideways (normals more than 26
  // degrees from up); with too few of them, on those below the top's height: a cone
  // flatter than 26 degrees (a wide lid, a flat lampshade) faces up as much as a top.
  // Its axis then comes from the footprint's outline when the upright cylinder, the
  // cone's start, finds no side either.
  bool flat_cone_sides = true;
  // An upright cylinder's top is its cap's median height when the cap (points inside
  // its circle facing up) lies above its side's middle and is flat to the noise: its
  // heights' interquartile range within this many sigma of the height noise (sigma_z
  // times the ray's slope; 1.35 unsmoothed, less smoothed). A lid seen from above, as a
  // box's top face sets the box's height; bags in a box spread 2.4 sigma and more
  // (nyu_basement). Else its side's 98 % height, which the depth noise lifts above the
  // rim by two sigma (5 mm of a flat tin's 4 cm at 2.4 m). A frustum widening up to
  // that lid ends there too. 0: off (before session 34).
  double lid_spread_sigmas = 2.0;
  // An upright cylinder's circle is chosen and refined at its points' own scatter
  // (noise_factor times the scale of the least median residual among the circles drawn)
  // where that is below their tolerance: the smoothed side points of a mug 1.7 m away
  // scatter 1.2 mm about its circle against a tolerance of 10 mm, within which a circle
  // twice as wide through the front and the handle explains them too. Off: every circle
  // at the tolerance (before session 42).
  bool circle_own_scatter = true;
  // A secondary primitive must explain this share of the points the salient one misses
  // and at least this share of all points.
  double min_secondary_share = 0.12;
  // Against a cone through the body and what is above it (a bottle far away, both
  // explaining every point), a neck of this share is weighed: the information criterion
  // over the residuals decides between the pair and the cone, not the neck's share.
  double pair_min_secondary_share = 0.04;
  // ... a neck: narrowing to this share of the body's radius or less (a bowl's flared
  // rim above the cylinder of its foot is no neck). Also when the body alone explains
  // too little (under min_coverage, at least half the points) and the two together
  // enough: a bottle whose shoulder and neck are a third of its height or more.
  double pair_max_neck_share = 0.6;
  // Score penalty for a round side (cylinder, cone) when the side normals bunch into
  // flat faces, and for a box when they spread around like a round side.
  double side_shape_penalty = 0.1;
  // A ball's cap seen alone: the resting sphere's fit starts with its centre this share
  // of the radius (half the top) beyond the cap's mean point, away from the camera.
  double sphere_cap_depth_share = 0.8;
  // A sphere is tried when the top is at most this many times the footprint's width: a
  // ball is as tall as it is wide, but a dark one returns depth only where it faces the
  // camera, a cap some 0.6 of its diameter wide under its full height.
  double sphere_max_top_over_width = 1.8;
  // A sphere must show, across the view and along it, at least this share of the
  // curvature 1 / (2 r) of its near side (a cylinder's or a cone's side shows none along
  // its axis, a box's edge none across it): few noisy points favour the sphere's three
  // parameters by the information criterion whatever their shape.
  double sphere_min_curvature_share = 0.25;
  // A cylinder in any orientation needs its side normals spread round its axis: the
  // |mean of e^(4i psi)| of their angles below this (two faces of a box give ~1).
  double max_round_facetedness = 0.5;
  // A cylinder standing on its rim (a tin on its edge, lid to the camera) needs the
  // outline of its points seen along its axis to be a circle: this share of the
  // outline's directions on the fitted circle (a square's outline puts about 0.3 there,
  // a circle all but the arc the table cuts off).
  double min_round_outline = 0.6;
  // A box that wins on a flat top seen from above gives way to the upright cylinder (and
  // the cone from it) of its footprint's round outline when the rectangle's residual
  // energy on that outline is at least this many times the circle's: at 1 the circle,
  // with two parameters fewer, explains the outline as well as the rectangle does. A
  // box's outline gives 0 to 0.8 (96 boxes on fresh rooms 9501-9620 and 10001-10120); a
  // flat bowl 2.3 m away, whose rim the depth noise blurs, 1.1 to 1.9 (before session 26:
  // 2, the circle leaving half of the rectangle's energy).
  double min_footprint_roundness = 1.0;
  // An upright cylinder whose side should face the camera but shows below its rim less
  // than this share of the pixels it predicts there is a body narrowing under its rim (a
  // bowl widening up seen from above), when a frustum with a foot of at least
  // min_foot_share of its rim would hide its side from the camera.
  double max_side_seen_share = 0.1;
  double min_foot_share = 0.3;
  // A solid cannot be seen through: an upright cylinder, cone or box through which the
  // camera saw the support's surface (SupportAround) inside its foot, by at least this
  // many pixels and this share of the object's pixels, is not what stands there (a cup
  // widening up seen from above, read as the cylinder of its rim: the table shows in the
  // ring between its foot and its rim; a ball read as a box: the table shows in the box's
  // near corners). A cylinder so contradicted offers the frustum on the foot the
  // support's surface leaves free. A box is asked only of an object that reaches down to
  // its support: one standing on another box and overhanging it shows the table under
  // it and is still a box.
  int min_foot_seen_pixels = 20;
  double min_foot_seen_share = 0.05;
  // The solid is shrunk, for that test, by this share of its foot's radius (a box: of its
  // shorter half side): a primitive fitted to a real body (a dome read as a cone, a box's
  // rounded edges) misses its outline by that much.
  double foot_seen_model_share = 0.1;
  // ... and a point counts when the ray to it runs inside that solid for more than the
  // point's tolerance (noise_factor sigma_z): the depth noise moves a point along its
  // ray, not across it. false: the solid is shrunk by the tolerance in every direction
  // too (a flat bowl 2.4 m away, 4 cm tall, then had no solid left to see through).
  bool foot_seen_along_ray = true;
  // A closed solid hides its own far side: a point the camera could see only through
  // an upright cylinder's or cone's side is not explained by it (through its top it may
  // be: the inside of a cup). A cylinder wider than two touching bodies, its axis
  // nearer than their faces, otherwise follows their fronts from its far inside.
  bool own_side_hides = true;
  // A tilted box no thicker than its points' tolerance is one face's noise: its depth
  // is not measured (ObjectShape::depth_unseen), as for a box seen by one side alone.
  bool one_face_box_partial = true;
  // A torus lying flat is no taller than its tube: it is fitted to the points under 1.5
  // times the height that 90 % of them lie under, and tried when that height, not the
  // top's, is under 0.55 of the footprint's width. A few points of a neighbour above it (a
  // ball's edge a straight cut gave a ring) otherwise pull its tube up round them, or
  // keep it from being tried. Off: every point, gated on the top (before session 44).
  bool torus_own_points = true;
  // At most this many points enter the fits (a deterministic subsample).
  int max_fit_points = 800;
  // The cone's Levenberg-Marquardt runs first on an even subsample of at most this many
  // of its points (the iterations from the profile's start), then two iterations on all
  // of them (the last steps, which set the result, see every point; the cone moves by
  // tenths of a millimetre against 8 iterations on all). 0: 8 iterations on all points.
  // 200 points put the sample's minimum within sigma_z / sqrt(200), under 0.2 mm near.
  int refine_sample_points = 200;
  // The box is turned by its faces' lines (besides its side normals' mean azimuth) only
  // when two standard errors of that mean turn the footprint's corners by more than
  // this: 1 mm is below the depth noise (sigma_z >= 1.2 mm), so within it no turn of
  // the box can change its score or extents beyond the noise; near objects seen over
  // hundreds of side points stay within it, far or small pieces do not.
  double box_azimuth_doubt_m = 0.001;
  std::uint64_t seed = 1;
};

// A fitted primitive with its full pose: PhysicalPrimitive keeps the axis only, the
// overlay also needs the box's in-plane orientation.
struct ShapeFit {
  PhysicalPrimitive primitive;
  Vec3 x_axis{1, 0, 0};  // box: local x (size_x) direction; others: any perpendicular
  double rms_m = 0;      // RMS distance of the explained points to the surface
  double coverage = 0;   // share of the points within tolerance
};

struct ObjectShape {
  std::vector<ShapeFit> primitives;  // salient first; empty when unknown
  double fit = 0;                    // the salient coverage, 0 when unknown
  // The salient box was seen by one side face alone (no top, no side across it): its
  // depth is not measured, only the thickness of that face's noise.
  bool depth_unseen = false;
  // Every candidate the recognizer tried, for diagnostics (kind, coverage, rms).
  std::vector<ShapeFit> candidates;
};

// The support's surface seen around an object's foot: its points in the sensor frame
// (pixels of no object, on the support within its depth noise), each standing for
// `pixels_per_point` image pixels (a strided sample), and the object's own pixel count
// (min_foot_seen_share's base; 0: its points' count).
struct SupportAround {
  std::vector<Vec3> points;
  int pixels_per_point = 1;
  int object_pixels = 0;
};

// Points (and optional unit normals, same size or empty) of one object in the sensor
// frame; `support` is the plane it rests on, normal pointing up (away from the table);
// `around` the support's surface seen around it (empty: no free-space test).
ObjectShape recognize_object_shape(const std::vector<Vec3>& points,
                                   const std::vector<Vec3>& normals, const Plane& support,
                                   const ShapeRecognizerParams& params = {},
                                   const SupportAround& around = {});

// Whether p lies inside the fitted solid grown by `margin` metres on every side
// (sphere, cylinder, cone and torus by their bounding cylinder about the axis).
bool within_shape(const ShapeFit& fit, Vec3 p, double margin);

// The parameters the recognizer's information criterion counts for a fitted shape
// resting on `support` (object_shape_recognizer.cpp, parameter_count): a cylinder whose
// axis is not the support's normal (lying, or tilted on its rim) counts as a lying
// cylinder, 6; a plane, which the recognizer does not fit, as a box, 6.
int fitted_parameter_count(const ShapeFit& fit, const Plane& support);

// The radius the scanner's MLS smooths a point over at depth z with its defaults
// (scanner.cpp smooth_cluster: 1.2 cm, 3 sigma_z, its window of 6 pixels of a camera
// with that focal length): points closer than this share their noise, so they are not
// independent samples.
inline double shared_noise_radius_m(double z, double focal_px, const DepthNoise& noise) {
  return std::max({0.012, 3 * noise.sigma_z(z), 6 * z / focal_px});
}

}  // namespace annex
