#include "annex/runtime/match_report.h"

#include <gtest/gtest.h>

namespace annex {
namespace {

HapticSpec two_object_spec() {
  Primitive body = make_primitive(ShapeKind::cylinder, "body");
  body.dimensions[0].value_m = 0.04;
  body.dimensions[1].value_m = 0.2;
  Primitive ball = make_primitive(ShapeKind::sphere, "ball");
  ball.dimensions[0].value_m = 0.05;
  return {{{"bottle", "", true, 1.0, {body}}, {"orb", "", true, 1.0, {ball}}}};
}

PhysicalScene one_cylinder_scene() {
  PhysicalObject p;
  p.id = "p1";
  p.primitives.push_back({ShapeKind::cylinder, {0.02, 0.2}, {}, {0, -1, 0}, 0.9});
  return {{}, {p}};
}

TEST(MatchReport, ScriptLinesOnePerVirtualObject) {
  const HapticSpec spec = two_object_spec();
  const PhysicalScene scene = one_cylinder_scene();
  const MatchResult r = match_objects(spec, scene);
  // radius 0.5 and height 1, equal weights: 75.
  EXPECT_EQ(format_match_lines(spec, scene, r), "match bottle p1 75.00\nvirtual-only orb\n");
}

TEST(MatchReport, TableShowsEveryFactor) {
  const HapticSpec spec = two_object_spec();
  const PhysicalScene scene = one_cylinder_scene();
  const std::string table = format_vote_table(spec, scene, match_objects(spec, scene));
  EXPECT_NE(table.find("bottle x p1: cylinder 'body'"), std::string::npos) << table;
  EXPECT_NE(table.find("radius"), std::string::npos);
  EXPECT_NE(table.find("ratio 0.500  x w_h 0.500 = 0.250"), std::string::npos) << table;
  EXPECT_NE(table.find("vote = C x w_o 1.000 x w_s 1.000 x sum 0.750 = 75.00"), std::string::npos)
      << table;
  EXPECT_NE(table.find("total vote 75.00"), std::string::npos);
}

TEST(MatchReport, NoSharedShapeSaysSo) {
  const HapticSpec spec = two_object_spec();
  const PhysicalScene scene = one_cylinder_scene();
  const VoteExplanation e = explain_vote(spec.objects[1], scene.objects[0]);
  EXPECT_EQ(format_explanation(spec.objects[1], scene.objects[0], e),
            "orb x p1: no shared shape, vote 0\n");
}

}  // namespace
}  // namespace annex
