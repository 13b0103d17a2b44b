// The shape decision on a body whose side hides under its rim (object_shape_recognizer.cpp,
// frustum_under_rim): a bowl widening up seen from above shows only its top disc, a tin
// of the same size shows its near wall too; the first is a frustum, the second a cylinder.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "annex/runtime/scanner.h"
#include "annex/runtime/synthetic_scene.h"

namespace annex {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The scanned object most of whose pixels show object 0 of a one-object scene seen from
// `distance_m` at `tilt_deg`, the object standing on the camera's aim point.
std::optional<PhysicalObject> scan_one(SyntheticObject object, double distance_m, double tilt_deg) {
  SyntheticSceneParams p;
  p.seed = 11;
  p.object_count = 0;
  p.camera_distance_min_m = p.camera_distance_max_m = distance_m;
  p.camera_tilt_min_deg = p.camera_tilt_max_deg = tilt_deg;
  Result<SyntheticScene> s = generate_scene(p);
  EXPECT_TRUE(s.ok());
  if (!s) return std::nullopt;
  const double t = s->camera_tilt_deg * kPi / 180;
  const Vec3 aim = s->camera_position +
                   Vec3{0, std::cos(t), -std::sin(t)} * (s->camera_position.z / std::sin(t));
  object.center.x = aim.x;
  object.center.y = aim.y;
  s->objects = {object};
  const SyntheticFrame f = render_scene(*s);
  const Result<ScanResult> scan = scan_frame(f.frame);
  EXPECT_TRUE(scan.ok());
  if (!scan) return std::nullopt;
  for (std::size_t k = 0; k < scan->clusters.size(); ++k) {
    int mine = 0;
    for (int i : scan->clusters[k].pixels) mine += f.labels[static_cast<std::size_t>(i)] == 0;
    if (2 * mine > static_cast<int>(scan->clusters[k].pixels.size())) return scan->scene.objects[k];
  }
  return std::nullopt;
}

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
