// The panels on a headless ImGui context (no GL, like imgui's example_null): drawing
// them emits no edits by itself, the camera orbits, dragging a handle moves the
// selected primitive as one undo step, and the modal prompts and the file dialog
// answer clicks on their buttons.
#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_internal.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <variant>
#include <unistd.h>

#include "panels.h"
#include "view.h"
#include "../unique_temp_dir.h"

namespace annex::authoring {
namespace {

class HeadlessPanels : public ::testing::Test {
 protected:
  void SetUp() override {
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(1600, 900);
    io.DeltaTime = 1.f / 60.f;
    io.IniFilename = nullptr;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    ASSERT_TRUE(doc.apply(cmd::AddObject{"bottle"}));
    Primitive body = make_primitive(ShapeKind::cylinder, "body");
    body.pose.position = {0, 0.1, 0};
    ASSERT_TRUE(doc.apply(cmd::AddPrimitive{0, ShapeKind::cylinder, body, ""}));
    ASSERT_TRUE(doc.apply(cmd::AddPrimitive{0, ShapeKind::cone, std::nullopt, "neck"}));
    ASSERT_TRUE(doc.apply(cmd::EndEdit{}));
    ui.camera.distance_m = 1.0f;
  }
  void TearDown() override { ImGui::DestroyContext(); }

  // One frame with the mouse at `mouse`, left button `down`; edits are applied after
  // the frame as the app does. Returns the frame's commands.
  std::vector<Command> frame(ImVec2 mouse, bool down) {
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = mouse;
    io.MouseDown[0] = down;
    ImGui::NewFrame();
    draw_editor(doc, ui, queue);
    ImGui::Render();
    std::vector<Command> out = queue.commands;
    for (const Command& c : queue.commands) EXPECT_TRUE(doc.apply(c)) << command_label(c);
    actions = queue.actions;
    queue = CommandQueue{};
    return out;
  }

  // The position of the widget `label` in the window whose name starts with `window`
  // (a child window's name starts with its parent's), found by hovering: the mouse
  // sweeps the window one frame per spot until ImGui reports that widget hovered.
  // `scopes` are the PushID()s around the widget (strings, or ints as in PushID(int)).
  std::optional<ImVec2> locate(const std::string& window, const char* label,
                               const std::vector<std::variant<const char*, int>>& scopes = {}) {
    frame(ImVec2(-100, -100), false);  // a popup opened last frame appears in this one
    for (ImGuiWindow* w : GImGui->Windows) {
      if (!w->Active || std::string(w->Name).rfind(window, 0) != 0) continue;
      ImGuiID seed = w->ID;
      for (const auto& scope : scopes)
        seed = std::holds_alternative<int>(scope)
                   ? ImHashData(&std::get<int>(scope), sizeof(int), seed)
                   : ImHashStr(std::get<const char*>(scope), 0, seed);
      const ImGuiID id = ImHashStr(label, 0, seed);
      for (float y = w->Pos.y + 2; y < w->Pos.y + w->Size.y; y += 4)
        for (float x = w->Pos.x + 2; x < w->Pos.x + w->Size.x; x += 8) {
          frame(ImVec2(x, y), false);
          if (GImGui->HoveredId == id) return ImVec2(x, y);
        }
    }
    return std::nullopt;
  }

  // Ctrl (+ Shift: select through) and a left drag from `from` to `to` in five steps, as
  // a person's box selection arrives frame by frame.
  void box_drag(ImVec2 from, ImVec2 to, bool shift = false) {
    ImGui::GetIO().KeyCtrl = true;
    ImGui::GetIO().KeyShift = shift;
    frame(from, false);
    frame(from, true);
    for (int i = 1; i <= 4; ++i)
      frame(ImVec2(from.x + (to.x - from.x) * i / 4, from.y + (to.y - from.y) * i / 4), true);
    frame(to, false);
    ImGui::GetIO().KeyCtrl = false;
    ImGui::GetIO().KeyShift = false;
  }

  // Presses and releases the left button at `at`; returns the app actions requested.
  std::vector<AppAction> click(ImVec2 at) {
    frame(at, true);
    frame(at, false);
    return actions;
  }

