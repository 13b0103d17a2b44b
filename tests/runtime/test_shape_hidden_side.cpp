// The shape decision on a body whose side hides under its rim (object_shape_recognizer.cpp,
// frustum_under_rim): a bowl widening up seen from above shows only its top disc, a tin
// of the same size shows its near wall too; the first is a frustum, the second a cylinder.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "annex/runtime/scanner.h"
#include "annex/runtime/synthetic_scene.h"
#include "scan_one.h"

namespace annex {
namespace {

SyntheticObject bowl(double rim_m, double height_m, double foot_m) {
  SyntheticObject o = resting_object(ShapeKind::cone, {rim_m, height_m}, 0, 0);
  o.apex_down = true;
  o.narrow_radius_m = foot_m;
  return o;
}

TEST(ShapeHiddenSide, BowlSeenFromAboveIsAFrustumWideningUp) {
  // Seen from 0.9 m at 50 degrees and from 1.2 m at 60: the side faces down, under the rim.
  for (const auto& [distance, tilt] : {std::pair{0.9, 50.0}, std::pair{1.2, 60.0}}) {
    const std::optional<PhysicalObject> o = scan_one(bowl(0.1, 0.045, 0.05), distance, tilt);
    ASSERT_TRUE(o && !o->primitives.empty()) << distance;
    const PhysicalPrimitive& p = o->primitives[0];
    EXPECT_EQ(p.kind, ShapeKind::cone) << distance << " m, " << tilt << " degrees";
    if (p.kind != ShapeKind::cone) continue;
    EXPECT_GT(p.axis.y, 0) << "wide end up: the axis, wide to narrow, points down (camera y down)";
    EXPECT_NEAR(p.dimensions_m[0], 0.1, 0.006);
    EXPECT_NEAR(p.dimensions_m[1], 0.045, 0.006);
    EXPECT_GT(p.narrow_radius_m, 0.03);  // a stable foot
    EXPECT_LT(p.narrow_radius_m, 0.1);
  }
}

TEST(ShapeHiddenSide, TinOfTheSameSizeShowsItsWallAndIsACylinder) {
  for (const auto& [distance, tilt] : {std::pair{0.9, 50.0}, std::pair{1.2, 60.0}}) {
    const std::optional<PhysicalObject> o =
        scan_one(resting_object(ShapeKind::cylinder, {0.1, 0.045}, 0, 0), distance, tilt);
    ASSERT_TRUE(o && !o->primitives.empty()) << distance;
    EXPECT_EQ(o->primitives[0].kind, ShapeKind::cylinder) << distance << " m, " << tilt << " degrees";
  }
}

TEST(ShapeHiddenSide, TallCanSeenFromAboveStaysACylinder) {
  const std::optional<PhysicalObject> o =
      scan_one(resting_object(ShapeKind::cylinder, {0.035, 0.12}, 0, 0), 0.8, 60);
  ASSERT_TRUE(o && !o->primitives.empty());
  EXPECT_EQ(o->primitives[0].kind, ShapeKind::cylinder);
}

}  // namespace
}  // namespace annex
