// Model units and size (issue 14 §1) with real models no one here wrote: assimp's own
// test models (Debian's assimp-testmodels), and the plane primitive in the editor (§2).
#include <gtest/gtest.h>

#include <filesystem>

#include "annex/authoring/editor_document.h"
#include "annex/authoring/match_preview.h"
#include "annex/authoring/script.h"
#include "annex/common/object_finder.h"
#include "annex/formats/haptic_format.h"
#include "annex/formats/scene_format.h"
#include "test_util.h"

namespace annex::authoring {
namespace {

namespace fs = std::filesystem;

const fs::path kModels = "/usr/share/assimp/models";
const fs::path kDuck = kModels / "Collada" / "duck.dae";
const fs::path kFbxBox = kModels / "FBX" / "box.fbx";

#define NEED(path)                                                                       \
  if (!fs::exists(path)) GTEST_SKIP() << path << " is absent (Debian's assimp-testmodels, " \
                                                 "installed by scripts/deps.sh)"

using testing::run;

std::string run_output(EditorDocument& doc, const std::string& line) {
  auto lines = parse_script(line, "t.script");
  EXPECT_TRUE(lines && lines->size() == 1);
  auto r = run_document_command(doc, lines->front(), "t.script");
  EXPECT_TRUE(r) << (r ? "" : r.error().format());
  return r ? r->output : "";
}

TEST(MeshUnits, ColladaStatesItsUnitAndAssimpAppliesIt) {
  NEED(kDuck);
  auto mesh = load_mesh(kDuck);
  ASSERT_TRUE(mesh) << mesh.error().format();
  EXPECT_TRUE(mesh->units.stated);
  EXPECT_EQ(mesh->units.metres_per_unit, 1.0);  // already in metres after the import
  EXPECT_NE(mesh->units.note.find("centimeter"), std::string::npos) << mesh->units.note;
  EXPECT_NE(mesh->units.note.find("0.01"), std::string::npos) << mesh->units.note;
  // The duck comes in 1.5 m tall: a giant, not a bath toy.
  EXPECT_GT(mesh->max.y - mesh->min.y, 1.0);
}

TEST(MeshUnits, FbxUnitScaleFactorAndFormatsWithoutUnits) {
  NEED(kFbxBox);
  auto fbx = load_mesh(kFbxBox);
  ASSERT_TRUE(fbx) << fbx.error().format();
  EXPECT_TRUE(fbx->units.stated);
  EXPECT_DOUBLE_EQ(fbx->units.metres_per_unit, 1.0);  // UnitScaleFactor 100 cm per unit
  EXPECT_NE(fbx->units.note.find("UnitScaleFactor 100"), std::string::npos) << fbx->units.note;
  auto obj = load_mesh(testing::sample_model("mug.obj"));
  ASSERT_TRUE(obj) << obj.error().format();
  EXPECT_FALSE(obj->units.stated);
  EXPECT_EQ(obj->units.note, "obj states no unit");
}

TEST(ModelUnits, UnitsAndScaleCommands) {
  EditorDocument doc;
  run(doc, "import " + testing::sample_model("mug.obj") + " mug\nadd cylinder body\n");
  const double r0 = doc.spec().objects[0].primitives[0].dimensions[0].value_m;
  const Vec3 p0 = doc.spec().objects[0].primitives[0].pose.position;
  run(doc, "select mug\nset model_units cm\n");
  EXPECT_DOUBLE_EQ(doc.spec().objects[0].model_scale, 0.01);
  // The primitives stay on the mesh: they shrink with it.
  EXPECT_NEAR(doc.spec().objects[0].primitives[0].dimensions[0].value_m, r0 * 0.01, 1e-12);
  EXPECT_NEAR(doc.spec().objects[0].primitives[0].pose.position.y, p0.y * 0.01, 1e-12);
  EXPECT_NEAR(doc.mesh_for(0)->max.y, doc.source_mesh_for(0)->max.y * 0.01, 1e-6);
  // One undo step restores scale and primitives together.
  run(doc, "undo\n");
  EXPECT_EQ(doc.spec().objects[0].model_scale, 1.0);
  EXPECT_NEAR(doc.spec().objects[0].primitives[0].dimensions[0].value_m, r0, 1e-12);
  run(doc, "select mug\nset model_scale 2\n");
  EXPECT_NEAR(doc.spec().objects[0].primitives[0].dimensions[0].value_m, 2 * r0, 1e-12);
  // Bad values are refused with the document unchanged.
  for (const char* bad : {"set model_scale 0", "set model_scale -1", "set model_units yards",
                          "set model_height 0"}) {
    auto lines = parse_script(bad, "t.script");
    ASSERT_TRUE(lines);
    auto r = run_document_command(doc, lines->front(), "t.script");
    EXPECT_FALSE(r) << bad;
    EXPECT_EQ(doc.spec().objects[0].model_scale, 2.0) << bad;
  }
  // The scale survives a save and an open.
  const fs::path dir = testing::fresh_dir("units");
  run(doc, "save " + (dir / "mug.haptic").string() + "\n");
  auto reopened = EditorDocument::open(dir / "mug.haptic");
  ASSERT_TRUE(reopened) << reopened.error().format();
  EXPECT_EQ(reopened->spec().objects[0].model_scale, 2.0);
  EXPECT_NEAR(reopened->mesh_for(0)->max.y, 2 * doc.source_mesh_for(0)->max.y, 1e-6);
}

// The case: the duck imported at its own scale gets a sphere of about 1 m and no
// sensible vote; told its real height (12 cm) it gets hand-sized primitives and votes
// for the household library's ball.
TEST(ModelUnits, DuckGivenItsRealHeightGetsHandSizedPrimitivesAndSensibleVotes) {
  NEED(kDuck);
  const PhysicalScene household =
      *read_scene_file(fs::path(ANNEX_SOURCE_DIR) / "samples" / "library" / "household.scene");
  EditorDocument doc;
  run(doc, "import " + kDuck.string() + " duck\nadd sphere body\n");
  const double giant_r = doc.spec().objects[0].primitives[0].dimensions[0].value_m;
  EXPECT_GT(giant_r, 0.5);
  const MatchResult giant = match_objects(doc.spec(), household);
  double giant_best = 0;
  for (const VoteExplanation& e : giant.table[0]) giant_best = std::max(giant_best, e.vote);
  EXPECT_LT(giant_best, 20);

  run(doc, "select duck\nset model_height 0.12\n");
  EXPECT_NEAR(doc.mesh_for(0)->max.y - doc.mesh_for(0)->min.y, 0.12, 1e-6);
  const std::string shown = run_output(doc, "model");
  EXPECT_NE(shown.find("0.120"), std::string::npos) << shown;
  EXPECT_NE(shown.find("centimeter"), std::string::npos) << shown;
  const Primitive body = doc.spec().objects[0].primitives[0];
  // The sphere scaled with the mesh: a bath toy's body, 4 to 8 cm in radius.
  EXPECT_GT(body.dimensions[0].value_m, 0.04);
  EXPECT_LT(body.dimensions[0].value_m, 0.08);
  // Refit at the new size: the same, within a millimetre.
  run(doc, "select duck body\nfit sphere\n");
  EXPECT_NEAR(doc.spec().objects[0].primitives[0].dimensions[0].value_m, body.dimensions[0].value_m,
              1e-3);
  const MatchResult sized = match_objects(doc.spec(), household);
  double best = 0;
  std::string best_id;
  for (size_t j = 0; j < sized.table[0].size(); ++j)
    if (sized.table[0][j].vote > best) best = sized.table[0][j].vote, best_id = household.objects[j].id;
  EXPECT_GT(best, 60) << best_id;
  EXPECT_GT(best, 3 * giant_best);
}

TEST(PlanePrimitive, AddFitSizeAndSave) {
  EditorDocument doc;
  run(doc, "import " + testing::sample_model("pingpong_paddle.obj") +
               " paddle\nadd plane face\nset size_x 0.2\nset size_y 0.15\n");
  const Primitive& face = doc.spec().objects[0].primitives[0];
  EXPECT_EQ(face.kind, ShapeKind::plane);
  ASSERT_EQ(face.dimensions.size(), 2u);
  EXPECT_EQ(face.dimensions[0].value_m, 0.2);
  EXPECT_EQ(face.dimensions[1].value_m, 0.15);
  // Fit to the paddle's blade: the rectangle spans its two wide directions.
  run(doc, "fit plane\n");
  const Primitive& fitted = doc.spec().objects[0].primitives[0];
  const MeshData* mesh = doc.mesh_for(0);
  const Vec3 size = mesh->max - mesh->min;
  const double widest = std::max({size.x, size.y, size.z});
  EXPECT_NEAR(fitted.dimensions[0].value_m, widest, 0.02 * widest);
  EXPECT_LT(fitted.dimensions[1].value_m, fitted.dimensions[0].value_m + 1e-9);
  run(doc, "validate\n");
  const fs::path dir = testing::fresh_dir("plane");
  run(doc, "save " + (dir / "paddle.haptic").string() + "\n");
  auto spec = read_haptic_file(dir / "paddle.haptic");
  ASSERT_TRUE(spec) << spec.error().format();
  EXPECT_EQ(spec->objects[0].primitives[0].kind, ShapeKind::plane);
}

}  // namespace
}  // namespace annex::authoring