  EditorDocument doc;
  UiState ui;
  CommandQueue queue;
  std::vector<AppAction> actions;  // the last frame's file actions (not carried out here)
};

AppAction action(AppAction::Kind kind, std::string path = {}) {
  AppAction a;
  a.kind = kind;
  a.path = std::move(path);
  return a;
}

TEST_F(HeadlessPanels, UnsavedPromptDontSaveGoesOnConfirmed) {
  ui.prompts.unsaved = action(AppAction::Kind::open, "/tmp/other.haptic");
  ui.prompts.unsaved_open_requested = true;
  const auto dont = locate("Unsaved changes", "Don't save");
  ASSERT_TRUE(dont.has_value());
  const std::vector<AppAction> got = click(*dont);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].kind, AppAction::Kind::open);
  EXPECT_EQ(got[0].path, "/tmp/other.haptic");
  EXPECT_TRUE(got[0].confirmed);
  EXPECT_FALSE(ui.prompts.unsaved.has_value());
}

TEST_F(HeadlessPanels, UnsavedPromptCancelDropsTheActionAndUntitledCannotSave) {
  ui.prompts.unsaved = action(AppAction::Kind::quit);
  ui.prompts.unsaved_open_requested = true;
  // An untitled spec has nowhere to save to: Save is disabled and does nothing.
  const auto save = locate("Unsaved changes", "Save");
  ASSERT_TRUE(save.has_value());
  EXPECT_TRUE(click(*save).empty());
  EXPECT_TRUE(ui.prompts.unsaved.has_value());
  const auto cancel = locate("Unsaved changes", "Cancel");
  ASSERT_TRUE(cancel.has_value());
  EXPECT_TRUE(click(*cancel).empty());
  EXPECT_FALSE(ui.prompts.unsaved.has_value());
  EXPECT_FALSE(locate("Unsaved changes", "Cancel").has_value());  // closed
}

TEST_F(HeadlessPanels, RecoverPromptRecoversOrDiscards) {
  for (const char* button : {"Recover", "Discard autosave"}) {
    ui.prompts.recover = "/tmp/spec.haptic";
    ui.prompts.recover_open_requested = true;
    const auto at = locate("Recover unsaved work", button);
    ASSERT_TRUE(at.has_value()) << button;
    const std::vector<AppAction> got = click(*at);
    ASSERT_EQ(got.size(), 1u) << button;
    EXPECT_EQ(got[0].kind, std::string(button) == "Recover" ? AppAction::Kind::recover
                                                            : AppAction::Kind::discard_recovery);
    EXPECT_EQ(got[0].path, "/tmp/spec.haptic");
    EXPECT_FALSE(ui.prompts.recover.has_value());
  }
}

TEST_F(HeadlessPanels, DraggingARankOntoAnotherReordersThePrimitives) {
  ASSERT_TRUE(doc.apply(cmd::Select{{0, -1}}));
  ui.rank_mode = true;
  const auto body = locate("Priorities", "#1  body", {"primitives", 0});
  const auto neck = locate("Priorities", "#2  neck", {"primitives", 1});
  ASSERT_TRUE(body.has_value());
  ASSERT_TRUE(neck.has_value());
  const std::size_t steps = doc.history().size();
  // Press on the neck, drag it past ImGui's drag threshold and onto the body, release.
  frame(*neck, true);
  for (int i = 1; i <= 4; ++i)
    frame(ImVec2(neck->x, neck->y + (body->y - neck->y) * i / 4.f), true);
  frame(*body, true);
  frame(*body, false);
  const auto& prims = doc.spec().objects[0].primitives;
  EXPECT_GT(prims[1].weight, prims[0].weight);  // the neck now ranks first
  EXPECT_DOUBLE_EQ(prims[1].weight, 1.0);       // rank 1 of 2: (2 - 0) / 2
  EXPECT_DOUBLE_EQ(prims[0].weight, 0.5);       // rank 2 of 2: (2 - 1) / 2
  EXPECT_EQ(doc.history().size(), steps + 1);   // one undo step
  ASSERT_TRUE(doc.apply(cmd::Undo{}));
  EXPECT_EQ(doc.spec().objects[0].primitives[1].weight, doc.spec().objects[0].primitives[0].weight);
}

