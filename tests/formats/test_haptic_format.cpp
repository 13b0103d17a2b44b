#include "annex/formats/haptic_format.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "annex/formats/file_io.h"
#include "format_test_util.h"

namespace annex {
namespace {

constexpr const char* kBottle =
    "annex-haptic 1\n"
    "object bottle\n"
    "  mesh models/bottle.obj\n"
    "  primitive body cylinder\n"
    "    radius 0.045 priority 0.8 scale 0.7 1.4\n"
    "    height 0.22\n"
    "  end\n"
    "end\n";

TEST(HapticFormat, ParsesTheExampleWithDefaults) {
  auto spec = parse_haptic(kBottle, "b.haptic");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  ASSERT_EQ(spec->objects.size(), 1u);
  const VirtualObject& o = spec->objects[0];
  EXPECT_EQ(o.name, "bottle");
  EXPECT_EQ(o.mesh, "models/bottle.obj");
  EXPECT_TRUE(o.annexable);
  EXPECT_EQ(o.priority, 1.0);
  ASSERT_EQ(o.primitives.size(), 1u);
  const Primitive& p = o.primitives[0];
  EXPECT_EQ(p.name, "body");
  EXPECT_EQ(p.kind, ShapeKind::cylinder);
  EXPECT_EQ(p.weight, 1.0);
  EXPECT_EQ(p.pose, Pose{});
  ASSERT_EQ(p.dimensions.size(), 2u);
  EXPECT_EQ(p.dimensions[0], (Dimension{0.045, 0.8, 0.7, 1.4}));
  EXPECT_EQ(p.dimensions[1], (Dimension{0.22, 1.0, 0.5, 2.0}));
}

TEST(HapticFormat, ChampagneGoldenReadsAndWritesBackByteForByte) {
  const std::string text = test::slurp(test::data_path("champagne.haptic"));
  auto spec = parse_haptic(text, "champagne.haptic");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  ASSERT_EQ(spec->objects.size(), 1u);
  ASSERT_EQ(spec->objects[0].primitives.size(), 2u);
  EXPECT_EQ(spec->objects[0].primitives[1].kind, ShapeKind::cone);
  EXPECT_EQ(spec->objects[0].primitives[1].dimensions[0].value_m, 0.015);
  EXPECT_EQ(write_haptic(*spec), text);
}

TEST(HapticFormat, AllShapesGoldenReadsAndWritesBackByteForByte) {
  const std::string text = test::slurp(test::data_path("all_shapes.haptic"));
  auto spec = parse_haptic(text, "all_shapes.haptic");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  ASSERT_EQ(spec->objects.size(), 4u);
  EXPECT_EQ(spec->objects[0].mesh, "models/wine glass.obj");
  EXPECT_EQ(spec->objects[2].mesh, "models/crate \"big\" #1.obj");
  EXPECT_EQ(spec->objects[3].mesh, "models\\scenery\\backdrop.obj");
  EXPECT_FALSE(spec->objects[3].annexable);
  EXPECT_TRUE(spec->objects[3].primitives.empty());
  EXPECT_EQ(spec->objects[1].primitives[0].kind, ShapeKind::torus);
  EXPECT_EQ(spec->objects[2].primitives[0].kind, ShapeKind::box);
  EXPECT_EQ(write_haptic(*spec), text);
  EXPECT_TRUE(validate_haptic(*spec).ok());
}

TEST(HapticFormat, HandWrittenFileCanonicalises) {
  auto spec = parse_haptic(test::slurp(test::data_path("commented.haptic")), "commented.haptic");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  EXPECT_EQ(write_haptic(*spec), test::slurp(test::data_path("commented.expected.haptic")));
}

TEST(HapticFormat, AcceptsCrlfBomAndCommentsEverywhere) {
  const std::string text =
      "\xEF\xBB\xBF# leading comment\r\n"
      "\r\n"
      "annex-haptic 1#no space needed before a comment\r\n"
      "object a # c\r\n"
      "  annexable no\r\n"
      "end\r\n";
  auto spec = parse_haptic(text, "x");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  ASSERT_EQ(spec->objects.size(), 1u);
  EXPECT_FALSE(spec->objects[0].annexable);
}

TEST(HapticFormat, NormalisesNearlyUnitRotationAndKeepsUnitOnesExactly) {
  const std::string text =
      "annex-haptic 1\nobject a\n primitive s sphere\n  radius 1\n"
      "  rotation 1.0005 0 0 0\n end\nend\n";
  auto spec = parse_haptic(text, "x");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  EXPECT_EQ(spec->objects[0].primitives[0].pose.rotation, (Quat{1, 0, 0, 0}));
}

TEST(HapticFormat, NegativeZeroReadsAsZero) {
  auto spec = parse_haptic(
      "annex-haptic 1\nobject a\n primitive s sphere\n  radius 1\n  position -0 0 -0.0\n "
      "end\nend\n",
      "x");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  EXPECT_FALSE(std::signbit(spec->objects[0].primitives[0].pose.position.x));
  EXPECT_NE(write_haptic(*spec).find("position 0 0 0\n"), std::string::npos);
}

TEST(HapticFormat, WarnsWhenAllDimensionPrioritiesAreZero) {
  std::vector<Diagnostic> warnings;
  auto spec = parse_haptic(
      "annex-haptic 1\nobject a\n  primitive s sphere\n    radius 1 priority 0\n  end\nend\n",
      "w.haptic", &warnings);
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].format(),
            "w.haptic:3:1: warning: all dimension priorities of sphere 's' are 0: only the shape "
            "counts");
}

