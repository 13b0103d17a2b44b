// The spec's per-object minimum vote (min_vote) and the warnings check prints for
// valid specs a newcomer still gets wrong (spec_warnings.h).
#include "annex/formats/spec_warnings.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "annex/formats/haptic_format.h"

namespace annex {
namespace {

constexpr const char* kCup =
    "annex-haptic 1\n"
    "\n"
    "object cup\n"
    "  mesh \"no such/cup.obj\"\n"
    "  annexable yes\n"
    "  priority 1\n"
    "  min_vote 25\n"
    "  primitive body cylinder\n"
    "    priority 1\n"
    "    position 0 0 0\n"
    "    rotation 1 0 0 0\n"
    "    radius 0.04 priority 1 scale 0.5 2\n"
    "    height 0.1 priority 1 scale 0.5 2\n"
    "  end\n"
    "end\n";

TEST(MinVote, ParsesAndWritesBackCanonically) {
  auto spec = parse_haptic(kCup, "cup.haptic");
  ASSERT_TRUE(spec) << spec.error().format();
  EXPECT_EQ(spec->objects[0].min_vote, 25);
  EXPECT_EQ(write_haptic(*spec), kCup);
  // Without the key it is 0 and not written.
  spec->objects[0].min_vote = 0;
  EXPECT_EQ(write_haptic(*spec).find("min_vote"), std::string::npos);
}

TEST(MinVote, OutOfRangeIsAnErrorAtItsValue) {
  std::string text = kCup;
  text.replace(text.find("min_vote 25"), 11, "min_vote 1e9");
  auto spec = parse_haptic(text, "cup.haptic");
  ASSERT_FALSE(spec);
  EXPECT_EQ(spec.error().location.line, 7);
  EXPECT_EQ(spec.error().location.column, 12);
  HapticSpec built;
  built.objects.push_back({"a", "", false, 1.0, {}, -1.0});
  EXPECT_FALSE(validate_haptic(built, "<editor>"));
}

TEST(SpecWarnings, MissingMeshPointsAtItsPath) {
  auto spec = parse_haptic(kCup, "cup.haptic");
  ASSERT_TRUE(spec);
  const auto w = spec_warnings(*spec, kCup, "cup.haptic", std::filesystem::temp_directory_path());
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].location.line, 4);
  EXPECT_EQ(w[0].location.column, 8);
  EXPECT_NE(w[0].message.find("mesh 'no such/cup.obj' does not exist"), std::string::npos)
      << w[0].message;
  EXPECT_EQ(w[0].format().rfind("cup.haptic:4:8: warning: ", 0), 0u) << w[0].format();
}

TEST(SpecWarnings, EmptyAndNothingAnnexable) {
  HapticSpec empty;
  auto w = spec_warnings(empty, "annex-haptic 1\n", "e.haptic", ".");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].message.find("no virtual objects"), std::string::npos);
  const char* text = "annex-haptic 1\n# decoration\nobject dragon\n  annexable no\nend\n";
  auto spec = parse_haptic(text, "d.haptic");
  ASSERT_TRUE(spec);
  w = spec_warnings(*spec, text, "d.haptic", ".");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].message.find("no object is annexable"), std::string::npos);
  EXPECT_EQ(w[0].location.line, 3);
}

}  // namespace
}  // namespace annex