TEST_F(HeadlessPanels, FileDialogListsMatchingFilesAndOpensTheChosenOne) {
  const annex::test::TempDir dir("file_dialog");
  std::filesystem::create_directories(dir / "models");
  std::ofstream(dir / "a.haptic") << "annex-haptic 1\n";
  std::ofstream(dir / "notes.txt") << "not a spec\n";
  ui.file_dialog.open_requested = true;
  ui.file_dialog.purpose = AppAction::Kind::open;
  ui.file_dialog.title = "Open a haptic spec";
  ui.file_dialog.directory = dir.string();
  ui.file_dialog.extensions = {".haptic"};
  // Only .haptic files and folders are listed.
  EXPECT_FALSE(locate("File##dialog/entries", "notes.txt").has_value());
  const auto entry = locate("File##dialog/entries", "a.haptic");
  ASSERT_TRUE(entry.has_value());
  EXPECT_TRUE(click(*entry).empty());
  EXPECT_EQ(ui.file_dialog.filename, "a.haptic");
  const auto ok = locate("File##dialog", "OK");
  ASSERT_TRUE(ok.has_value());
  const std::vector<AppAction> got = click(*ok);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].kind, AppAction::Kind::open);
  EXPECT_EQ(std::filesystem::path(got[0].path), dir / "a.haptic");
}

TEST_F(HeadlessPanels, DrawingAloneRequestsNoEdits) {
  const HapticSpec before = doc.spec();
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(frame(ImVec2(-100, -100), false).empty());
  EXPECT_EQ(doc.spec(), before);
  // The layout leaves the viewport between the panels.
  EXPECT_GT(ui.layout.viewport.w, 500.f);
  EXPECT_GT(ui.layout.viewport.x, 200.f);
  EXPECT_LT(ui.layout.viewport.x + ui.layout.viewport.w, 1400.f);
}

TEST_F(HeadlessPanels, DraggingEmptyViewportOrbitsTheCamera) {
  ASSERT_TRUE(doc.apply(cmd::Select{{0, -1}}));  // no primitive: no handles
  frame(ImVec2(-100, -100), false);
  const ImVec2 c(ui.layout.viewport.x + ui.layout.viewport.w * 0.8f, ui.layout.viewport.y + ui.layout.viewport.h * 0.8f);
  const float yaw = ui.camera.yaw_deg;
  EXPECT_TRUE(frame(c, true).empty());
  EXPECT_TRUE(frame(ImVec2(c.x + 50, c.y), true).empty());
  EXPECT_TRUE(frame(ImVec2(c.x + 50, c.y), false).empty());
  EXPECT_NE(ui.camera.yaw_deg, yaw);
}

TEST_F(HeadlessPanels, ClickingAnObjectSelectsIt) {
  ASSERT_TRUE(doc.apply(cmd::AddObject{"lamp"}));
  ASSERT_TRUE(doc.apply(cmd::AddPrimitive{1, ShapeKind::sphere, std::nullopt, "body"}));
  ASSERT_TRUE(doc.apply(cmd::Select{{1, -1}}));
  frame(ImVec2(-100, -100), false);
  // Click on the first object's primitive centre.
  const Rect& vp = ui.layout.viewport;
  const glm::mat4 vpm = projection_matrix(ui.camera, vp.w / vp.h) * view_matrix(ui.camera);
  const glm::mat4 m =
      place_objects(doc, ui)[0].model * primitive_matrix(doc.spec().objects[0].primitives[0]);
  ImVec2 at;
  ASSERT_TRUE(project(vpm, vp, glm::vec3(m[3]), at));
  ASSERT_EQ(pick_object(doc, ui, at), 0);
  frame(at, false);
  frame(at, true);
  const std::vector<Command> released = frame(at, false);
  ASSERT_EQ(released.size(), 1u);
  EXPECT_EQ(doc.selection(), (Selection{0, -1}));
  // Far from everything: nothing picked.
  EXPECT_EQ(pick_object(doc, ui, ImVec2(vp.x + 2, vp.y + vp.h - 2)), -1);
}

