// The `.haptic` exclude rules (props never to annex): reading, the canonical writer's
// round trip, validate_haptic, and the errors with their line and column.
#include <gtest/gtest.h>

#include <string>

#include "annex/formats/haptic_format.h"

namespace annex {
namespace {

constexpr const char* kObject =
    "annex-haptic 1\n"
    "object lamp\n"
    "  primitive shade sphere\n"
    "    radius 0.05\n"
    "  end\n"
    "end\n";

std::string with(const std::string& rules) {
  return std::string(kObject) + rules;
}

TEST(HapticExclude, ReadsShapesAndRanges) {
  const auto spec = parse_haptic(with("exclude tall   # nothing taller than 40 cm\n"
                                      "  prop_height min 0.4\n"
                                      "end\n"
                                      "exclude football\n"
                                      "  shape sphere\n"
                                      "  radius min 0.11\n"
                                      "end\n"
                                      "exclude mid_boxes\n"
                                      "  size_z max 0.3 min 0.1\n"
                                      "  shape box\n"
                                      "end\n"),
                                 "x.haptic");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  ASSERT_EQ(spec->exclude.size(), 3u);
  const ExcludeRule& tall = spec->exclude[0];
  EXPECT_EQ(tall.name, "tall");
  EXPECT_FALSE(tall.shape.has_value());
  ASSERT_EQ(tall.ranges.size(), 1u);
  EXPECT_EQ(tall.ranges[0].dimension, "prop_height");
  EXPECT_EQ(tall.ranges[0].min_m, 0.4);
  EXPECT_FALSE(tall.ranges[0].max_m.has_value());
  EXPECT_EQ(spec->exclude[1].shape, ShapeKind::sphere);
  EXPECT_EQ(spec->exclude[1].ranges[0].dimension, "radius");
  const ExcludeRule& boxes = spec->exclude[2];
  EXPECT_EQ(boxes.shape, ShapeKind::box);  // shape after the range: keys in any order
  EXPECT_EQ(boxes.ranges[0].min_m, 0.1);
  EXPECT_EQ(boxes.ranges[0].max_m, 0.3);
}

TEST(HapticExclude, OlderFilesHaveNoRules) {
  const auto spec = parse_haptic(kObject, "x.haptic");
  ASSERT_TRUE(spec.ok());
  EXPECT_TRUE(spec->exclude.empty());
  EXPECT_EQ(write_haptic(*spec).find("exclude"), std::string::npos);
}

TEST(HapticExclude, CanonicalFormRoundTrips) {
  const std::string canonical = write_haptic(*parse_haptic(kObject, "x")) +
                                "\n"
                                "exclude tall\n"
                                "  shape any\n"
                                "  prop_height min 0.4\n"
                                "end\n"
                                "\n"
                                "exclude hot_mugs\n"
                                "  shape cylinder\n"
                                "  radius min 0.03 max 0.05\n"
                                "  height max 0.12\n"
                                "end\n";
  const auto spec = parse_haptic(canonical, "c.haptic");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  EXPECT_EQ(write_haptic(*spec), canonical);
  EXPECT_TRUE(validate_haptic(*spec).ok());
  EXPECT_EQ(*parse_haptic(write_haptic(*spec), "again"), *spec);
}

struct BadRule {
  const char* rules;
  int line, column;  // 0: the end of the input
  const char* message;
};

TEST(HapticExclude, ErrorsNameLineAndColumn) {
  // Rules start at line 7.
  const BadRule cases[] = {
      {"exclude a\n  radius min 0.1\nend\n", 8, 3, "'radius' needs a shape"},
      {"exclude a\n  shape box\n  radius min 0.1\nend\n", 9, 3,
       "'radius' is not a dimension of a box"},
      {"exclude a\nend\n", 8, 1, "names neither a shape nor a size range"},
      {"exclude a\n  prop_height\nend\n", 8, 14, "expected 'min METRES' and/or 'max METRES'"},
      {"exclude a\n  prop_height min 0.5 max 0.2\nend\n", 8, 27,
       "minimum 0.5 is larger than maximum 0.2"},
      {"exclude a\n  prop_height min -1\nend\n", 8, 19, "finite metres >= 0"},
      {"exclude a\n  prop_height min 0.1 min 0.2\nend\n", 8, 23, "duplicate key 'min'"},
      {"exclude a\n  prop_hieght min 0.1\nend\n", 8, 3, "did you mean 'prop_height'"},
      {"exclude a\n  shape ball\nend\n", 8, 9, "unknown shape 'ball'"},
      {"exclude a\n  shape any\n  shape box\nend\n", 9, 3, "duplicate key 'shape'"},
      {"exclude a\n  shape any\n  prop_height max 1\n", 0, 0, "missing 'end' for exclude rule 'a'"},
      {"exclude a\n  shape any\nobject b\n", 9, 1, "missing 'end' for exclude rule 'a'"},
      {"exclude a\n  shape torus\nend\nexclude a\n  shape box\nend\n", 10, 9,
       "duplicate exclude rule name 'a' (first at line 7)"},
      {"exclude 9a\n  shape box\nend\n", 7, 9, "exclude rule name"},
  };
  for (const BadRule& c : cases) {
    const std::string text = with(c.rules);
    const auto spec = parse_haptic(text, "bad.haptic");
    ASSERT_FALSE(spec.ok()) << c.rules;
    const Error& e = spec.error();
    EXPECT_NE(e.message.find(c.message), std::string::npos) << e.format();
    if (c.line > 0) {
      EXPECT_EQ(e.location.line, c.line) << e.format();
      EXPECT_EQ(e.location.column, c.column) << e.format();
    }
  }
}

TEST(HapticExclude, ValidateRefusesWhatCouldNotBeRead) {
  HapticSpec spec = *parse_haptic(kObject, "x");
  spec.exclude.push_back({"cones", ShapeKind::cone, {{"major_radius", 0.1, std::nullopt}}});
  Status st = validate_haptic(spec, "doc.haptic");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("not a dimension of a cone"), std::string::npos)
      << st.error().format();
  spec.exclude[0].ranges = {{"radius", std::nullopt, std::nullopt}};
  st = validate_haptic(spec, "doc.haptic");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("needs 'min' or 'max'"), std::string::npos);
  spec.exclude[0].ranges = {{"radius", 0.2, 0.1}};
  EXPECT_FALSE(validate_haptic(spec).ok());
  spec.exclude[0].ranges = {{"radius", 0.1, 0.2}, {"radius", 0.3, std::nullopt}};
  EXPECT_FALSE(validate_haptic(spec).ok());
  spec.exclude[0].ranges = {{"radius", 0.1, 0.2}};
  EXPECT_TRUE(validate_haptic(spec).ok());
  spec.exclude.push_back({"everything", std::nullopt, {}});
  EXPECT_FALSE(validate_haptic(spec).ok());
}

}  // namespace
}  // namespace annex
