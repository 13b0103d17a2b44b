#include "annex/authoring/editor_document.h"

#include <cstdlib>

#include <gtest/gtest.h>

#include "annex/formats/haptic_format.h"
#include "test_util.h"

namespace annex::authoring {
namespace {

// A document with one object (no mesh) holding a cylinder.
EditorDocument doc_with_cylinder() {
  EditorDocument doc;
  EXPECT_TRUE(doc.apply(cmd::AddObject{"bottle"}));
  EXPECT_TRUE(doc.apply(cmd::AddPrimitive{0, ShapeKind::cylinder, std::nullopt, "body"}));
  return doc;
}

TEST(EditorDocument, StartsEmptyCleanAndUntitled) {
  EditorDocument doc;
  EXPECT_TRUE(doc.spec().objects.empty());
  EXPECT_FALSE(doc.dirty());
  EXPECT_TRUE(doc.path().empty());
  EXPECT_FALSE(doc.can_undo());
  EXPECT_EQ(doc.title(), "untitled");
}

TEST(EditorDocument, AddSelectsTheNewPrimitiveAndUndoRedoRestore) {
  EditorDocument doc = doc_with_cylinder();
  EXPECT_EQ(doc.selection(), (Selection{0, 0}));
  EXPECT_EQ(doc.spec().objects[0].primitives[0].name, "body");
  const HapticSpec with = doc.spec();
  ASSERT_TRUE(doc.apply(cmd::Undo{}));
  EXPECT_TRUE(doc.spec().objects[0].primitives.empty());
  EXPECT_EQ(doc.selection(), (Selection{0, -1}));
  ASSERT_TRUE(doc.apply(cmd::Redo{}));
  EXPECT_EQ(doc.spec(), with);
  EXPECT_EQ(doc.selection(), (Selection{0, 0}));
}

TEST(EditorDocument, EveryEditIsUndoable) {
  EditorDocument doc;
  std::vector<Command> edits = {
      cmd::AddObject{"bottle"},
      cmd::AddPrimitive{0, ShapeKind::cylinder, std::nullopt, "body"},
      cmd::AddPrimitive{0, ShapeKind::cone, std::nullopt, "neck"},
      cmd::DuplicatePrimitive{0, 1},
      cmd::RemovePrimitive{0, 2},
      cmd::RenamePrimitive{0, 0, "bodyx"},
      cmd::SetKind{0, 1, ShapeKind::sphere},
      cmd::SetPose{0, 0, Pose{{0, 0.1, 0}, rotation_from_z({0, 1, 0})}},
      cmd::SetDimension{0, 0, 0, 0.045},
      cmd::SetScaleLimits{0, 0, 1, 0.6, 1.5},
      cmd::SetWeight{WeightLevel::object, 0, -1, -1, 0.7},
      cmd::SetWeight{WeightLevel::primitive, 0, 1, -1, 0.3},
      cmd::SetWeight{WeightLevel::dimension, 0, 0, 1, 0.2},
      cmd::SetRank{WeightLevel::dimension, 0, 0, {1, 0}},
      cmd::AddObject{"lamp"},
      cmd::SetAnnexable{1, false},
      cmd::RenameObject{1, "lamp2"},
      cmd::SetRank{WeightLevel::object, -1, -1, {1, 0}},
      cmd::ReplacePrimitive{0, 1, make_primitive(ShapeKind::torus, "ring")},
      cmd::RemoveObject{1},
  };
  std::vector<HapticSpec> states{doc.spec()};
  for (const Command& c : edits) {
    ASSERT_TRUE(doc.apply(c)) << command_label(c);
    ASSERT_TRUE(doc.apply(cmd::EndEdit{}));
    ASSERT_NE(doc.spec(), states.back()) << command_label(c) << " changed nothing";
    states.push_back(doc.spec());
  }
  for (std::size_t i = states.size() - 1; i > 0; --i) {
    ASSERT_TRUE(doc.can_undo());
    ASSERT_TRUE(doc.apply(cmd::Undo{}));
    EXPECT_EQ(doc.spec(), states[i - 1]) << "undo of step " << i;
  }
  EXPECT_FALSE(doc.can_undo());
  EXPECT_FALSE(doc.dirty());
  for (std::size_t i = 1; i < states.size(); ++i) {
    ASSERT_TRUE(doc.apply(cmd::Redo{}));
    EXPECT_EQ(doc.spec(), states[i]) << "redo of step " << i;
  }
  EXPECT_FALSE(doc.can_redo());
}

TEST(EditorDocument, SliderDragIsOneUndoStep) {
  EditorDocument doc = doc_with_cylinder();
  const std::size_t before = doc.history().size();
  for (double w : {0.9, 0.8, 0.7, 0.6})
    ASSERT_TRUE(doc.apply(cmd::SetWeight{WeightLevel::primitive, 0, 0, -1, w}));
  ASSERT_TRUE(doc.apply(cmd::EndEdit{}));
  EXPECT_EQ(doc.history().size(), before + 1);
  EXPECT_EQ(doc.spec().objects[0].primitives[0].weight, 0.6);
  ASSERT_TRUE(doc.apply(cmd::SetWeight{WeightLevel::primitive, 0, 0, -1, 0.5}));
  EXPECT_EQ(doc.history().size(), before + 2);  // after EndEdit, a new step
  ASSERT_TRUE(doc.apply(cmd::Undo{}));
  ASSERT_TRUE(doc.apply(cmd::Undo{}));
  EXPECT_EQ(doc.spec().objects[0].primitives[0].weight, 1.0);
}

TEST(EditorDocument, DifferentFieldsDoNotMerge) {
  EditorDocument doc = doc_with_cylinder();
  const std::size_t before = doc.history().size();
  ASSERT_TRUE(doc.apply(cmd::SetDimension{0, 0, 0, 0.05}));
  ASSERT_TRUE(doc.apply(cmd::SetDimension{0, 0, 1, 0.3}));
  EXPECT_EQ(doc.history().size(), before + 2);
}

TEST(EditorDocument, BadEditsAreErrorsAndChangeNothing) {
  EditorDocument doc = doc_with_cylinder();
  const HapticSpec spec = doc.spec();
  const std::size_t steps = doc.history().size();
  EXPECT_FALSE(doc.apply(cmd::SetDimension{0, 0, 5, 0.1}));
  EXPECT_FALSE(doc.apply(cmd::SetDimension{0, 0, 0, -0.1}));
  EXPECT_FALSE(doc.apply(cmd::SetWeight{WeightLevel::object, 0, -1, -1, 1.5}));
  EXPECT_FALSE(doc.apply(cmd::SetScaleLimits{0, 0, 0, 2.0, 1.0}));
  EXPECT_FALSE(doc.apply(cmd::RemovePrimitive{3, 0}));
  EXPECT_FALSE(doc.apply(cmd::SetRank{WeightLevel::primitive, 0, -1, {0, 0}}));
  EXPECT_FALSE(doc.apply(cmd::Select{{4, -1}}));
  EXPECT_FALSE(doc.apply(cmd::ImportMesh{"/nonexistent/mesh.obj", ""}));
  EXPECT_EQ(doc.spec(), spec);
  EXPECT_EQ(doc.history().size(), steps);
}

TEST(EditorDocument, NamesStayUnique) {
  EditorDocument doc = doc_with_cylinder();
  ASSERT_TRUE(doc.apply(cmd::DuplicatePrimitive{0, 0}));
  ASSERT_TRUE(doc.apply(cmd::AddObject{"bottle"}));
  EXPECT_EQ(doc.spec().objects[0].primitives[1].name, "body_2");
  EXPECT_EQ(doc.spec().objects[1].name, "bottle_2");
}

TEST(EditorDocument, RankSetsWeightsFromOrder) {
  EditorDocument doc = doc_with_cylinder();
  ASSERT_TRUE(doc.apply(cmd::AddPrimitive{0, ShapeKind::cone, std::nullopt, "neck"}));
  ASSERT_TRUE(doc.apply(cmd::SetRank{WeightLevel::primitive, 0, -1, {1, 0}}));
  EXPECT_DOUBLE_EQ(doc.spec().objects[0].primitives[1].weight, 1.0);
  EXPECT_DOUBLE_EQ(doc.spec().objects[0].primitives[0].weight, 0.5);
}

TEST(EditorDocument, AddPrimitiveWrapsTheMesh) {
  EditorDocument doc;
  ASSERT_TRUE(doc.apply(cmd::ImportMesh{doc.mesh_reference(testing::sample_model("mug.obj")), ""}));
  EXPECT_EQ(doc.spec().objects[0].name, "mug");
  ASSERT_NE(doc.mesh_for(0), nullptr);
  ASSERT_TRUE(doc.apply(cmd::AddPrimitive{0, ShapeKind::cylinder, std::nullopt, ""}));
  const Primitive& p = doc.spec().objects[0].primitives[0];
  EXPECT_EQ(p.name, "cylinder");
  EXPECT_GT(p.dimensions[0].value_m, 0.03);
  EXPECT_LT(p.dimensions[0].value_m, 0.09);
  EXPECT_GT(p.pose.position.y, 0.03);
}

TEST(EditorDocument, ValidationUsesTheFormatsWords) {
  EditorDocument doc;
  ASSERT_TRUE(doc.apply(cmd::AddObject{"bottle"}));
  const Status v = doc.validate();
  ASSERT_FALSE(v);
  const Status direct = validate_haptic(doc.spec(), "<untitled>");
  ASSERT_FALSE(direct);
  EXPECT_EQ(v.error().format(), direct.error().format());
  EXPECT_NE(v.error().message.find("has no primitive"), std::string::npos);
}

TEST(EditorDocument, SaveRefusesAnInvalidSpecAndKeepsTheOldFile) {
  const auto dir = testing::fresh_dir("save");
  EditorDocument doc = doc_with_cylinder();
  ASSERT_TRUE(doc.save_as(dir / "a.haptic"));
  ASSERT_TRUE(doc.apply(cmd::AddObject{"empty"}));  // annexable without primitives
  const Status s = doc.save();
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("has no primitive"), std::string::npos);
  auto on_disk = read_haptic_file(dir / "a.haptic");
  ASSERT_TRUE(on_disk);
  EXPECT_EQ(on_disk->objects.size(), 1u);
}

// A mesh far from the spec (here the source tree's samples, the spec in a temporary
// folder) keeps its absolute path: "../../../work/..." would break when the spec moves.
TEST(EditorDocument, AMeshFarFromTheSpecStaysAbsolute) {
  const auto dir = testing::fresh_dir("far_mesh");
  EditorDocument doc;
  ASSERT_TRUE(
      doc.apply(cmd::ImportMesh{doc.mesh_reference(testing::sample_model("torch.obj")), "torch"}));
  ASSERT_TRUE(doc.apply(cmd::AddPrimitive{0, ShapeKind::cylinder, std::nullopt, "body"}));
  ASSERT_TRUE(doc.save_as(dir / "torch.haptic"));
  const std::string mesh = doc.spec().objects[0].mesh;
  EXPECT_TRUE(std::filesystem::path(mesh).is_absolute()) << mesh;
  EXPECT_EQ(mesh.find(".."), std::string::npos) << mesh;
  EXPECT_NE(doc.mesh_for(0), nullptr);
}

TEST(EditorDocument, SaveOpenRoundTripWithRelativeMeshPath) {
  const auto dir = testing::fresh_dir("roundtrip");
  // The samples' layout: specs/ and models/ side by side.
  std::filesystem::create_directories(dir / "models");
  for (const char* f : {"torch.obj", "torch.mtl"})
    std::filesystem::copy_file(testing::sample_model(f), dir / "models" / f);
  EditorDocument doc;
  ASSERT_TRUE(
      doc.apply(cmd::ImportMesh{doc.mesh_reference(dir / "models" / "torch.obj"), "torch"}));
  ASSERT_TRUE(doc.apply(cmd::AddPrimitive{0, ShapeKind::cylinder, std::nullopt, "body"}));
  EXPECT_TRUE(doc.dirty());
  std::filesystem::create_directories(dir / "specs");
  ASSERT_TRUE(doc.save_as(dir / "specs" / "torch.haptic"));
  EXPECT_FALSE(doc.dirty());
  const std::string mesh = doc.spec().objects[0].mesh;
  EXPECT_EQ(mesh, "../models/torch.obj");
  EXPECT_NE(doc.mesh_for(0), nullptr);

  auto reopened = EditorDocument::open(dir / "specs" / "torch.haptic");
  ASSERT_TRUE(reopened) << reopened.error().format();
  EXPECT_EQ(reopened->spec(), doc.spec());
  EXPECT_NE(reopened->mesh_for(0), nullptr);
  EXPECT_TRUE(reopened->warnings().empty());
  EXPECT_FALSE(reopened->dirty());

  // Undo after save still names the mesh from the new folder.
  ASSERT_TRUE(doc.apply(cmd::Undo{}));
  EXPECT_EQ(doc.spec().objects[0].mesh, mesh);
  EXPECT_NE(doc.mesh_for(0), nullptr);
}

TEST(EditorDocument, MissingMeshIsAWarningNotAnError) {
  const auto dir = testing::fresh_dir("missing");
  testing::write_text(dir / "s.haptic",
                      "annex-haptic 1\nobject ghost\n  mesh gone.obj\n  annexable no\nend\n");
  auto doc = EditorDocument::open(dir / "s.haptic");
  ASSERT_TRUE(doc) << doc.error().format();
  EXPECT_EQ(doc->mesh_for(0), nullptr);
  ASSERT_EQ(doc->warnings().size(), 1u);
  EXPECT_NE(doc->warnings()[0].find("gone.obj"), std::string::npos);
}

TEST(EditorDocument, AutosaveAndCrashRecovery) {
  const auto dir = testing::fresh_dir("autosave");
  const auto spec = dir / "b.haptic";
  EditorDocument doc = doc_with_cylinder();
  ASSERT_TRUE(doc.save_as(spec));
  EXPECT_FALSE(has_recovery(spec));
  ASSERT_TRUE(doc.write_autosave());  // clean: nothing written
  EXPECT_FALSE(std::filesystem::exists(autosave_path_for(spec)));

  ASSERT_TRUE(doc.apply(cmd::SetDimension{0, 0, 0, 0.033}));
  ASSERT_TRUE(doc.write_autosave());
  EXPECT_EQ(doc.autosave_path(), autosave_path_for(spec));
  EXPECT_TRUE(has_recovery(spec));

  // The editor "crashes": a new session recovers the edit, unsaved.
  auto recovered = EditorDocument::open(spec, /*recover=*/true);
  ASSERT_TRUE(recovered) << recovered.error().format();
  EXPECT_EQ(recovered->spec().objects[0].primitives[0].dimensions[0].value_m, 0.033);
  EXPECT_TRUE(recovered->dirty());
  EXPECT_EQ(recovered->path(), spec);
  ASSERT_TRUE(recovered->save());
  EXPECT_FALSE(has_recovery(spec));
  EXPECT_FALSE(std::filesystem::exists(autosave_path_for(spec)));
}

TEST(EditorDocument, UntitledAutosaveGoesToTheStateDir) {
  const auto dir = testing::fresh_dir("state");
  ::setenv("ANNEX_AUTHOR_STATE_DIR", dir.c_str(), 1);
  EditorDocument doc;
  ASSERT_TRUE(doc.apply(cmd::ImportMesh{doc.mesh_reference(testing::sample_model("mug.obj")), ""}));
  ASSERT_TRUE(doc.apply(cmd::AddPrimitive{0, ShapeKind::cylinder, std::nullopt, ""}));
  ASSERT_TRUE(doc.write_autosave());
  EXPECT_EQ(doc.autosave_path(), dir / "untitled.haptic.autosave");
  EXPECT_TRUE(has_untitled_recovery());
  auto rec = EditorDocument::recover_untitled();
  ASSERT_TRUE(rec) << rec.error().format();
  EXPECT_TRUE(rec->path().empty());
  EXPECT_TRUE(rec->dirty());
  EXPECT_NE(rec->mesh_for(0), nullptr);
  doc.remove_autosave();
  EXPECT_FALSE(has_untitled_recovery());
  ::unsetenv("ANNEX_AUTHOR_STATE_DIR");
}

// The spec's exclude rules (props never to annex) survive the editor: opened, edited
// and saved, they are written back unchanged.
TEST(EditorDocument, KeepsTheSpecsExcludeRules) {
  const auto dir = testing::fresh_dir("exclude");
  const auto path = dir / "rules.haptic";
  HapticSpec spec;
  spec.exclude.push_back({"tall", std::nullopt, {{"prop_height", 0.4, std::nullopt}}});
  ASSERT_TRUE(write_haptic_file(path, spec).ok());
  auto doc = EditorDocument::open(path);
  ASSERT_TRUE(doc.ok()) << doc.error().format();
  ASSERT_TRUE(doc->apply(cmd::AddObject{"bottle"}));
  ASSERT_TRUE(doc->apply(cmd::AddPrimitive{0, ShapeKind::cylinder, std::nullopt, "body"}));
  ASSERT_TRUE(doc->save());
  const auto saved = read_haptic_file(path);
  ASSERT_TRUE(saved.ok()) << saved.error().format();
  EXPECT_EQ(saved->exclude, spec.exclude);
  EXPECT_EQ(saved->objects.size(), 1u);
}

}  // namespace
}  // namespace annex::authoring
