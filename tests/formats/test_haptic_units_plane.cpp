// The `.haptic` model_scale key and the plane primitive, and planes in `.scene` files
// (issue 14 §1 and §2): reading, defaults for older files, the canonical writer and
// the errors with their line and column.
#include <gtest/gtest.h>

#include <string>

#include "annex/formats/haptic_format.h"
#include "annex/formats/scene_format.h"

namespace annex {
namespace {

constexpr const char* kPanel =
    "annex-haptic 1\n"
    "object keypad\n"
    "  mesh models/keypad.glb\n"
    "  model_scale 0.01\n"
    "  primitive keys plane\n"
    "    position 0 0.01 0\n"
    "    rotation 0.7071067811865476 -0.7071067811865476 0 0\n"
    "    size_x 0.2 priority 0.7 scale 0.8 1.5\n"
    "    size_y 0.12\n"
    "  end\n"
    "end\n";

TEST(HapticUnitsPlane, ReadsModelScaleAndAPlane) {
  const auto spec = parse_haptic(kPanel, "p.haptic");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  const VirtualObject& o = spec->objects.at(0);
  EXPECT_EQ(o.model_scale, 0.01);
  ASSERT_EQ(o.primitives.size(), 1u);
  EXPECT_EQ(o.primitives[0].kind, ShapeKind::plane);
  ASSERT_EQ(o.primitives[0].dimensions.size(), 2u);
  EXPECT_EQ(o.primitives[0].dimensions[0].value_m, 0.2);
  EXPECT_EQ(o.primitives[0].dimensions[0].max_scale, 1.5);
  EXPECT_EQ(o.primitives[0].dimensions[1].value_m, 0.12);
  // Canonical: written back byte for byte, model_scale after mesh.
  const std::string written = write_haptic(*spec);
  EXPECT_NE(written.find("  mesh models/keypad.glb\n  model_scale 0.01\n"), std::string::npos)
      << written;
  EXPECT_EQ(parse_haptic(written, "w.haptic").value(), *spec);
}

TEST(HapticUnitsPlane, OlderFilesReadAtScaleOneAndTheWriterOmitsIt) {
  const auto spec = parse_haptic(
      "annex-haptic 1\nobject a\n  primitive b sphere\n    radius 0.05\n  end\nend\n", "o.haptic");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  EXPECT_EQ(spec->objects[0].model_scale, 1.0);
  EXPECT_EQ(write_haptic(*spec).find("model_scale"), std::string::npos);
}

void expect_error(const std::string& text, int line, int column, const std::string& words) {
  const auto spec = parse_haptic(text, "e.haptic");
  ASSERT_FALSE(spec.ok()) << text;
  EXPECT_EQ(spec.error().location.line, line) << spec.error().format();
  EXPECT_EQ(spec.error().location.column, column) << spec.error().format();
  EXPECT_NE(spec.error().message.find(words), std::string::npos) << spec.error().format();
}

TEST(HapticUnitsPlane, Errors) {
  const std::string head = "annex-haptic 1\nobject a\n";
  const std::string prim = "  primitive b plane\n    size_x 0.1\n    size_y 0.1\n  end\nend\n";
  expect_error(head + "  model_scale 0\n" + prim, 3, 15, "model_scale must be positive");
  expect_error(head + "  model_scale -2\n" + prim, 3, 15, "model_scale must be positive");
  expect_error(head + "  model_scale 1cm\n" + prim, 3, 15, "model_scale");
  expect_error(head + "  model_scale 1\n  model_scale 2\n" + prim, 4, 3, "duplicate key 'model_scale'");
  expect_error(head + "  model_scal 0.1\n" + prim, 3, 3, "did you mean 'model_scale'");
  // A plane has no thickness.
  expect_error(head + "  primitive b plane\n    size_x 0.1\n    size_y 0.1\n    size_z 0.1\n  end\nend\n",
               6, 5, "unknown key 'size_z'");
  expect_error(head + "  primitive b plane\n    size_x 0.1\n  end\nend\n", 5, 3,
               "plane 'b' is missing dimension 'size_y'");
  expect_error(head + "  primitive b plain\n", 3, 15, "did you mean 'plane'");
}

TEST(HapticUnitsPlane, ValidateChecksModelScale) {
  auto spec = parse_haptic(kPanel, "p.haptic").value();
  spec.objects[0].model_scale = 0;
  const Status st = validate_haptic(spec, "doc.haptic");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("model_scale"), std::string::npos) << st.error().format();
}

TEST(ScenePlane, ReadsWritesAPlaneWithItsSideDirection) {
  const std::string text =
      "annex-scene 2\n"
      "support s1 0 -1 0 0.8 points 1000\n"
      "\n"
      "object s1.free\n"
      "  on s1\n"
      "  points 5000\n"
      "  fit 1\n"
      "  plane size_x 0.6 size_y 0.4 center 0 0.8 1.2 axis 0 -1 0 x_axis 1 0 0 fit 1\n"
      "end\n";
  const auto scene = parse_scene(text, "s.scene");
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  const PhysicalPrimitive& p = scene->objects.at(0).primitives.at(0);
  EXPECT_EQ(p.kind, ShapeKind::plane);
  EXPECT_EQ(p.dimensions_m, (std::vector<double>{0.6, 0.4}));
  EXPECT_EQ(p.x_axis, (Vec3{1, 0, 0}));
  EXPECT_EQ(write_scene(*scene), text);
  // x_axis belongs to planes only.
  const auto bad = parse_scene(
      "annex-scene 2\nobject a\n  box size_x 1 size_y 1 size_z 1 x_axis 1 0 0\nend\n", "b.scene");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().location.line, 3);
  EXPECT_EQ(bad.error().location.column, 34);
}

}  // namespace
}  // namespace annex
