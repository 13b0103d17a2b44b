#include "annex/common/voter.h"

#include <gtest/gtest.h>

namespace annex {
namespace {

Primitive prim(ShapeKind kind, std::string name, double w_s, std::vector<double> dims,
               std::vector<double> weights = {}) {
  Primitive p = make_primitive(kind, std::move(name));
  p.weight = w_s;
  for (size_t i = 0; i < dims.size(); ++i) {
    p.dimensions[i].value_m = dims[i];
    p.dimensions[i].weight = i < weights.size() ? weights[i] : 1.0;
  }
  return p;
}

PhysicalObject phys(std::string id, std::vector<PhysicalPrimitive> prims) {
  PhysicalObject p;
  p.id = std::move(id);
  p.primitives = std::move(prims);
  return p;
}

PhysicalPrimitive pp(ShapeKind kind, std::vector<double> dims) {
  PhysicalPrimitive p;
  p.kind = kind;
  p.dimensions_m = std::move(dims);
  return p;
}

TEST(Voter, IdenticalShapeAndSizeGivesC) {
  VirtualObject v{"bottle", "", true, 1.0, {prim(ShapeKind::cylinder, "body", 1.0, {0.04, 0.2})}};
  EXPECT_DOUBLE_EQ(vote(v, phys("p", {pp(ShapeKind::cylinder, {0.04, 0.2})})), 100.0);
}

TEST(Voter, FollowsThePaperEquation) {
  // x = C * w_o * w_s * sum(min/max * w_h), w_h normalised to sum 1:
  // radius 0.03 vs 0.04 -> 0.75, weight 0.6/(0.6+0.2) = 0.75
  // height 0.20 vs 0.10 -> 0.5,  weight 0.2/0.8 = 0.25
  VirtualObject v{"bottle", "", true, 0.8,
                  {prim(ShapeKind::cylinder, "body", 0.5, {0.04, 0.10}, {0.6, 0.2})}};
  const VoteExplanation e = explain_vote(v, phys("p", {pp(ShapeKind::cylinder, {0.03, 0.20})}));
  const double sum = 0.75 * 0.75 + 0.5 * 0.25;
  EXPECT_NEAR(e.vote, 100.0 * 0.8 * 0.5 * sum, 1e-9);
  ASSERT_EQ(e.terms.size(), 2u);
  EXPECT_EQ(e.terms[0].name, "radius");
  EXPECT_NEAR(e.terms[0].ratio, 0.75, 1e-12);
  EXPECT_NEAR(e.terms[0].weight, 0.75, 1e-12);
  EXPECT_NEAR(e.terms[1].ratio, 0.5, 1e-12);
  EXPECT_NEAR(e.dimension_sum, sum, 1e-12);
  EXPECT_EQ(e.virtual_primitive, 0);
  EXPECT_EQ(e.physical_primitive, 0);
}

TEST(Voter, RatioIsUnitFree) {
  VirtualObject v{"b", "", true, 1.0, {prim(ShapeKind::sphere, "s", 1.0, {0.05})}};
  VirtualObject v_mm{"b", "", true, 1.0, {prim(ShapeKind::sphere, "s", 1.0, {50.0})}};
  EXPECT_NEAR(vote(v, phys("p", {pp(ShapeKind::sphere, {0.02})})),
              vote(v_mm, phys("p", {pp(ShapeKind::sphere, {20.0})})), 1e-9);
  EXPECT_NEAR(vote(v, phys("p", {pp(ShapeKind::sphere, {0.02})})), 40.0, 1e-9);
}

TEST(Voter, NoSharedShapeVotesZero) {
  VirtualObject v{"ball", "", true, 1.0, {prim(ShapeKind::sphere, "s", 1.0, {0.05})}};
  const VoteExplanation e = explain_vote(v, phys("p", {pp(ShapeKind::cylinder, {0.05, 0.1})}));
  EXPECT_EQ(e.vote, 0.0);
  EXPECT_EQ(e.virtual_primitive, -1);
  EXPECT_EQ(vote(v, phys("unknown", {})), 0.0);
}

TEST(Voter, HighestPriorityPrimitiveSharedWins) {
  // The cone has the higher w_s, so it decides even though the cylinder would vote more.
  VirtualObject v{"bottle", "", true, 1.0,
                  {prim(ShapeKind::cylinder, "body", 0.5, {0.04, 0.2}),
                   prim(ShapeKind::cone, "neck", 0.9, {0.02, 0.08})}};
  const PhysicalObject p = phys("p", {pp(ShapeKind::cylinder, {0.04, 0.2}),
                                      pp(ShapeKind::cone, {0.04, 0.04})});
  const VoteExplanation e = explain_vote(v, p);
  EXPECT_EQ(e.virtual_primitive, 1);
  EXPECT_EQ(e.physical_primitive, 1);
  EXPECT_NEAR(e.vote, 90.0 * (0.5 * 0.5 + 0.5 * 0.5), 1e-9);
  // Without a cone on the prop the cylinder is the first shared shape.
  const VoteExplanation body = explain_vote(v, phys("q", {pp(ShapeKind::cylinder, {0.04, 0.2})}));
  EXPECT_EQ(body.virtual_primitive, 0);
  EXPECT_NEAR(body.vote, 50.0, 1e-9);
}

TEST(Voter, EqualPrioritiesFollowAuthoredOrder) {
  VirtualObject v{"x", "", true, 1.0,
                  {prim(ShapeKind::cylinder, "a", 0.7, {0.04, 0.2}),
                   prim(ShapeKind::sphere, "b", 0.7, {0.04}),
                   prim(ShapeKind::cone, "c", 0.9, {0.04, 0.1})}};
  EXPECT_EQ(primitive_priority_order(v), (std::vector<int>{2, 0, 1}));
}

TEST(Voter, BestOfSeveralPhysicalPrimitivesOfTheSameShape) {
  VirtualObject v{"x", "", true, 1.0, {prim(ShapeKind::cylinder, "a", 1.0, {0.04, 0.2})}};
  const PhysicalObject p = phys("p", {pp(ShapeKind::cylinder, {0.01, 0.2}),
                                      pp(ShapeKind::cylinder, {0.04, 0.2})});
  const VoteExplanation e = explain_vote(v, p);
  EXPECT_EQ(e.physical_primitive, 1);
  EXPECT_DOUBLE_EQ(e.vote, 100.0);
}

TEST(Voter, BoxesCompareSortedSizes) {
  // A scan cannot tell which side of a box the author called x: 10x20x30 cm equals 30x10x20.
  VirtualObject v{"crate", "", true, 1.0, {prim(ShapeKind::box, "b", 1.0, {0.1, 0.2, 0.3})}};
  EXPECT_NEAR(vote(v, phys("p", {pp(ShapeKind::box, {0.3, 0.1, 0.2})})), 100.0, 1e-9);
  // The weight travels with its virtual dimension: only size_z (0.3) matters.
  VirtualObject w{"crate", "", true, 1.0,
                  {prim(ShapeKind::box, "b", 1.0, {0.1, 0.2, 0.3}, {0, 0, 1})}};
  const VoteExplanation e = explain_vote(w, phys("p", {pp(ShapeKind::box, {0.15, 0.1, 0.2})}));
  EXPECT_NEAR(e.vote, 100.0 * 0.2 / 0.3, 1e-9);
  EXPECT_EQ(e.terms[0].name, "size_z");
}

TEST(Voter, AllZeroDimensionWeightsMeanShapeOnly) {
  VirtualObject v{"x", "", true, 0.5,
                  {prim(ShapeKind::cylinder, "a", 1.0, {0.04, 0.2}, {0.0, 0.0})}};
  // Equal weights then: (0.5 + 1) / 2.
  EXPECT_NEAR(vote(v, phys("p", {pp(ShapeKind::cylinder, {0.02, 0.2})})), 50.0 * 0.75, 1e-9);
}

TEST(Voter, ZeroPrioritiesVoteZero) {
  VirtualObject v{"x", "", true, 0.0, {prim(ShapeKind::sphere, "a", 1.0, {0.04})}};
  EXPECT_EQ(vote(v, phys("p", {pp(ShapeKind::sphere, {0.04})})), 0.0);
}

TEST(Voter, CustomC) {
  VirtualObject v{"x", "", true, 1.0, {prim(ShapeKind::torus, "a", 1.0, {0.05, 0.01})}};
  EXPECT_NEAR(vote(v, phys("p", {pp(ShapeKind::torus, {0.05, 0.02})}), VoteParams{1.0}), 0.75, 1e-12);
}

}  // namespace
}  // namespace annex