using test::BadInput;

std::string obj(const std::string& body) {
  return "annex-haptic 1\nobject a\n" + body + "end\n";
}
std::string prim(const std::string& body) {
  return obj("  primitive p cylinder\n" + body + "  end\n");
}
const std::string kDims = "    radius 1\n    height 1\n";

TEST(HapticFormat, InvalidInputsReportMessageLineAndColumn) {
  const std::vector<BadInput> cases = {
      {"empty", "", 1, 1, "empty input; expected the header 'annex-haptic 1'"},
      {"only comments", "# nothing\n", 2, 1, "empty input; expected the header 'annex-haptic 1'"},
      {"wrong header", "annex-haptics 1\n", 1, 1,
       "expected the header 'annex-haptic 1', found 'annex-haptics'"},
      {"scene header", "annex-scene 1\n", 1, 1,
       "expected the header 'annex-haptic 1', found 'annex-scene' (this is a .scene file)"},
      {"missing version", "annex-haptic\n", 1, 13, "expected a whole number after 'annex-haptic'"},
      {"bad version", "annex-haptic one\n", 1, 14,
       "expected a whole number after 'annex-haptic', found 'one'"},
      {"future version", "annex-haptic 2\n", 1, 14,
       "unsupported format version 2; this reader knows version 1"},
      {"header trailing", "annex-haptic 1 x\n", 1, 16,
       "unexpected 'x' after 'annex-haptic 1'; expected the end of the line"},
      {"unknown top key", "annex-haptic 1\nobjet a\n", 2, 1,
       "unknown key 'objet' at top level; did you mean 'object'?"},
      {"stray end", "annex-haptic 1\nend\n", 2, 1, "stray 'end' at top level; no object is open"},
      {"missing object name", "annex-haptic 1\nobject\n", 2, 7,
       "expected object name after 'object'"},
      {"bad object name", "annex-haptic 1\nobject 9lives\n", 2, 8,
       "invalid object name '9lives'; a name starts with a letter or '_' and continues with "
       "letters, digits, '_', '.' or '-'"},
      {"quoted object name", "annex-haptic 1\nobject \"a\"\n", 2, 8,
       "invalid object name '\"a\"'; a name starts with a letter or '_' and continues with "
       "letters, digits, '_', '.' or '-'"},
      {"object trailing", "annex-haptic 1\nobject a b\n", 2, 10,
       "unexpected 'b' after 'object a'; expected the end of the line"},
      {"duplicate object", obj("  annexable no\n") + "object a\n", 5, 8,
       "duplicate object name 'a' (first at line 2)"},
      {"missing end at eof", "annex-haptic 1\nobject a\n  annexable no\n", 4, 1,
       "missing 'end' for object 'a' (opened at line 2) at the end of the input"},
      {"missing end no newline", "annex-haptic 1\nobject a\n  annexable no", 3, 15,
       "missing 'end' for object 'a' (opened at line 2) at the end of the input"},
      {"missing end before object", "annex-haptic 1\nobject a\n  annexable no\nobject b\n", 4, 1,
       "missing 'end' for object 'a' (opened at line 2) before 'object'"},
      {"annexable without primitive", obj(""), 3, 1,
       "annexable object 'a' has no primitive; add one or set 'annexable no'"},
      {"unknown object key", obj("  meshh x\n"), 3, 3,
       "unknown key 'meshh' in object 'a'; did you mean 'mesh'?"},
      {"unknown object key no suggestion", obj("  colour red\n"), 3, 3,
       "unknown key 'colour' in object 'a'; expected one of: mesh, model_scale, annexable, priority, min_vote, "
       "primitive, end"},
      {"duplicate object key", obj("  annexable no\n  annexable no\n"), 4, 3,
       "duplicate key 'annexable' in object 'a' (first at line 3)"},
      {"annexable maybe", obj("  annexable maybe\n"), 3, 13,
       "expected 'yes' or 'no' after 'annexable', found 'maybe'"},
      {"annexable missing", obj("  annexable\n"), 3, 12,
       "expected 'yes' or 'no' after 'annexable'"},
      {"mesh missing", obj("  mesh\n"), 3, 7, "expected a path after 'mesh'"},
      {"mesh empty", obj("  mesh \"\"\n"), 3, 8, "expected a non-empty path after 'mesh'"},
      {"mesh two tokens", obj("  mesh a b\n"), 3, 10,
       "unexpected 'b' after 'mesh'; expected the end of the line"},
      {"unterminated string", obj("  mesh \"a b\n"), 3, 8,
       "unterminated string; expected a closing '\"'"},
      {"bad escape", obj("  mesh \"a\\n\"\n"), 3, 10,
       "unknown escape in string; only \\\" and \\\\ are allowed"},
      {"quote inside token", obj("  mesh a\"b\n"), 3, 9,
       "unexpected '\"' inside a token; quote the whole token"},
      {"text after closing quote", obj("  mesh \"a\"b\n"), 3, 11,
       "expected a space after the closing '\"'"},
      {"control character",
       obj("  mesh a\x01"
           "b\n"),
       3, 9, "control character 0x01 is not allowed"},
      {"object priority range", obj("  priority 1.5\n"), 3, 12,
       "priority must be in [0, 1], found 1.5"},
      {"object priority negative", obj("  priority -0.1\n"), 3, 12,
       "priority must be in [0, 1], found -0.1"},
      {"nan", obj("  priority nan\n"), 3, 12,
       "expected a finite number after 'priority', found 'nan'"},
      {"inf", obj("  priority inf\n"), 3, 12,
       "expected a finite number after 'priority', found 'inf'"},
      {"not a number", obj("  priority high\n"), 3, 12,
       "expected a number after 'priority', found 'high'"},
      {"partial number", obj("  priority 0.5x\n"), 3, 12,
       "expected a number after 'priority', found '0.5x'"},
      {"plus sign", obj("  priority +1\n"), 3, 12,
       "expected a number after 'priority', found '+1'"},
      {"out of range", obj("  priority 1e999\n"), 3, 12,
       "number '1e999' after 'priority' is out of range"},
      {"quoted number", obj("  priority \"1\"\n"), 3, 12,
       "expected a number after 'priority', found '\"1\"'"},
      {"primitive missing name", obj("  primitive\n"), 3, 12,
       "expected primitive name after 'primitive'"},
      {"primitive missing shape", obj("  primitive p\n"), 3, 14,
       "expected a shape after 'primitive p' (one of: sphere, cylinder, cone, torus, box, plane)"},
      {"primitive unknown shape", obj("  primitive p cylindre\n"), 3, 15,
       "unknown shape 'cylindre'; did you mean 'cylinder'?"},
      {"primitive trailing", obj("  primitive p box x\n"), 3, 19,
       "unexpected 'x' after 'primitive p box'; expected the end of the line"},
      {"duplicate primitive",
       obj("  primitive p cylinder\n" + kDims + "  end\n  primitive p sphere\n"), 7, 13,
       "duplicate primitive name 'p' in object 'a' (first at line 3)"},
      {"unknown primitive key", prim("    raduis 1\n"), 4, 5,
       "unknown key 'raduis' in cylinder 'p'; did you mean 'radius'?"},
      {"other shape's dimension", prim("    size_x 1\n"), 4, 5,
       "unknown key 'size_x' in cylinder 'p'; expected one of: priority, position, rotation, "
       "radius, height, end"},
      {"duplicate dimension", prim("    radius 1\n    radius 2\n"), 5, 5,
       "duplicate key 'radius' in cylinder 'p' (first at line 4)"},
      {"duplicate primitive key", prim(kDims + "    priority 1\n    priority 1\n"), 7, 5,
       "duplicate key 'priority' in cylinder 'p' (first at line 6)"},
      {"missing dimension", prim("    radius 1\n"), 5, 3,
       "cylinder 'p' is missing dimension 'height'"},
      {"missing primitive end before primitive",
       obj("  primitive p cylinder\n" + kDims + "  primitive q sphere\n"), 6, 3,
       "missing 'end' for cylinder 'p' (opened at line 3) before 'primitive'"},
      {"missing primitive end at eof", "annex-haptic 1\nobject a\n  primitive p sphere\n", 4, 1,
       "missing 'end' for sphere 'p' (opened at line 3) at the end of the input"},
      {"primitive end trailing", prim(kDims).replace(prim(kDims).find("  end"), 5, "  end x"), 6, 7,
       "unexpected 'x' after 'end'; expected the end of the line"},
      {"zero size", prim("    radius 0\n    height 1\n"), 4, 12,
       "radius must be positive, found 0"},
      {"negative size", prim("    radius 1\n    height -2\n"), 5, 12,
       "height must be positive, found -2"},
      {"dimension missing value", prim("    radius\n"), 4, 11, "expected a number after 'radius'"},
      {"dimension priority range", prim("    radius 1 priority 2\n    height 1\n"), 4, 23,
       "priority must be in [0, 1], found 2"},
      {"dimension unknown subkey", prim("    radius 1 prio 2\n    height 1\n"), 4, 14,
       "unknown key 'prio' in dimension 'radius'; expected one of: priority, scale"},
      {"dimension subkey typo", prim("    radius 1 scal 1 2\n    height 1\n"), 4, 14,
       "unknown key 'scal' in dimension 'radius'; did you mean 'scale'?"},
      {"dimension duplicate subkey", prim("    radius 1 priority 1 priority 1\n    height 1\n"), 4,
       25, "duplicate key 'priority' in dimension 'radius' (first at column 14)"},
      {"scale min zero", prim("    radius 1 scale 0 2\n    height 1\n"), 4, 20,
       "scale minimum must be positive, found 0"},
      {"scale min above max", prim("    radius 1 scale 2 1\n    height 1\n"), 4, 22,
       "scale minimum 2 is larger than maximum 1"},
      {"scale missing max", prim("    radius 1 scale 2\n    height 1\n"), 4, 21,
       "expected a number after 'scale'"},
      {"rotation not unit", prim(kDims + "    rotation 1 1 0 0\n"), 6, 20,
       "rotation must be a unit quaternion w x y z, found norm 1.4142135623730951"},
      {"rotation zero", prim(kDims + "    rotation 0 0 0 0\n"), 6, 20,
       "rotation must be a unit quaternion w x y z, found norm 0"},
      {"rotation short", prim(kDims + "    rotation 1 0 0\n"), 6, 19,
       "expected a number after 'rotation'"},
      {"position trailing", prim(kDims + "    position 0 0 0 0\n"), 6, 20,
       "unexpected '0' after 'position'; expected the end of the line"},
      {"torus minor too big",
       obj("  primitive t torus\n    minor_radius 0.05\n    major_radius 0.04\n  end\n"), 4, 18,
       "torus minor_radius 0.05 must be smaller than major_radius 0.04"},
      {"torus minor equal",
       obj("  primitive t torus\n    major_radius 0.05\n    minor_radius 0.05\n  end\n"), 5, 18,
       "torus minor_radius 0.05 must be smaller than major_radius 0.05"},
      {"line too long", "annex-haptic 1\n# " + std::string(5000, 'x') + "\n", 2, 4097,
       "line is longer than 4096 bytes"},
  };
  test::expect_located_errors(
      cases, [](const std::string& t, const std::string& o) { return parse_haptic(t, o); },
      "bad.haptic");
}