TEST_F(HeadlessPanels, HandleDragMovesThePrimitiveInOneUndoStep) {
  ASSERT_TRUE(doc.apply(cmd::Select{{0, 0}}));
  frame(ImVec2(-100, -100), false);  // lays out the viewport
  ui.gizmo = GizmoMode::move;
  // Where the X handle is drawn: from the primitive's centre along its local x.
  const Rect& vp = ui.layout.viewport;
  const glm::mat4 vpm = projection_matrix(ui.camera, vp.w / vp.h) * view_matrix(ui.camera);
  const glm::mat4 m =
      place_objects(doc, ui)[0].model * primitive_matrix(doc.spec().objects[0].primitives[0]);
  ImVec2 center, tip;
  ASSERT_TRUE(project(vpm, vp, glm::vec3(m[3]), center));
  ASSERT_TRUE(project(
      vpm, vp, glm::vec3(m[3]) + glm::normalize(glm::vec3(m[0])) * ui.camera.distance_m * 0.16f,
      tip));
  const ImVec2 grab(center.x + 0.8f * (tip.x - center.x), center.y + 0.8f * (tip.y - center.y));
  const ImVec2 dir(tip.x - center.x, tip.y - center.y);

  const std::size_t steps = doc.history().size();
  const double x0 = doc.spec().objects[0].primitives[0].pose.position.x;
  frame(grab, false);
  frame(grab, true);
  for (int i = 1; i <= 3; ++i)
    frame(ImVec2(grab.x + dir.x * 0.3f * i, grab.y + dir.y * 0.3f * i), true);
  const std::vector<Command> last =
      frame(ImVec2(grab.x + dir.x * 0.9f, grab.y + dir.y * 0.9f), false);
  ASSERT_FALSE(last.empty());
  EXPECT_TRUE(std::holds_alternative<cmd::EndEdit>(last.back()));

  const Primitive& p = doc.spec().objects[0].primitives[0];
  EXPECT_GT(p.pose.position.x, x0 + 0.05);
  EXPECT_NEAR(p.pose.position.y, 0.1, 1e-6);
  EXPECT_EQ(doc.history().size(), steps + 1);
  ASSERT_TRUE(doc.apply(cmd::Undo{}));
  EXPECT_EQ(doc.spec().objects[0].primitives[0].pose.position.x, x0);
}


// At 1280x720 every Inspector button can be reached: the add buttons wrap (torus and box
// were past the panel's edge), the third handle option has its own line.
TEST_F(HeadlessPanels, At1280x720EveryInspectorButtonIsReachable) {
  ImGui::GetIO().DisplaySize = ImVec2(1280, 720);
  ASSERT_TRUE(doc.apply(cmd::Select{{0, 0}}));
  frame(ImVec2(-100, -100), false);
  for (const char* label : {"sphere", "cylinder", "cone", "torus", "box", "move", "rotate", "size"})
    EXPECT_TRUE(locate("Inspector", label).has_value()) << label;
}

// Frame selected points the camera at the selected object, not at all of them.
TEST_F(HeadlessPanels, FrameSelectedCentresTheSelectedObject) {
  ASSERT_TRUE(doc.apply(cmd::AddObject{"second"}));
  ASSERT_TRUE(doc.apply(cmd::AddPrimitive{1, ShapeKind::sphere, std::nullopt, "ball"}));
  frame(ImVec2(-100, -100), false);
  frame_all(doc, ui);
  const glm::vec3 all(ui.camera.target[0], ui.camera.target[1], ui.camera.target[2]);
  ASSERT_TRUE(doc.apply(cmd::Select{{1, -1}}));
  frame_selected(doc, ui);
  const glm::vec3 one(ui.camera.target[0], ui.camera.target[1], ui.camera.target[2]);
  const std::vector<Placement> placed = place_objects(doc, ui);
  glm::vec3 where(0);
  for (const Placement& p : placed)
    if (p.object == 1) where = glm::vec3(p.model[3]);
  EXPECT_GT(glm::length(one - all), 1e-3f);
  EXPECT_LT(std::abs(one.x - where.x), 0.06f);
}

// A spec that does not parse: the modal shows its file:line:column error until OK.
TEST_F(HeadlessPanels, ABrokenSpecShowsItsErrorInAModal) {
  ui.prompts.open_error = "bad.haptic:4:12: error: radius must be positive, found -0.1";
  ui.prompts.open_error_requested = true;
  const auto ok = locate("Could not open the spec", "OK");
  ASSERT_TRUE(ok.has_value());
  // The whole message is in the modal, wrapped, not cut: its window is wide enough.
  ImGuiWindow* modal = nullptr;
  for (ImGuiWindow* w : GImGui->Windows)
    if (w->Active && std::string(w->Name).rfind("Could not open the spec", 0) == 0) modal = w;
  ASSERT_NE(modal, nullptr);
  EXPECT_GE(modal->ContentSize.x + 1,
            std::min(ImGui::CalcTextSize(ui.prompts.open_error.c_str()).x,
                     ImGui::GetFontSize() * 45 - modal->WindowPadding.x));
  EXPECT_TRUE(click(*ok).empty());
  EXPECT_TRUE(ui.prompts.open_error.empty());
  EXPECT_FALSE(locate("Could not open the spec", "OK").has_value());
}

