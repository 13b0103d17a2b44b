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
  Vec3 axis{0, 0, 1};                // symmetry axis (box: its local z axis; plane: its normal)
  double fit = 1.0;                  // share of the object's points the shape explains, [0, 1]
  // Cone only: the radius at its narrow end, 0 for a pointed cone. A frustum (a cup,
  // a bowl, a lampshade) is a cone whose tip is cut off; `axis` runs from the wide end
  // to the narrow one, so it points down for a cup standing on its foot.
  double narrow_radius_m = 0.0;
  // Plane only: the direction of its size_x side, in the plane; zero when unknown.
  Vec3 x_axis{0, 0, 0};
  bool operator==(const PhysicalPrimitive&) const = default;
};

struct PhysicalObject {
  std::string id;
  std::vector<PhysicalPrimitive> primitives;  // salient first; empty when the shape is unknown
  int point_count = 0;
  double fit = 0.0;  // quality of the salient fit, [0, 1]
  // The support it stands on (PhysicalScene::supports id); empty when unknown.
  std::string support_id;
  // The object whose top it stands on (its id: a box on a box, a jar on a tin); empty
  // when it stands on the support itself. `support_id` stays the support under the stack.
  std::string on_object;
  // Seen only in part (cut by the image border, or too few points to tell its shape):
  // a poor prop, which does not vote unless asked (MatchParams::partial_objects_vote).
  bool partial = false;
  bool operator==(const PhysicalObject&) const = default;
};

// Support plane n.x + d = 0, n a unit normal pointing away from the surface (up).
struct Plane {
  Vec3 normal{0, -1, 0};
  double d = 0.0;
  bool operator==(const Plane&) const = default;
};

// A near-horizontal surface objects stand on: floor, table, shelf, seat, cabinet top.
struct SupportSurface {
  std::string id;  // s1, s2, ...
  Plane plane;
  int point_count = 0;  // its pixels in the frame
  bool operator==(const SupportSurface&) const = default;
};

struct PhysicalScene {
  // The primary support (the first of `supports` when a scan found several; the only
  // one a version-1 scene file holds).
  std::optional<Plane> support;
  std::vector<PhysicalObject> objects;
  std::vector<SupportSurface> supports;  // every support; empty in version-1 files
  bool operator==(const PhysicalScene&) const = default;
};

}  // namespace annex