TEST(HapticFormat, ErrorFormatsLikeACompiler) {
  auto r = parse_haptic(prim("    raduis 1\n"), "spec.haptic");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().format(),
            "spec.haptic:4:5: error: unknown key 'raduis' in cylinder 'p'; did you mean 'radius'?");
}

TEST(HapticFormat, RefusesInputOverTheSizeLimit) {
  const std::string big(kMaxTextFileBytes + 1, '\n');
  auto r = parse_haptic(big, "big.haptic");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "input is 16777217 bytes, more than the limit of 16777216 bytes");
}

TEST(HapticFormat, CapsObjectsAndPrimitives) {
  std::string many = "annex-haptic 1\n";
  for (int i = 0; i <= 4096; ++i) many += "object o" + std::to_string(i) + "\nannexable no\nend\n";
  auto r = parse_haptic(many, "x");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "more than 4096 objects in one file");
  EXPECT_EQ(r.error().location.line, 2 + 3 * 4096);

  std::string prims = "annex-haptic 1\nobject a\n";
  for (int i = 0; i <= 64; ++i)
    prims += "primitive p" + std::to_string(i) + " sphere\nradius 1\nend\n";
  r = parse_haptic(prims + "end\n", "x");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "object 'a' has more than 64 primitives");
  EXPECT_EQ(r.error().location.line, 3 + 3 * 64);
}

