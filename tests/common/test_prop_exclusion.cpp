// The spec's exclude rules on scanned props: the prop's height above its support, the
// first rule that forbids a prop, and the ObjectFinder leaving excluded props out.
#include "annex/common/prop_exclusion.h"

#include <gtest/gtest.h>

#include "annex/common/object_finder.h"

namespace annex {
namespace {

// A table whose surface is y = 0.8 in a y-down camera frame: up is -y.
const Plane kTable{{0, -1, 0}, 0.8};

PhysicalPrimitive upright(ShapeKind kind, std::vector<double> dims, double base_y, double half) {
  PhysicalPrimitive p;
  p.kind = kind;
  p.dimensions_m = std::move(dims);
  p.center = {0.1, base_y - half, 1.0};
  p.axis = {0, -1, 0};
  return p;
}

PhysicalObject object(std::string id, std::vector<PhysicalPrimitive> prims) {
  PhysicalObject o;
  o.id = std::move(id);
  o.primitives = std::move(prims);
  o.fit = 0.9;
  return o;
}

// A virtual object of one sphere.
VirtualObject one_sphere(std::string name, double radius_m) {
  VirtualObject v;
  v.name = std::move(name);
  Primitive p = make_primitive(ShapeKind::sphere, "body");
  p.dimensions[0].value_m = radius_m;
  v.primitives.push_back(p);
  return v;
}

TEST(PropExclusion, HeightAboveTheSupport) {
  // A bottle: a 20 cm body on the table and a 10 cm neck on it.
  const PhysicalObject bottle = object("p1", {upright(ShapeKind::cylinder, {0.04, 0.2}, 0.8, 0.1),
                                              upright(ShapeKind::cone, {0.015, 0.1}, 0.6, 0.05)});
  EXPECT_NEAR(prop_height_m(bottle, kTable), 0.3, 1e-9);
  // A ball of radius 5 cm resting on it.
  const PhysicalObject ball = object("p2", {upright(ShapeKind::sphere, {0.05}, 0.8, 0.05)});
  EXPECT_NEAR(prop_height_m(ball, kTable), 0.1, 1e-9);
  // Without a support: the extent along the salient axis.
  EXPECT_NEAR(prop_height_m(bottle, std::nullopt), 0.3, 1e-9);
  // A box lying on its side (axis horizontal): its sides bound the height.
  PhysicalPrimitive side = upright(ShapeKind::box, {0.3, 0.4, 0.1}, 0.8, 0.25);
  side.axis = {1, 0, 0};
  EXPECT_NEAR(prop_height_m(object("p3", {side}), kTable), 0.25 + 0.25, 1e-9);
}

TEST(PropExclusion, FirstMatchingRuleWins) {
  HapticSpec spec;
  spec.exclude.push_back({"tall", std::nullopt, {{"prop_height", 0.4, std::nullopt}}});
  spec.exclude.push_back({"football", ShapeKind::sphere, {{"radius", 0.11, std::nullopt}}});
  spec.exclude.push_back({"small_tori", ShapeKind::torus, {{"major_radius", std::nullopt, 0.03}}});
  const PhysicalObject lamp_post =
      object("p1", {upright(ShapeKind::cylinder, {0.03, 0.5}, 0.8, 0.25)});
  EXPECT_EQ(excluding_rule(spec, lamp_post, kTable), 0);
  const PhysicalObject football = object("p2", {upright(ShapeKind::sphere, {0.11}, 0.8, 0.11)});
  EXPECT_EQ(excluding_rule(spec, football, kTable), 1);
  const PhysicalObject tennis = object("p3", {upright(ShapeKind::sphere, {0.033}, 0.8, 0.033)});
  EXPECT_FALSE(excluding_rule(spec, tennis, kTable).has_value());
  const PhysicalObject ring = object("p4", {upright(ShapeKind::torus, {0.025, 0.005}, 0.8, 0.005)});
  EXPECT_EQ(excluding_rule(spec, ring, kTable), 2);
  // A rule's ranges all hold on one primitive; an unknown shape matches no rule of a shape.
  EXPECT_FALSE(excluding_rule(spec, object("p5", {}), kTable).has_value());
  EXPECT_EQ(describe_exclude_rule(spec.exclude[1]), "shape sphere, radius min 0.11");
  EXPECT_EQ(describe_exclude_rule(spec.exclude[0]), "shape any, prop_height min 0.4");
}

TEST(PropExclusion, TheObjectFinderLeavesExcludedPropsOut) {
  HapticSpec spec;
  spec.objects.push_back(one_sphere("lamp", 0.11));
  PhysicalScene scene;
  scene.support = kTable;
  scene.objects.push_back(object("p1", {upright(ShapeKind::sphere, {0.11}, 0.8, 0.11)}));
  scene.objects.push_back(object("p2", {upright(ShapeKind::sphere, {0.06}, 0.8, 0.06)}));
  // Without the rule the football is the better prop.
  MatchResult free = match_objects(spec, scene);
  ASSERT_TRUE(free.matches[0].physical_index.has_value());
  EXPECT_EQ(*free.matches[0].physical_index, 0);
  EXPECT_EQ(free.excluded_by, (std::vector<int>{-1, -1}));
  spec.exclude.push_back({"football", ShapeKind::sphere, {{"radius", 0.1, std::nullopt}}});
  MatchResult ruled = match_objects(spec, scene);
  ASSERT_TRUE(ruled.matches[0].physical_index.has_value());
  EXPECT_EQ(*ruled.matches[0].physical_index, 1);
  EXPECT_EQ(ruled.excluded_by, (std::vector<int>{0, -1}));
  // The vote the rule prevented is still explained.
  EXPECT_GT(ruled.table[0][0].vote, ruled.table[0][1].vote);
  // Only excluded props left: the lamp stays virtual-only.
  scene.objects.pop_back();
  EXPECT_FALSE(match_objects(spec, scene).matches[0].physical_index.has_value());
}

TEST(PropExclusion, HeightsFromTheObjectsOwnSupport) {
  // Two supports: the floor 0.75 m below the table (s1, the scene's first) and the
  // table (s2). A 20 cm ball on the table is 20 cm tall, not 95 cm: a rule against
  // props taller than 50 cm leaves it a candidate.
  HapticSpec spec;
  spec.objects.push_back(one_sphere("ball", 0.1));
  spec.exclude.push_back({"tall", std::nullopt, {{"prop_height", 0.5, std::nullopt}}});
  const Plane floor{{0, -1, 0}, 1.55};
  PhysicalScene scene;
  scene.support = floor;
  scene.supports = {{"s1", floor, 9000}, {"s2", kTable, 5000}};
  PhysicalObject on_table = object("p1", {upright(ShapeKind::sphere, {0.1}, 0.8, 0.1)});
  on_table.support_id = "s2";
  scene.objects.push_back(on_table);
  MatchResult r = match_objects(spec, scene);
  EXPECT_EQ(r.excluded_by, (std::vector<int>{-1}));
  ASSERT_TRUE(r.matches[0].physical_index.has_value());
  // Without its support id, the scene's first support measures it (95 cm: excluded).
  scene.objects[0].support_id.clear();
  EXPECT_EQ(match_objects(spec, scene).excluded_by, (std::vector<int>{0}));
}

}  // namespace
}  // namespace annex
