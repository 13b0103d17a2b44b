// The plane primitive in the Voter and in fitting a virtual panel onto a real flat
// surface (issue 14 §2).
#include <gtest/gtest.h>

#include <cmath>

#include "annex/common/object_finder.h"
#include "annex/common/prop_fit.h"
#include "annex/common/voter.h"

namespace annex {
namespace {

VirtualObject panel(double x, double y) {
  VirtualObject v;
  v.name = "panel";
  Primitive p = make_primitive(ShapeKind::plane, "face");
  p.dimensions[0].value_m = x;
  p.dimensions[1].value_m = y;
  v.primitives.push_back(p);
  return v;
}

PhysicalObject flat(std::string id, double a, double b) {
  PhysicalObject o;
  o.id = std::move(id);
  PhysicalPrimitive p;
  p.kind = ShapeKind::plane;
  p.dimensions_m = {a, b};
  p.center = {0, 0.8, 1.2};
  p.axis = {0, -1, 0};
  p.x_axis = {1, 0, 0};
  o.primitives.push_back(p);
  return o;
}

TEST(PlaneVote, ComparesSidesSortedBySize) {
  // A 30 x 20 cm panel on a 20 x 30 cm surface: the same rectangle turned.
  const VoteExplanation e = explain_vote(panel(0.3, 0.2), flat("f", 0.2, 0.3));
  EXPECT_NEAR(e.vote, 100, 1e-9);
  ASSERT_EQ(e.terms.size(), 2u);
  EXPECT_EQ(e.terms[0].name, "size_x");
  EXPECT_EQ(e.terms[0].physical_m, 0.3);
  // Half as long, as wide: (0.5 + 1) / 2.
  EXPECT_NEAR(vote(panel(0.3, 0.2), flat("f", 0.6, 0.2)), 75, 1e-9);
}

TEST(PlaneVote, IsItsOwnShapeClass) {
  // A box prop never takes a panel, and a plane never votes for a box's virtual object.
  PhysicalObject box;
  box.id = "b";
  PhysicalPrimitive solid;
  solid.kind = ShapeKind::box;
  solid.dimensions_m = {0.3, 0.2, 0.1};
  box.primitives.push_back(solid);
  EXPECT_EQ(vote(panel(0.3, 0.2), box), 0);
  VirtualObject crate;
  crate.name = "crate";
  crate.primitives.push_back(make_primitive(ShapeKind::box, "body"));
  EXPECT_EQ(vote(crate, flat("f", 0.3, 0.2)), 0);
  // Matching: the panel goes to the surface, the crate to the box.
  HapticSpec spec{{panel(0.3, 0.2), crate}};
  PhysicalScene scene;
  scene.objects = {box, flat("f", 0.3, 0.25)};
  const MatchResult m = match_objects(spec, scene);
  EXPECT_EQ(m.matches[0].physical_index, 1);
  EXPECT_EQ(m.matches[1].physical_index, 0);
}

TEST(PlaneFit, LaysThePanelOnTheSurface) {
  VirtualObject v = panel(0.3, 0.2);
  // The panel's long side along the surface's long side, corners on its corners.
  PropFit fit = fit_to_prop(v.primitives[0], flat("f", 0.6, 0.3).primitives[0]);
  EXPECT_NEAR(fit.scale.x, 2.0, 1e-12);
  EXPECT_NEAR(fit.scale.y, 1.5, 1e-12);
  EXPECT_EQ(fit.scale.z, 1.0);
  EXPECT_TRUE(fit.clamped == false);
  Vec3 corner = fit.world_from_model.apply({0.15, 0.1, 0});
  EXPECT_NEAR(corner.x, 0.3, 1e-9);
  EXPECT_NEAR(std::abs(corner.z - 1.2), 0.15, 1e-9);
  EXPECT_NEAR(corner.y, 0.8, 1e-9);  // on the surface's plane
  // The panel's normal is the surface's.
  const Vec3 o = fit.world_from_model.apply({0, 0, 0});
  const Vec3 n = fit.world_from_model.apply({0, 0, 1}) - o;
  EXPECT_NEAR(n.y, -1, 1e-9);
  // A tall panel (size_y the longer) on a wide surface is turned a quarter.
  v = panel(0.2, 0.3);
  fit = fit_to_prop(v.primitives[0], flat("f", 0.6, 0.3).primitives[0]);
  corner = fit.world_from_model.apply({0.1, 0.15, 0}) - fit.world_from_model.apply({0, 0, 0});
  EXPECT_NEAR(std::abs(corner.x), 0.3, 1e-9);
  EXPECT_NEAR(std::abs(corner.z), 0.15, 1e-9);
}

TEST(ModelFromMesh, ScalesByModelScale) {
  VirtualObject v;
  v.model_scale = 0.01;
  const Vec3 p = model_from_mesh(v).apply({100, 50, -20});
  EXPECT_NEAR(p.x, 1.0, 1e-12);
  EXPECT_NEAR(p.y, 0.5, 1e-12);
  EXPECT_NEAR(p.z, -0.2, 1e-12);
}

TEST(RotationFromAxes, RoundTripsRotate) {
  const Vec3 x = normalized(Vec3{1, 1, 0}), z{0, 0, 1};
  const Vec3 y = cross(z, x);
  const Quat q = rotation_from_axes(x, y, z);
  const Vec3 rx = rotate(q, {1, 0, 0}), ry = rotate(q, {0, 1, 0});
  EXPECT_NEAR(rx.x, x.x, 1e-12);
  EXPECT_NEAR(rx.y, x.y, 1e-12);
  EXPECT_NEAR(ry.x, y.x, 1e-12);
  EXPECT_NEAR(ry.y, y.y, 1e-12);
  // The 180-degree branches.
  const Quat flip = rotation_from_axes({-1, 0, 0}, {0, -1, 0}, {0, 0, 1});
  EXPECT_NEAR(rotate(flip, {1, 0, 0}).x, -1, 1e-12);
  const Quat flip_x = rotation_from_axes({1, 0, 0}, {0, -1, 0}, {0, 0, -1});
  EXPECT_NEAR(rotate(flip_x, {0, 1, 0}).y, -1, 1e-12);
}

}  // namespace
}  // namespace annex