// The tutorial's step 2 by hand, from the view the editor opens on: import the bottle,
// click "Add primitive: cylinder", Ctrl+drag a rectangle over the lower two thirds of
// the bottle, click "Fit to box selection": radius 4.5 cm, height about 19 cm, axis up
// (docs/editor.md). The selection is the surface seen in the rectangle, so neither the
// bottom disc nor the back (cut higher by perspective) tilts or widens the fit.
TEST_F(HeadlessPanels, TutorialBoxSelectionByHandFitsTheBody) {
  doc = EditorDocument{};
  ASSERT_TRUE(doc.apply(cmd::ImportMesh{
      std::string(ANNEX_SOURCE_DIR) + "/samples/models/champagne_bottle.obj", ""}));
  ASSERT_TRUE(doc.apply(cmd::EndEdit{}));
  frame(ImVec2(-100, -100), false);
  frame_all(doc, ui);
  const auto add = locate("Inspector", "cylinder");
  ASSERT_TRUE(add.has_value());
  click(*add);
  ASSERT_EQ(doc.spec().objects.at(0).primitives.size(), 1u);
  ASSERT_EQ(doc.selection().primitive, 0);

  // Where a person drags: a little outside the bottle's sides and below its foot, up to
  // where the body meets the shoulder on the side facing them (19 cm, two thirds of 30).
  const Rect& vp = ui.layout.viewport;
  const glm::mat4 mvp = projection_matrix(ui.camera, vp.w / vp.h) * view_matrix(ui.camera) *
                        place_objects(doc, ui)[0].model;
  float left = 1e9f, right = -1e9f, bottom = -1e9f;
  for (int k = 0; k < 72; ++k) {
    const float t = 6.2831853f * k / 72;
    for (float y : {0.f, 0.2f}) {
      ImVec2 s;
      ASSERT_TRUE(project(mvp, vp, glm::vec3(0.045f * std::cos(t), y, 0.045f * std::sin(t)), s));
      left = std::min(left, s.x);
      right = std::max(right, s.x);
      bottom = std::max(bottom, s.y);
    }
  }
  const glm::vec3 eye = camera_position(ui.camera);
  const glm::vec3 toward = glm::normalize(glm::vec3(eye.x, 0, eye.z));
  ImVec2 mark;
  ASSERT_TRUE(project(mvp, vp, glm::vec3(0, 0.19f, 0) + toward * 0.045f, mark));
  const ImVec2 from(left - 12, bottom + 12), to(right + 12, mark.y);
  ASSERT_TRUE(vp.contains(from) && vp.contains(to));

  box_drag(from, to);
  ASSERT_GT(ui.box_points.size(), 200u) << ui.status;

  const std::string label =
      "Fit to box selection (" + std::to_string(ui.box_points.size()) + " points)";
  const auto fit = locate("Inspector", label.c_str());
  ASSERT_TRUE(fit.has_value()) << label;
  click(*fit);
  const Primitive& body = doc.spec().objects.at(0).primitives.at(0);
  std::printf("by hand: %zu points, radius %.2f cm, height %.2f cm, axis %.2f degrees off up\n",
              ui.box_points.size(), body.dimensions[0].value_m * 100,
              body.dimensions[1].value_m * 100,
              std::acos(std::min(1.0, std::abs(body.pose.axis().y))) * 180 / 3.14159265);
  EXPECT_EQ(body.kind, ShapeKind::cylinder);
  EXPECT_NEAR(body.dimensions[0].value_m, 0.045, 0.0015);  // radius
  EXPECT_NEAR(body.dimensions[1].value_m, 0.19, 0.012);    // height
  EXPECT_GT(std::abs(body.pose.axis().y), std::cos(1.0 * 3.14159265 / 180));  // within 1 degree
  EXPECT_NEAR(body.pose.position.x, 0, 0.002);
  EXPECT_NEAR(body.pose.position.z, 0, 0.002);

  // Step 3, the neck: "Add primitive: cone", Ctrl+drag from the shoulder to above the
  // top, "Fit to box selection": a cone standing up, its apex (+Z) at the top. The neck
  // curves, yet its normal lines all meet the bottle's axis.
  const auto add_cone = locate("Inspector", "cone");
  ASSERT_TRUE(add_cone.has_value());
  click(*add_cone);
  ASSERT_EQ(doc.selection().primitive, 1);
  ImVec2 top;
  ASSERT_TRUE(project(mvp, vp, glm::vec3(0, 0.3f, 0), top));
  const ImVec2 neck_from(left - 12, mark.y - 2), neck_to(right + 12, top.y - 12);
  box_drag(neck_from, neck_to);
  const std::string neck_label =
      "Fit to box selection (" + std::to_string(ui.box_points.size()) + " points)";
  const auto fit_neck = locate("Inspector", neck_label.c_str());
  ASSERT_TRUE(fit_neck.has_value()) << neck_label;
  click(*fit_neck);
  const Primitive& neck = doc.spec().objects.at(0).primitives.at(1);
  std::printf("neck by hand: radius %.2f cm, height %.2f cm, axis y %.4f\n",
              neck.dimensions[0].value_m * 100, neck.dimensions[1].value_m * 100,
              neck.pose.axis().y);
  EXPECT_EQ(neck.kind, ShapeKind::cone);
  EXPECT_GT(neck.pose.axis().y, std::cos(1.0 * 3.14159265 / 180));  // up, apex at the top
  EXPECT_NEAR(neck.dimensions[0].value_m, 0.045, 0.004);  // the shoulder's radius
  // From the shoulder to the top (30 cm): the rectangle's lower edge meets the front at
  // 19 cm and the sides, seen from above, lower.
  EXPECT_NEAR(neck.dimensions[1].value_m, 0.115, 0.015);

  // The same with the axis snapped to the object's up, chosen in the combo by hand.
  const auto snap = locate("Inspector", "##snap");
  ASSERT_TRUE(snap.has_value());
  click(*snap);
  const auto up = locate("##Combo", "axis: object up (+Y)", {1});  // Combo PushID()s each item
  ASSERT_TRUE(up.has_value());
  click(*up);
  ASSERT_EQ(ui.fit_snap, AxisSnap::object_up);
  const auto refit = locate("Inspector", neck_label.c_str());
  ASSERT_TRUE(refit.has_value());
  click(*refit);
  const Primitive& snapped = doc.spec().objects.at(0).primitives.at(1);
  EXPECT_NEAR(snapped.pose.axis().y, 1.0, 1e-9);
  EXPECT_NEAR(snapped.dimensions[1].value_m, neck.dimensions[1].value_m, 0.005);
}

