#include "annex/formats/scene_format.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "format_test_util.h"

namespace annex {
namespace {

TEST(SceneFormat, KitchenGoldenReadsAndWritesBackByteForByte) {
  const std::string text = test::slurp(test::data_path("kitchen.scene"));
  auto scene = parse_scene(text, "kitchen.scene");
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  ASSERT_TRUE(scene->support.has_value());
  EXPECT_EQ(scene->support->normal, (Vec3{0, -1, 0}));
  EXPECT_EQ(scene->support->d, 0.8);
  ASSERT_EQ(scene->objects.size(), 4u);
  const PhysicalObject& p1 = scene->objects[0];
  EXPECT_EQ(p1.id, "p1");
  EXPECT_EQ(p1.point_count, 1200);
  EXPECT_EQ(p1.fit, 0.93);
  ASSERT_EQ(p1.primitives.size(), 2u);
  EXPECT_EQ(p1.primitives[0].kind, ShapeKind::cylinder);
  EXPECT_EQ(p1.primitives[0].dimensions_m, (std::vector<double>{0.04, 0.2}));
  EXPECT_EQ(p1.primitives[0].center, (Vec3{0, 0, 0.8}));
  EXPECT_EQ(p1.primitives[1].kind, ShapeKind::cone);
  EXPECT_TRUE(scene->objects[3].primitives.empty());
  EXPECT_EQ(write_scene(*scene), text);
}

TEST(SceneFormat, Version2CarriesSupportsPartialAndFrustums) {
  PhysicalScene scene;
  scene.supports = {{"s1", Plane{{0, -1, 0}, 1.3}, 5000}, {"s2", Plane{{0, -1, 0}, 0.55}, 800}};
  scene.support = scene.supports[0].plane;
  PhysicalObject cup;
  cup.id = "p1";
  cup.support_id = "s2";
  cup.point_count = 900;
  cup.fit = 0.8;
  PhysicalPrimitive frustum{ShapeKind::cone, {0.05, 0.1}, {0, 0.5, 1}, {0, 1, 0}, 0.8};
  frustum.narrow_radius_m = 0.03;
  cup.primitives.push_back(frustum);
  PhysicalObject cut;
  cut.id = "p2";
  cut.support_id = "s1";
  cut.partial = true;
  scene.objects = {cup, cut};
  const std::string text = write_scene(scene);
  EXPECT_EQ(text.rfind("annex-scene 2\nsupport s1 0 -1 0 1.3 points 5000\nsupport s2 ", 0), 0u) << text;
  EXPECT_NE(text.find("  on s2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("  partial\n"), std::string::npos) << text;
  EXPECT_NE(text.find(" narrow_radius 0.03 "), std::string::npos) << text;
  auto back = parse_scene(text, "v2.scene");
  ASSERT_TRUE(back.ok()) << back.error().format();
  EXPECT_EQ(*back, scene);
  EXPECT_TRUE(validate_scene(scene, "v2.scene").ok());
  // A scene that needs nothing of version 2 is written as version 1.
  PhysicalScene plain;
  plain.support = Plane{{0, -1, 0}, 0.8};
  EXPECT_EQ(write_scene(plain).rfind("annex-scene 1\n", 0), 0u);
  // An object on a support the scene does not hold is refused before writing.
  scene.objects[0].support_id = "s7";
  EXPECT_FALSE(validate_scene(scene, "v2.scene").ok());
}

TEST(SceneFormat, Version3CarriesObjectsStandingOnObjects) {
  PhysicalScene scene;
  scene.supports = {{"s1", Plane{{0, -1, 0}, 0.8}, 5000}};
  scene.support = scene.supports[0].plane;
  PhysicalObject lower, upper;
  lower.id = "p1";
  lower.support_id = "s1";
  lower.primitives.push_back({ShapeKind::box, {0.2, 0.1, 0.3}, {0, 0.65, 1}, {0, -1, 0}, 0.9});
  upper.id = "p2";
  upper.support_id = "s1";  // the support under the stack
  upper.on_object = "p1";
  upper.primitives.push_back({ShapeKind::box, {0.1, 0.1, 0.1}, {0, 0.45, 1}, {0, -1, 0}, 0.9});
  scene.objects = {lower, upper};
  const std::string text = write_scene(scene);
  EXPECT_EQ(text.rfind("annex-scene 3\n", 0), 0u) << text;
  EXPECT_NE(text.find("object p2\n  on s1\n  on_object p1\n"), std::string::npos) << text;
  auto back = parse_scene(text, "v3.scene");
  ASSERT_TRUE(back.ok()) << back.error().format();
  EXPECT_EQ(*back, scene);
  EXPECT_TRUE(validate_scene(scene, "v3.scene").ok());
  // An object standing on another comes before or after it in the file alike.
  std::swap(scene.objects[0], scene.objects[1]);
  back = parse_scene(write_scene(scene), "v3.scene");
  ASSERT_TRUE(back.ok()) << back.error().format();
  EXPECT_EQ(*back, scene);
  // Without stacking the writer stays at version 2, which older readers take.
  scene.objects[0].on_object.clear();
  EXPECT_EQ(write_scene(scene).rfind("annex-scene 2\n", 0), 0u);
  // The validator refuses what the reader would.
  scene.objects[0].on_object = "p9";
  auto st = validate_scene(scene, "scan");
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().message, "object 'p2' stands on object 'p9', which the scene does not hold");
  scene.objects[0].on_object = "p1";
  scene.objects[1].on_object = "p2";
  st = validate_scene(scene, "scan");
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().message, "objects stand on each other in a loop (p2 on p1 on p2)");
}

TEST(SceneFormat, NoSupportGolden) {
  const std::string text = test::slurp(test::data_path("no_support.scene"));
  auto scene = parse_scene(text, "no_support.scene");
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  EXPECT_FALSE(scene->support.has_value());
  EXPECT_EQ(write_scene(*scene), text);
}

TEST(SceneFormat, DefaultsAndAnyKeyOrder) {
  auto scene =
      parse_scene("annex-scene 1\nobject a\n  box size_z 3 fit 0.5 size_y 2 size_x 1\nend\n", "x");
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  const PhysicalObject& o = scene->objects[0];
  EXPECT_EQ(o.point_count, 0);
  EXPECT_EQ(o.fit, 0.0);
  const PhysicalPrimitive& p = o.primitives[0];
  EXPECT_EQ(p.dimensions_m, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(p.center, (Vec3{0, 0, 0}));
  EXPECT_EQ(p.axis, (Vec3{0, 0, 1}));
  EXPECT_EQ(p.fit, 0.5);
}

TEST(SceneFormat, NormalisesAxesAndSupportNormal) {
  auto scene = parse_scene(
      "annex-scene 1\nsupport 0 -2 0 1\nobject a\n  sphere radius 1 axis 0 3 4\nend\n", "x");
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  EXPECT_EQ(scene->support->normal, (Vec3{0, -1, 0}));
  const Vec3 a = scene->objects[0].primitives[0].axis;
  EXPECT_NEAR(a.y, 0.6, 1e-15);
  EXPECT_NEAR(a.z, 0.8, 1e-15);
}

// Squaring these would underflow or overflow; they still normalise and round-trip.
TEST(SceneFormat, TinyAndHugeAxesNormalise) {
  auto scene = parse_scene(
      "annex-scene 1\nobject a\n  sphere radius 1 axis 1e-200 0 -1e-200\n"
      "  sphere radius 1 axis 1e300 0 1e300\n  sphere radius 1 axis 0 5e-324 0\nend\n",
      "x");
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  const auto& p = scene->objects[0].primitives;
  EXPECT_NEAR(p[0].axis.x, std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(p[0].axis.z, -std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(p[1].axis.z, std::sqrt(0.5), 1e-15);
  EXPECT_EQ(p[2].axis, (Vec3{0, 1, 0}));
  EXPECT_EQ(*parse_scene(write_scene(*scene), "y"), *scene);
}

using test::BadInput;

std::string obj(const std::string& body) {
  return "annex-scene 1\nobject a\n" + body + "end\n";
}
std::string repeated(const std::string& line, int times) {
  std::string out;
  for (int i = 0; i < times; ++i) out += line;
  return out;
}

TEST(SceneFormat, InvalidInputsReportMessageLineAndColumn) {
  const std::vector<BadInput> cases = {
      {"empty", "", 1, 1, "empty input; expected the header 'annex-scene 1'"},
      {"haptic header", "annex-haptic 1\n", 1, 1,
       "expected the header 'annex-scene 1', found 'annex-haptic' (this is a .haptic file)"},
      {"future version", "annex-scene 4\n", 1, 13,
       "unsupported format version 4; this reader knows versions 1 to 3"},
      {"v2 has no 'on_object'", "annex-scene 2\nobject a\n  on_object b\nend\nobject b\nend\n", 3, 3,
       "'on_object' in object 'a' needs the header 'annex-scene 3'"},
      {"v3 on an undeclared object", "annex-scene 3\nobject a\n  on_object b\nend\n", 3, 13,
       "object 'a' stands on object 'b', which the file does not declare"},
      {"v3 on itself", "annex-scene 3\nobject a\n  on_object a\nend\n", 3, 13,
       "object 'a' cannot stand on itself"},
      {"v3 stacking loop",
       "annex-scene 3\nobject a\n  on_object b\nend\nobject b\n  on_object a\nend\n", 3, 13,
       "objects stand on each other in a loop (a on b on a)"},
      {"v3 duplicate on_object",
       "annex-scene 3\nobject b\nend\nobject a\n  on_object b\n  on_object b\nend\n", 6, 3,
       "duplicate key 'on_object' in object 'a' (first at line 5)"},
      {"v2 support without id", "annex-scene 2\nsupport 0 1 0 0\n", 2, 9,
       "invalid support id '0'; a name starts with a letter or '_' and continues with letters, "
       "digits, '_', '.' or '-'"},
      {"v2 duplicate support id", "annex-scene 2\nsupport s1 0 1 0 0\nsupport s1 0 1 0 1\n", 3, 9,
       "duplicate support id 's1' (first at line 2)"},
      {"v2 support extra key", "annex-scene 2\nsupport s1 0 1 0 0 pts 3\n", 2, 20,
       "unknown key 'pts' in support 's1'; expected 'points' or the end of the line"},
      {"v2 object on undeclared support", "annex-scene 2\nobject a\n  on s4\nend\n", 3, 6,
       "object 'a' is on support 's4', which the file does not declare"},
      {"v1 has no 'on'", obj("  on s1\n"), 3, 3, "'on' in object 'a' needs the header 'annex-scene 2'"},
      {"narrow radius too wide", obj("  cone radius 0.05 height 0.1 narrow_radius 0.06\n"), 3, 45,
       "cone narrow_radius must be less than its radius (the wide end)"},
      {"narrow radius on a cylinder", obj("  cylinder radius 1 height 1 narrow_radius 0.5\n"), 3, 30,
       "unknown key 'narrow_radius' in cylinder at column 3; expected one of: radius, height, "
       "center, axis, fit"},
      {"unknown top key", "annex-scene 1\nsuport 0 1 0 0\n", 2, 1,
       "unknown key 'suport' at top level; did you mean 'support'?"},
      {"support zero normal", "annex-scene 1\nsupport 0 0 0 1\n", 2, 13,
       "support must be a non-zero vector"},
      {"support missing d", "annex-scene 1\nsupport 0 1 0\n", 2, 14,
       "expected a number after 'support'"},
      {"support twice", "annex-scene 1\nsupport 0 1 0 0\nsupport 0 1 0 0\n", 3, 1,
       "duplicate key 'support' at top level (first at line 2)"},
      {"support in object", obj("  support 0 1 0 0\n"), 3, 3,
       "missing 'end' for object 'a' (opened at line 2) before 'support'"},
      {"stray end", "annex-scene 1\nend\n", 2, 1, "stray 'end' at top level; no object is open"},
      {"duplicate id", obj("") + "object a\nend\n", 4, 8,
       "duplicate object id 'a' (first at line 2)"},
      {"bad id", "annex-scene 1\nobject -a\n", 2, 8,
       "invalid object id '-a'; a name starts with a letter or '_' and continues with letters, "
       "digits, '_', '.' or '-'"},
      {"missing end", "annex-scene 1\nobject a\n", 3, 1,
       "missing 'end' for object 'a' (opened at line 2) at the end of the input"},
      {"negative points", obj("  points -1\n"), 3, 10, "points must be 0 or more, found -1"},
      {"fractional points", obj("  points 1.5\n"), 3, 10,
       "expected a whole number after 'points', found '1.5'"},
      {"huge points", obj("  points 99999999999\n"), 3, 10,
       "number '99999999999' after 'points' is out of range"},
      {"fit range", obj("  fit 1.01\n"), 3, 7, "fit must be in [0, 1], found 1.01"},
      {"duplicate fit", obj("  fit 1\n  fit 1\n"), 4, 3,
       "duplicate key 'fit' in object 'a' (first at line 3)"},
      {"unknown object key", obj("  cylindre radius 1 height 1\n"), 3, 3,
       "unknown key 'cylindre' in object 'a'; did you mean 'cylinder'?"},
      {"unknown primitive key", obj("  cylinder raduis 1 height 1\n"), 3, 12,
       "unknown key 'raduis' in cylinder at column 3; did you mean 'radius'?"},
      {"duplicate primitive key", obj("  sphere radius 1 radius 2\n"), 3, 19,
       "duplicate key 'radius' in sphere at column 3 (first at column 10)"},
      {"missing dimension", obj("  cylinder radius 1 center 0 0 0\n"), 3, 3,
       "cylinder is missing dimension 'height'"},
      {"zero dimension", obj("  sphere radius 0\n"), 3, 17, "radius must be positive, found 0"},
      {"zero axis", obj("  sphere radius 1 axis 0 0 0\n"), 3, 28, "axis must be a non-zero vector"},
      {"short center", obj("  sphere radius 1 center 0 0\n"), 3, 29,
       "expected a number after 'center'"},
      {"primitive fit range", obj("  sphere radius 1 fit -1\n"), 3, 23,
       "fit must be in [0, 1], found -1"},
      {"non-finite", obj("  sphere radius inf\n"), 3, 17,
       "expected a finite number after 'radius', found 'inf'"},
      {"torus", obj("  torus major_radius 1 minor_radius 2\n"), 3, 37,
       "torus minor_radius 2 must be smaller than major_radius 1"},
      {"65 primitives", obj(repeated("sphere radius 1\n", 65)), 3 + 64, 1,
       "object 'a' has more than 64 primitives"},
  };
  test::expect_located_errors(
      cases, [](const std::string& t, const std::string& o) { return parse_scene(t, o); },
      "bad.scene");
}

TEST(SceneFormat, ValidateUsesTheReaderWords) {
  auto scene = parse_scene(test::slurp(test::data_path("kitchen.scene")), "k");
  ASSERT_TRUE(scene.ok());
  EXPECT_TRUE(validate_scene(*scene).ok());
  // Each case breaks one rule of the kitchen scene in memory.
  struct BadScene {
    const char* name;
    std::function<void(PhysicalScene&)> mutate;
    std::string origin;
    std::string message;
  };
  const std::vector<BadScene> cases = {
      {"negative height", [](PhysicalScene& s) { s.objects[0].primitives[0].dimensions_m[1] = -1; },
       "scan: object 'p1'", "height must be positive, found -1"},
      {"fat torus", [](PhysicalScene& s) { s.objects[2].primitives[0].dimensions_m[1] = 1; },
       "scan: object 'p3'", "torus minor_radius 1 must be smaller than major_radius 0.05"},
      {"zero axis",
       [](PhysicalScene& s) {
         s.objects[0].primitives[1].axis = Vec3{0, 0, 0};
       },
       "scan: object 'p1'", "axis must be a non-zero vector"},
      {"missing dimension",
       [](PhysicalScene& s) { s.objects[0].primitives[1].dimensions_m.pop_back(); },
       "scan: object 'p1'", "cone is missing dimension 'height'"},
      {"fit range", [](PhysicalScene& s) { s.objects[1].fit = 2; }, "scan: object 'p2'",
       "fit must be in [0, 1], found 2"},
      {"negative points", [](PhysicalScene& s) { s.objects[1].point_count = -5; },
       "scan: object 'p2'", "points must be 0 or more, found -5"},
      {"duplicate id", [](PhysicalScene& s) { s.objects[1].id = "p1"; }, "scan: object 'p1'",
       "duplicate object id 'p1'"},
      {"zero support normal", [](PhysicalScene& s) { s.support->normal = Vec3{}; }, "scan",
       "support must be a non-zero vector"},
  };
  for (const BadScene& c : cases) {
    SCOPED_TRACE(c.name);
    PhysicalScene s = *scene;
    c.mutate(s);
    auto st = validate_scene(s, "scan");
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().location, (Location{c.origin, 0, 0}));
    EXPECT_EQ(st.error().message, c.message);
  }
}

TEST(SceneFormat, PropertyWriteThenParseIsIdentity) {
  test::Gen g(1604);
  for (int i = 0; i < 1000; ++i) {
    const PhysicalScene scene = test::random_scene(g);
    ASSERT_TRUE(validate_scene(scene).ok()) << validate_scene(scene).error().format();
    const std::string text = write_scene(scene);
    auto back = parse_scene(text, "gen");
    ASSERT_TRUE(back.ok()) << back.error().format() << "\n" << text;
    ASSERT_EQ(*back, scene) << text;
    ASSERT_EQ(write_scene(*back), text);
  }
}

}  // namespace
}  // namespace annex
