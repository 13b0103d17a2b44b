#pragma once
// What a scan found: physical objects resting on a support plane, each with its
// salient primitive and any secondary ones (a bottle's body and neck).

#include <optional>
#include <string>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/shape.h"

namespace annex {

// A primitive fitted to (part of) a physical object, in the sensor frame.
struct PhysicalPrimitive {
  ShapeKind kind = ShapeKind::cylinder;
  std::vector<double> dimensions_m;  // dimension_count(kind) entries, dimension_names order
  Vec3 center;                       // centre of the fitted shape
  Vec3 axis{0, 0, 1};                // symmetry axis (box: its local z axis)
  double fit = 1.0;                  // share of the object's points the shape explains, [0, 1]
  bool operator==(const PhysicalPrimitive&) const = default;
};

struct PhysicalObject {
  std::string id;
  std::vector<PhysicalPrimitive> primitives;  // salient first; empty when the shape is unknown
  int point_count = 0;
  double fit = 0.0;  // quality of the salient fit, [0, 1]
  bool operator==(const PhysicalObject&) const = default;
};

// Support plane n.x + d = 0, n a unit normal pointing away from the surface (up).
struct Plane {
  Vec3 normal{0, -1, 0};
  double d = 0.0;
  bool operator==(const Plane&) const = default;
};

struct PhysicalScene {
  std::optional<Plane> support;
  std::vector<PhysicalObject> objects;
  bool operator==(const PhysicalScene&) const = default;
};

}  // namespace annex
