#pragma once
// Objects standing on objects (a box on a box, a jar on a tin): an object whose lowest
// points sit on another object's top, not on the support, rests on that top face, and
// its shapes are fitted on that face as their plane (so its height starts there, not at
// the table). Private to the scanner.

#include <vector>

#include "annex/common/physical_scene.h"
#include "annex/runtime/object_shape_recognizer.h"

namespace annex {

struct StackedObject {
  std::vector<Vec3> points, normals;  // smoothed points of one object, its normals
  ObjectShape shape;                  // fitted on the support; refitted when stacked
  int rests_on = -1;                  // index of the object below, -1 for the support
  int part_of = -1;  // index of the object it rises from (a neck on a shoulder), -1 none
};

// What tells a part rising from an object's top (a bottle's neck on its shoulder) from an
// object standing on a level top (a tin on a tin).
struct NeckParams {
  // Only an object at most this share of the lower one's width across its foot: one as
  // wide as the top has no top around it to look at, only the lower object's wall.
  double max_width_share = 0.6;
  // The lower object's surface just beyond the foot falls away from it more steeply
  // than this: a shoulder, not a lid (a lid is level to the noise).
  double min_slope_deg = 20;
  // ... and less steeply than this: beyond a lid's edge the lower object's wall is
  // upright.
  double max_slope_deg = 75;
  // A neck rises on its body's axis: its foot's centre within this share of the lower
  // object's width (its points' reach from that centre) of the lower shape's axis.
  double max_off_axis_share = 0.1;
  // A direction falls away when its least-squares fall is this many standard errors
  // clear of level (noise alone makes a few points seem to slope).
  double min_fall_t = 3;
  // That surface: the lower object's points from this far beyond the foot's reach ...
  double ring_gap_m = 0.003;
  // ... over at most this width (and half the way to the lower object's edge), when at
  // least ring_min_points of them are seen.
  double ring_width_m = 0.015;
  int ring_min_points = 12;
};

// How far above the support an object's base may be and still stand on it (the
// default band_m below).
inline constexpr double kStackBand_m = 0.03;

// band_m: how far above the support an object's base may be and still stand on it,
// and how close a base must be to a lower object's top to stand on it.
// An object rising from a slope of the one below (NeckParams) is not refitted: it is
// marked part_of that object, which the caller merges it into.
void fit_stacked_objects(std::vector<StackedObject>& objects, const Plane& support,
                         const ShapeRecognizerParams& params, double band_m = kStackBand_m,
                         const NeckParams& neck = {});

// The object whose top each support is. A support that is no furniture (a storage box's
// or a carton's top, found as a support of its own) stays part of the object under it,
// so the cluster holding most of its surface pixels is that object; objects standing
// on the support stand on it, by the support's id, with no geometry re-derived.
// surface_pixels: per support, its surface's pixels; label: cluster index per pixel
// (-1 none). Returns per support the cluster index, or -1 (furniture, the floor).
std::vector<int> objects_under_supports(const std::vector<std::vector<int>>& surface_pixels,
                                        const std::vector<int>& label, double min_share = 0.5);

}  // namespace annex
