// The panels on a headless ImGui context (no GL, like imgui's example_null): drawing
// them emits no edits by itself, the camera orbits, and dragging a handle moves the
// selected primitive as one undo step.
#include <gtest/gtest.h>
#include <imgui.h>

#include "panels.h"
#include "view.h"

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
    queue = CommandQueue{};
    return out;
  }

  EditorDocument doc;
  UiState ui;
  CommandQueue queue;
};

TEST_F(HeadlessPanels, DrawingAloneRequestsNoEdits) {
  const HapticSpec before = doc.spec();
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(frame(ImVec2(-100, -100), false).empty());
  EXPECT_EQ(doc.spec(), before);
  // The layout leaves the viewport between the panels.
  EXPECT_GT(ui.viewport.w, 500.f);
  EXPECT_GT(ui.viewport.x, 200.f);
  EXPECT_LT(ui.viewport.x + ui.viewport.w, 1400.f);
}

TEST_F(HeadlessPanels, DraggingEmptyViewportOrbitsTheCamera) {
  ASSERT_TRUE(doc.apply(cmd::Select{{0, -1}}));  // no primitive: no handles
  frame(ImVec2(-100, -100), false);
  const ImVec2 c(ui.viewport.x + ui.viewport.w * 0.8f, ui.viewport.y + ui.viewport.h * 0.8f);
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
  const Rect& vp = ui.viewport;
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
  const Rect& vp = ui.viewport;
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

}  // namespace
}  // namespace annex::authoring
