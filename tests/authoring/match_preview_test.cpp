#include "annex/authoring/match_preview.h"

#include <gtest/gtest.h>

namespace annex::authoring {
namespace {

PhysicalObject cylinder_prop(std::string id, double r, double h) {
  PhysicalObject p;
  p.id = std::move(id);
  p.primitives.push_back({ShapeKind::cylinder, {r, h}, {}, {0, 1, 0}, 0.9});
  return p;
}

TEST(MatchPreview, RanksCandidatesAndShowsTheAssignment) {
  HapticSpec spec;
  VirtualObject bottle;
  bottle.name = "bottle";
  Primitive body = make_primitive(ShapeKind::cylinder, "body");
  body.dimensions[0].value_m = 0.045;
  body.dimensions[1].value_m = 0.2;
  bottle.primitives.push_back(body);
  spec.objects.push_back(bottle);
  VirtualObject sky;
  sky.name = "sky";
  sky.annexable = false;
  spec.objects.push_back(sky);

  PhysicalScene scene;
  scene.objects.push_back(cylinder_prop("thin_pen", 0.005, 0.14));
  scene.objects.push_back(cylinder_prop("wine_bottle", 0.04, 0.2));

  const MatchPreview mp = preview_match(spec, scene);
  ASSERT_EQ(mp.objects.size(), 2u);
  const ObjectPreview& b = mp.objects[0];
  EXPECT_TRUE(b.voted);
  ASSERT_EQ(b.ranked.size(), 2u);
  EXPECT_EQ(b.ranked[0].id, "wine_bottle");
  EXPECT_GT(b.ranked[0].explanation.vote, b.ranked[1].explanation.vote);
  ASSERT_EQ(b.ranked[0].explanation.terms.size(), 2u);
  EXPECT_EQ(b.ranked[0].explanation.terms[0].name, "radius");
  ASSERT_TRUE(b.assigned.has_value());
  EXPECT_EQ(b.assigned_id, "wine_bottle");
  EXPECT_NEAR(b.assigned_vote, b.ranked[0].explanation.vote, 1e-9);
  EXPECT_NEAR(mp.total_vote, b.assigned_vote, 1e-9);
  EXPECT_FALSE(mp.objects[1].voted);
  EXPECT_FALSE(mp.objects[1].assigned.has_value());
}

TEST(MatchPreview, NoSharedShapeStaysVirtualOnly) {
  HapticSpec spec;
  VirtualObject ball;
  ball.name = "ball";
  ball.primitives.push_back(make_primitive(ShapeKind::sphere, "ball"));
  spec.objects.push_back(ball);
  PhysicalScene scene;
  scene.objects.push_back(cylinder_prop("can", 0.033, 0.12));
  const MatchPreview mp = preview_match(spec, scene);
  ASSERT_EQ(mp.objects.size(), 1u);
  EXPECT_TRUE(mp.objects[0].voted);
  EXPECT_FALSE(mp.objects[0].assigned.has_value());
  EXPECT_EQ(mp.objects[0].ranked[0].explanation.vote, 0.0);
}

// The spec's exclude rules: the excluded prop ranks last with its rule, greyed in the
// panel, and the next best prop is assigned.
TEST(MatchPreview, ExcludedPropsCarryTheirRule) {
  HapticSpec spec;
  VirtualObject bottle;
  bottle.name = "bottle";
  Primitive body = make_primitive(ShapeKind::cylinder, "body");
  body.dimensions[0].value_m = 0.045;
  body.dimensions[1].value_m = 0.2;
  bottle.primitives.push_back(body);
  spec.objects.push_back(bottle);
  spec.exclude.push_back({"wide", ShapeKind::cylinder, {{"radius", 0.03, std::nullopt}}});

  PhysicalScene scene;
  scene.objects.push_back(cylinder_prop("wine_bottle", 0.04, 0.2));
  scene.objects.push_back(cylinder_prop("thin_pen", 0.005, 0.14));
  const MatchPreview mp = preview_match(spec, scene);
  const ObjectPreview& b = mp.objects[0];
  ASSERT_EQ(b.ranked.size(), 2u);
  EXPECT_EQ(b.ranked[0].id, "thin_pen");
  EXPECT_TRUE(b.ranked[0].excluded_by.empty());
  EXPECT_EQ(b.ranked[1].id, "wine_bottle");
  EXPECT_EQ(b.ranked[1].excluded_by, "wide: shape cylinder, radius min 0.03");
  // Its vote is still shown: higher than the pen's, but not assigned.
  EXPECT_GT(b.ranked[1].explanation.vote, b.ranked[0].explanation.vote);
  ASSERT_TRUE(b.assigned.has_value());
  EXPECT_EQ(b.assigned_id, "thin_pen");
}

}  // namespace
}  // namespace annex::authoring
