#include "annex/common/object_finder.h"

#include <gtest/gtest.h>

namespace annex {
namespace {

VirtualObject sphere_object(std::string name, double radius, double w_o = 1.0) {
  Primitive p = make_primitive(ShapeKind::sphere, "ball");
  p.dimensions[0].value_m = radius;
  return {std::move(name), "", true, w_o, {p}};
}

PhysicalObject sphere_prop(std::string id, double radius) {
  PhysicalObject o;
  o.id = std::move(id);
  o.primitives.push_back({ShapeKind::sphere, {radius}, {}, {0, 0, 1}, 1.0});
  return o;
}

TEST(ObjectFinder, AssignsEachVirtualObjectItsBestAvailableProp) {
  HapticSpec spec{{sphere_object("small", 0.02), sphere_object("big", 0.10)}};
  PhysicalScene scene{{}, {sphere_prop("p1", 0.10), sphere_prop("p2", 0.02)}};
  const MatchResult r = match_objects(spec, scene);
  ASSERT_EQ(r.matches.size(), 2u);
  EXPECT_EQ(r.matches[0].physical_index, 1);
  EXPECT_EQ(r.matches[1].physical_index, 0);
  EXPECT_DOUBLE_EQ(r.total_vote, 200.0);
  EXPECT_EQ(r.voters, (std::vector<int>{0, 1}));
}

TEST(ObjectFinder, MorePropsThanObjectsAndZeroVotesStayVirtual) {
  Primitive cyl = make_primitive(ShapeKind::cylinder, "body");
  HapticSpec spec{{sphere_object("ball", 0.05), {"saber", "", true, 1.0, {cyl}}}};
  PhysicalScene scene{{}, {sphere_prop("p1", 0.04), sphere_prop("p2", 0.05), sphere_prop("p3", 0.2)}};
  const MatchResult r = match_objects(spec, scene);
  EXPECT_EQ(r.matches[0].physical_index, 1);
  EXPECT_FALSE(r.matches[1].physical_index.has_value()) << "no cylinder in the scene";
}

TEST(ObjectFinder, FewerPropsThanObjectsPriorityDecides) {
  HapticSpec spec{{sphere_object("minor", 0.05, 0.3), sphere_object("major", 0.05, 0.9)}};
  PhysicalScene scene{{}, {sphere_prop("p1", 0.05)}};
  const MatchResult r = match_objects(spec, scene);
  EXPECT_FALSE(r.matches[0].physical_index.has_value());
  EXPECT_EQ(r.matches[1].physical_index, 0);
}

TEST(ObjectFinder, VirtualOnlyObjectsDoNotVote) {
  VirtualObject deco = sphere_object("deco", 0.05);
  deco.annexable = false;
  HapticSpec spec{{deco, sphere_object("ball", 0.05)}};
  PhysicalScene scene{{}, {sphere_prop("p1", 0.05)}};
  const MatchResult r = match_objects(spec, scene);
  EXPECT_EQ(r.voters, (std::vector<int>{1}));
  EXPECT_FALSE(r.matches[0].physical_index.has_value());
  EXPECT_EQ(r.matches[1].physical_index, 0);
}

TEST(ObjectFinder, MinimumVoteThreshold) {
  HapticSpec spec{{sphere_object("ball", 0.05)}};
  PhysicalScene scene{{}, {sphere_prop("p1", 0.02)}};  // vote 40
  EXPECT_EQ(match_objects(spec, scene).matches[0].physical_index, 0);
  MatchParams strict;
  strict.min_vote = 50;
  EXPECT_FALSE(match_objects(spec, scene, strict).matches[0].physical_index.has_value());
}

TEST(ObjectFinder, MatchedObjectsAndTakenPropsSitOut) {
  HapticSpec spec{{sphere_object("a", 0.05), sphere_object("b", 0.05)}};
  PhysicalScene scene{{}, {sphere_prop("p1", 0.05), sphere_prop("p2", 0.04)}};
  // "a" already holds p1: only "b" votes, and only for p2.
  const MatchResult r = match_objects(spec, scene, {}, {true, false}, {true, false});
  EXPECT_EQ(r.voters, (std::vector<int>{1}));
  EXPECT_FALSE(r.matches[0].physical_index.has_value());
  EXPECT_EQ(r.matches[1].physical_index, 1);
}

TEST(ObjectFinder, EmptySceneAndEmptySpec) {
  HapticSpec spec{{sphere_object("a", 0.05)}};
  const MatchResult r = match_objects(spec, PhysicalScene{});
  ASSERT_EQ(r.matches.size(), 1u);
  EXPECT_FALSE(r.matches[0].physical_index.has_value());
  EXPECT_TRUE(match_objects(HapticSpec{}, PhysicalScene{{}, {sphere_prop("p1", 0.1)}}).matches.empty());
}


TEST(ObjectFinder, PartialObjectsVoteOnlyWhenAsked) {
  HapticSpec spec{{sphere_object("a", 0.05)}};
  PhysicalScene scene{{}, {sphere_prop("p1", 0.05), sphere_prop("p2", 0.03)}};
  scene.objects[0].partial = true;  // the better prop, but cut by the image border
  const MatchResult whole_only = match_objects(spec, scene);
  EXPECT_EQ(whole_only.matches[0].physical_index, 1);
  MatchParams params;
  params.partial_objects_vote = true;
  EXPECT_EQ(match_objects(spec, scene, params).matches[0].physical_index, 0);
}

}  // namespace
}  // namespace annex
