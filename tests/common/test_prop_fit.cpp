#include "annex/common/prop_fit.h"

#include <gtest/gtest.h>

namespace annex {
namespace {

void expect_near(Vec3 a, Vec3 b, double tol = 1e-12) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

Primitive bottle_body() {
  Primitive p = make_primitive(ShapeKind::cylinder, "body");
  p.dimensions[0] = {0.04, 1, 0.5, 1.5};  // radius
  p.dimensions[1] = {0.20, 1, 0.8, 1.2};  // height
  // On a Y-up model: the cylinder's axis (+Z) turned onto +Y, its centre 10 cm up.
  p.pose = {{0, 0.1, 0}, rotation_from_z({0, 1, 0})};
  return p;
}

TEST(PropFit, ScalesPerDimensionAndClampsToLimits) {
  const PhysicalPrimitive prop{ShapeKind::cylinder, {0.05, 0.30}, {0.2, -0.1, 1.0}, {0, -1, 0}, 1};
  const PropFit fit = fit_to_prop(bottle_body(), prop);
  expect_near(fit.wanted_scale, {1.25, 1.25, 1.5});
  expect_near(fit.scale, {1.25, 1.25, 1.2});  // height clamped to max 1.2
  EXPECT_TRUE(fit.clamped);
}

TEST(PropFit, PrimitiveCentreAndAxisLandOnTheProp) {
  const PhysicalPrimitive prop{ShapeKind::cylinder, {0.04, 0.20}, {0.2, -0.1, 1.0}, {0, -1, 0}, 1};
  const PropFit fit = fit_to_prop(bottle_body(), prop);
  EXPECT_FALSE(fit.clamped);
  // The body's centre (model 0, 0.1, 0) goes to the prop's centre...
  expect_near(fit.world_from_model.apply({0, 0.1, 0}), {0.2, -0.1, 1.0});
  // ...and the top of the body (model +Y) goes along the prop's axis (sensor -Y, up).
  expect_near(fit.world_from_model.apply({0, 0.2, 0}), {0.2, -0.2, 1.0});
}

TEST(PropFit, HeightScaleStretchesAlongTheAxis) {
  Primitive body = bottle_body();
  body.dimensions[1].max_scale = 2.0;
  const PhysicalPrimitive prop{ShapeKind::cylinder, {0.04, 0.40}, {0, 0, 1}, {0, -1, 0}, 1};
  const PropFit fit = fit_to_prop(body, prop);
  // Model top of body, 0.1 m above the centre, ends 0.2 m above the prop's centre.
  expect_near(fit.world_from_model.apply({0, 0.2, 0}), {0, -0.2, 1});
  // A point on the rim keeps its radius (radius scale 1).
  const Vec3 rim = fit.world_from_model.apply({0.04, 0.1, 0});
  EXPECT_NEAR(norm(rim - Vec3{0, 0, 1}), 0.04, 1e-12);
}

TEST(PropFit, BoxSidesPairBySize) {
  Primitive box = make_primitive(ShapeKind::box, "crate");
  box.dimensions[0].value_m = 0.1;
  box.dimensions[1].value_m = 0.2;
  box.dimensions[2].value_m = 0.3;
  const PhysicalPrimitive prop{ShapeKind::box, {0.6, 0.15, 0.3}, {}, {0, 0, 1}, 1};
  const PropFit fit = fit_to_prop(box, prop);
  expect_near(fit.wanted_scale, {1.5, 1.5, 2.0});
}

TEST(PropFit, RigidInverse) {
  const Pose pose{{0.3, -0.2, 0.5}, normalized(Quat{0.9, 0.1, -0.3, 0.2})};
  const Affine id = affine_from_pose(pose) * inverse_rigid(pose);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(id.m[i * 4 + j], (i == j) ? 1.0 : 0.0, 1e-12);
}

TEST(PropFit, PreviewScaleAtLimits) {
  const Primitive body = bottle_body();
  expect_near(local_scale_for(body, {body.dimensions[0].min_scale, body.dimensions[1].min_scale}),
              {0.5, 0.5, 0.8});
  Primitive ball = make_primitive(ShapeKind::sphere, "b");
  expect_near(local_scale_for(ball, {2.0}), {2, 2, 2});
}

}  // namespace
}  // namespace annex
