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
};

// band_m: how far above the support an object's base may be and still stand on it,
// and how close a base must be to a lower object's top to stand on it.
void fit_stacked_objects(std::vector<StackedObject>& objects, const Plane& support,
                         const ShapeRecognizerParams& params, double band_m = 0.03);

// The object whose top each support is. A support that is no furniture (a storage box's
// or a carton's top, found as a support of its own) stays part of the object under it,
// so the cluster holding most of its surface pixels is that object; objects standing
// on the support stand on it, by the support's id, with no geometry re-derived.
// surface_pixels: per support, its surface's pixels; label: cluster index per pixel
// (-1 none). Returns per support the cluster index, or -1 (furniture, the floor).
std::vector<int> objects_under_supports(const std::vector<std::vector<int>>& surface_pixels,
                                        const std::vector<int>& label, double min_share = 0.5);

}  // namespace annex