TEST(HapticFormat, PropertyWriteThenParseIsIdentity) {
  test::Gen g(20161107);
  for (int i = 0; i < 1000; ++i) {
    const HapticSpec spec = test::random_spec(g);
    ASSERT_TRUE(validate_haptic(spec).ok()) << validate_haptic(spec).error().format();
    const std::string text = write_haptic(spec);
    auto back = parse_haptic(text, "gen");
    ASSERT_TRUE(back.ok()) << back.error().format() << "\n" << text;
    ASSERT_EQ(*back, spec) << text;
    ASSERT_EQ(write_haptic(*back), text);
  }
}

// The editor's in-memory check uses the same words, located by object and primitive.
TEST(HapticFormat, ValidateUsesTheReaderWords) {
  auto spec = parse_haptic(kBottle, "b");
  ASSERT_TRUE(spec.ok());
  EXPECT_TRUE(validate_haptic(*spec).ok());

  const auto expect = [](const HapticSpec& s, const std::string& origin, const std::string& msg) {
    auto st = validate_haptic(s, "doc");
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().location, (Location{origin, 0, 0}));
    EXPECT_EQ(st.error().message, msg);
  };
  const std::string where = "doc: object 'bottle' primitive 'body'";
  HapticSpec s = *spec;
  s.objects[0].primitives[0].dimensions[0].value_m = 0;
  expect(s, where, "radius must be positive, found 0");
  s = *spec;
  s.objects[0].primitives[0].dimensions[1].min_scale = 3;
  expect(s, where, "scale minimum 3 is larger than maximum 2 (dimension 'height')");
  s = *spec;
  s.objects[0].primitives[0].dimensions[1].min_scale = -1;
  expect(s, where, "scale minimum must be positive, found -1 (dimension 'height')");
  s = *spec;
  s.objects[0].primitives[0].dimensions[1].weight = 1.5;
  expect(s, where, "priority must be in [0, 1], found 1.5 (dimension 'height')");
  s = *spec;
  s.objects[0].primitives[0].weight = std::nan("");
  expect(s, where, "priority must be in [0, 1], found nan");
  s = *spec;
  s.objects[0].primitives[0].pose.rotation = Quat{2, 0, 0, 0};
  expect(s, where, "rotation must be a unit quaternion w x y z, found norm 2");
  s = *spec;
  s.objects[0].primitives[0].pose.position.y = INFINITY;
  expect(s, where, "position must be a finite number, found inf");
  s = *spec;
  s.objects[0].primitives[0].dimensions.pop_back();
  expect(s, where, "cylinder 'body' is missing dimension 'height'");
  s = *spec;
  s.objects[0].primitives.push_back(s.objects[0].primitives[0]);
  expect(s, where, "duplicate primitive name 'body' in object 'bottle'");
  s = *spec;
  s.objects[0].primitives[0].name = "a b";
  expect(s, "doc: object 'bottle' primitive 'a b'",
         "invalid primitive name 'a b'; a name starts with a letter or '_' and continues with "
         "letters, digits, '_', '.' or '-'");
  s = *spec;
  s.objects[0].primitives.clear();
  expect(s, "doc: object 'bottle'",
         "annexable object 'bottle' has no primitive; add one or set 'annexable no'");
  s.objects[0].annexable = false;
  EXPECT_TRUE(validate_haptic(s).ok());
  s = *spec;
  s.objects[0].mesh = "a\nb";
  expect(s, "doc: object 'bottle'", "mesh path contains a control character");
  s = *spec;
  s.objects.push_back(s.objects[0]);
  expect(s, "doc: object 'bottle'", "duplicate object name 'bottle'");
  s = *spec;
  s.objects[0].priority = -1;
  expect(s, "doc: object 'bottle'", "priority must be in [0, 1], found -1");
  s = *spec;
  s.objects[0].primitives[0] = make_primitive(ShapeKind::torus, "ring");
  s.objects[0].primitives[0].dimensions[1].value_m = 0.2;
  expect(s, "doc: object 'bottle' primitive 'ring'",
         "torus minor_radius 0.2 must be smaller than major_radius 0.1");
}

// Found by fuzz_haptic or by review; each input once broke an invariant.
TEST(HapticFormat, RegressionInputs) {
  // A name token may look like a key: positional, so it is just a name.
  auto r = parse_haptic(
      "annex-haptic 1\nobject end\n primitive end sphere\n  radius 1\n end\nend\n", "x");
  ASSERT_TRUE(r.ok()) << r.error().format();
  EXPECT_EQ(r->objects[0].name, "end");
  EXPECT_EQ(*parse_haptic(write_haptic(*r), "x"), *r);
}

}  // namespace
}  // namespace annex