// Ctrl+drag over the whole mug, seen from its handle's side, takes what the camera
// sees: every point faces the eye and no nearer part of the mesh (the handle in front
// of the body) lies on its line of sight. Ctrl+Shift+drag selects through: the back
// and the body behind the handle too.
TEST_F(HeadlessPanels, BoxSelectionTakesTheVisibleSurfaceOrSelectsThrough) {
  doc = EditorDocument{};
  ASSERT_TRUE(doc.apply(
      cmd::ImportMesh{std::string(ANNEX_SOURCE_DIR) + "/samples/models/mug.obj", ""}));
  ASSERT_TRUE(doc.apply(cmd::EndEdit{}));
  frame(ImVec2(-100, -100), false);
  frame_all(doc, ui);
  // The yaw that puts the eye on the handle's side (+X), a little above.
  float best_yaw = 0, best_x = -1e9f;
  for (int yaw = 0; yaw < 360; yaw += 5) {
    ui.camera.yaw_deg = static_cast<float>(yaw);
    const glm::vec3 e = camera_position(ui.camera) - glm::vec3(ui.camera.target[0], ui.camera.target[1], ui.camera.target[2]);
    if (e.x > best_x) best_x = e.x, best_yaw = static_cast<float>(yaw);
  }
  ui.camera.yaw_deg = best_yaw;
  ui.camera.pitch_deg = 15;
  frame(ImVec2(-100, -100), false);
  const MeshData* mesh = doc.mesh_for(0);
  ASSERT_NE(mesh, nullptr);
  const Placement placed = place_objects(doc, ui)[0];
  const Rect& vp = ui.layout.viewport;
  const glm::mat4 mvp = projection_matrix(ui.camera, vp.w / vp.h) * view_matrix(ui.camera) * placed.model;
  float left = 1e9f, right = -1e9f, top = 1e9f, bottom = -1e9f;
  for (std::size_t i = 0; i < mesh->vertex_count(); ++i) {
    const Vec3 v = mesh->vertex(i);
    ImVec2 s;
    ASSERT_TRUE(project(mvp, vp, glm::vec3(v.x, v.y, v.z), s));
    left = std::min(left, s.x), right = std::max(right, s.x);
    top = std::min(top, s.y), bottom = std::max(bottom, s.y);
  }
  const ImVec2 from(left - 10, top - 10), to(right + 10, bottom + 10);
  ASSERT_TRUE(vp.contains(from) && vp.contains(to));
  const glm::vec3 eye4 = glm::vec3(glm::inverse(placed.model) * glm::vec4(camera_position(ui.camera), 1));
  const glm::vec3 eye(eye4);

  // Fraction of the selected points that face away from the eye, and that a triangle
  // nearer than 1 % of their distance hides (Moller-Trumbore, every triangle).
  auto measure = [&](std::size_t& n, double& away, double& hidden) {
    n = ui.box_points.size();
    int a = 0, h = 0, tested = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const glm::vec3 p(ui.box_points[i].x, ui.box_points[i].y, ui.box_points[i].z);
      const glm::vec3 nn(ui.box_normals[i].x, ui.box_normals[i].y, ui.box_normals[i].z);
      if (glm::dot(nn, eye - p) <= 0) ++a;
      if (i % 7) continue;  // the ray test on every 7th point
      ++tested;
      const glm::vec3 dir = p - eye;
      bool blocked = false;
      for (std::size_t t = 0; t < mesh->triangle_count() && !blocked; ++t) {
        const Vec3 va = mesh->vertex(mesh->indices[3 * t]), vb = mesh->vertex(mesh->indices[3 * t + 1]),
                   vc = mesh->vertex(mesh->indices[3 * t + 2]);
        const glm::vec3 A(va.x, va.y, va.z), e1 = glm::vec3(vb.x, vb.y, vb.z) - A,
                        e2 = glm::vec3(vc.x, vc.y, vc.z) - A;
        const glm::vec3 q = glm::cross(dir, e2);
        const float det = glm::dot(e1, q);
        if (std::abs(det) < 1e-12f) continue;
        const glm::vec3 s = eye - A;
        const float u = glm::dot(s, q) / det;
        if (u < 0 || u > 1) continue;
        const glm::vec3 r = glm::cross(s, e1);
        const float v = glm::dot(dir, r) / det;
        if (v < 0 || u + v > 1) continue;
        if (glm::dot(e2, r) / det < 0.99f) blocked = true;  // along dir, 1 is the point
      }
      if (blocked) ++h;
    }
    away = n ? static_cast<double>(a) / n : 0;
    hidden = tested ? static_cast<double>(h) / tested : 0;
  };
  std::size_t seen_n = 0, through_n = 0;
  double seen_away = 0, seen_hidden = 0, through_away = 0, through_hidden = 0;
  box_drag(from, to);
  measure(seen_n, seen_away, seen_hidden);
  EXPECT_NE(ui.status.find("visible surface"), std::string::npos) << ui.status;
  box_drag(from, to, true);
  measure(through_n, through_away, through_hidden);
  EXPECT_NE(ui.status.find("through the whole depth"), std::string::npos) << ui.status;
  std::printf("visible: %zu points, %.3f facing away, %.3f hidden; through: %zu points, %.3f "
              "facing away, %.3f hidden\n",
              seen_n, seen_away, seen_hidden, through_n, through_away, through_hidden);
  ASSERT_GT(seen_n, 200u);
  EXPECT_EQ(seen_away, 0.0);
  EXPECT_LT(seen_hidden, 0.02);  // the depth cells' edges, at silhouettes
  EXPECT_GT(through_n, seen_n * 3 / 2);
  EXPECT_GT(through_away, 0.3);
  EXPECT_GT(through_hidden, 0.3);

  // View > Box select through makes a plain Ctrl+drag select through.
  ui.box_select_through = true;
  box_drag(from, to);
  EXPECT_EQ(ui.box_points.size(), through_n);
}

}  // namespace
}  // namespace annex::authoring
