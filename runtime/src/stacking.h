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

}  // namespace annex
