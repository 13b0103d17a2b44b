// The 3D viewport's interaction and 2D overlay (the GL renderer draws the scene
// underneath): orbit/pan/zoom, move/rotate/size handles on the selected primitive,
// Ctrl+drag box selection of mesh vertices, labels and the status line.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>

#include "panels.h"

namespace annex::authoring {

namespace {

constexpr ImU32 kAxisColors[3] = {IM_COL32(235, 80, 70, 255), IM_COL32(90, 210, 90, 255),
                                  IM_COL32(80, 140, 255, 255)};

float distance_to_segment(ImVec2 p, ImVec2 a, ImVec2 b) {
  const float dx = b.x - a.x, dy = b.y - a.y;
  const float len2 = dx * dx + dy * dy;
  float t = len2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0;
  t = std::clamp(t, 0.f, 1.f);
  const float cx = a.x + t * dx - p.x, cy = a.y + t * dy - p.y;
  return std::sqrt(cx * cx + cy * cy);
}

Quat axis_angle(Vec3 axis, double angle) {
  const double s = std::sin(angle / 2);
  return {std::cos(angle / 2), axis.x * s, axis.y * s, axis.z * s};
}

// Which dimension a size handle along local axis `k` changes (-1: all of them).
int size_dimension(ShapeKind kind, int k) {
  switch (kind) {
    case ShapeKind::sphere:
      return -1;
    case ShapeKind::cylinder:
    case ShapeKind::cone:
    case ShapeKind::torus:
      return k == 2 ? 1 : 0;
    case ShapeKind::box:
      return k;
  }
  return -1;
}

struct Handles {
  bool valid = false;
  ImVec2 center;
  ImVec2 tips[3];
  Vec3 axes_obj[3];  // local axes in the object frame
  float world_len = 0.1f;
};

Handles compute_handles(const EditorDocument& doc, const UiState& ui, const glm::mat4& view_proj,
                        const std::vector<Placement>& placed) {
  Handles h;
  const Selection sel = doc.selection();
  if (sel.object < 0 || sel.primitive < 0) return h;
  const Primitive& prim = doc.spec().objects[sel.object].primitives[sel.primitive];
  const Placement* pl = nullptr;
  for (const Placement& p : placed)
    if (p.object == sel.object && !p.ghost) pl = &p;
  if (pl == nullptr) return h;
  h.world_len = ui.camera.distance_m * 0.16f;
  const glm::mat4 m = pl->model * primitive_matrix(prim);
  if (!project(view_proj, ui.layout.viewport, glm::vec3(m[3]), h.center)) return h;
  for (int k = 0; k < 3; ++k) {
    const glm::vec3 dir = glm::normalize(glm::vec3(m[k]));
    if (!project(view_proj, ui.layout.viewport, glm::vec3(m[3]) + dir * h.world_len, h.tips[k])) return h;
    const Vec3 e{k == 0 ? 1.0 : 0.0, k == 1 ? 1.0 : 0.0, k == 2 ? 1.0 : 0.0};
    h.axes_obj[k] = rotate(prim.pose.rotation, e);
  }
  h.valid = true;
  return h;
}

void drag_handle(const EditorDocument& doc, UiState& ui, CommandQueue& queue, const Handles& h) {
  const HandleDrag& d = ui.drag;
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  const ImVec2 delta(mouse.x - d.start_mouse.x, mouse.y - d.start_mouse.y);
  const ImVec2 axis_px(h.tips[d.axis].x - h.center.x, h.tips[d.axis].y - h.center.y);
  const float len_px = std::max(1.f, std::sqrt(axis_px.x * axis_px.x + axis_px.y * axis_px.y));
  const float along = (delta.x * axis_px.x + delta.y * axis_px.y) / (len_px * len_px);
  Primitive p = d.start;
  if (ui.gizmo == GizmoMode::move) {
    p.pose.position = d.start.pose.position + h.axes_obj[d.axis] * (along * h.world_len);
  } else if (ui.gizmo == GizmoMode::rotate) {
    // Dragging across the handle turns about it, 0.6 degrees per pixel.
    const float across = (delta.x * -axis_px.y + delta.y * axis_px.x) / len_px;
    const Vec3 e{d.axis == 0 ? 1.0 : 0.0, d.axis == 1 ? 1.0 : 0.0, d.axis == 2 ? 1.0 : 0.0};
    p.pose.rotation = normalized(d.start.pose.rotation * axis_angle(e, across * 0.0105));
  } else {
    const double factor = std::max(0.05, 1.0 + along);
    const int dim = size_dimension(p.kind, d.axis);
    for (int i = 0; i < static_cast<int>(p.dimensions.size()); ++i)
      if (dim < 0 || dim == i)
        p.dimensions[i].value_m = std::max(1e-4, d.start.dimensions[i].value_m * factor);
  }
  (void)doc;
  queue.push(cmd::ReplacePrimitive{d.target.object, d.target.primitive, p});
}

}  // namespace

void select_box(const EditorDocument& doc, UiState& ui, ImVec2 a, ImVec2 b) {
  ui.box_start = a;
  ui.box_end = b;
  const Rect& vp = ui.layout.viewport;
  const glm::mat4 view_proj = projection_matrix(ui.camera, vp.w / vp.h) * view_matrix(ui.camera);
  const std::vector<Placement> placed = place_objects(doc, ui);
  ui.box_points.clear();
  ui.box_object = doc.selection().object;
  const MeshData* mesh = doc.mesh_for(ui.box_object);
  const Placement* pl = nullptr;
  for (const Placement& p : placed)
    if (p.object == ui.box_object && !p.ghost) pl = &p;
  if (mesh == nullptr || pl == nullptr) {
    ui.status = "Box selection: select an object with a mesh first.";
    return;
  }
  const float x0 = std::min(ui.box_start.x, ui.box_end.x),
              x1 = std::max(ui.box_start.x, ui.box_end.x);
  const float y0 = std::min(ui.box_start.y, ui.box_end.y),
              y1 = std::max(ui.box_start.y, ui.box_end.y);
  const glm::mat4 mvp = view_proj * pl->model;
  for (std::size_t i = 0; i < mesh->vertex_count(); ++i) {
    const Vec3 v = mesh->vertex(i);
    ImVec2 s;
    if (!project(mvp, ui.layout.viewport, glm::vec3(v.x, v.y, v.z), s)) continue;
    if (s.x >= x0 && s.x <= x1 && s.y >= y0 && s.y <= y1) ui.box_points.push_back(v);
  }
  char buf[96];
  std::snprintf(buf, sizeof buf, "Box selection: %zu vertices (Inspector > Fit to selection).",
                ui.box_points.size());
  ui.status = buf;
}

namespace {

void handle_keys(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantCaptureKeyboard) return;
  // The GLFW backend of ImGui 1.86 indexes keys by GLFW codes, which are ASCII for letters.
  if (io.KeyCtrl && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Z))) queue.push(cmd::Undo{});
  if (io.KeyCtrl && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Y))) queue.push(cmd::Redo{});
  if (io.KeyCtrl && ImGui::IsKeyPressed('S')) {
    if (doc.path().empty())
      open_file_dialog(ui, AppAction::Kind::save_as, doc);
    else
      queue.request(AppAction::Kind::save);
  }
  if (io.KeyCtrl && ImGui::IsKeyPressed('O')) open_file_dialog(ui, AppAction::Kind::open, doc);
  if (io.KeyCtrl && ImGui::IsKeyPressed('I'))
    open_file_dialog(ui, AppAction::Kind::import_mesh, doc);
  if (io.KeyCtrl && ImGui::IsKeyPressed('N')) queue.request(AppAction::Kind::new_document);
  if (io.KeyCtrl && ImGui::IsKeyPressed('Q')) queue.request(AppAction::Kind::quit);
  if (io.KeyCtrl) return;
  if (ImGui::IsKeyPressed('F')) queue.request(AppAction::Kind::fit_view);
  if (ImGui::IsKeyPressed('W')) ui.gizmo = GizmoMode::move;
  if (ImGui::IsKeyPressed('E')) ui.gizmo = GizmoMode::rotate;
  if (ImGui::IsKeyPressed('R')) ui.gizmo = GizmoMode::size;
  const Selection sel = doc.selection();
  if (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Delete)) && sel.object >= 0) {
    if (sel.primitive >= 0)
      queue.push(cmd::RemovePrimitive{sel.object, sel.primitive});
    else
      queue.push(cmd::RemoveObject{sel.object});
  }
}

void draw_toolbar(UiState& ui, CommandQueue& queue) {
  ImGui::SetNextWindowPos(ImVec2(ui.layout.viewport.x + 8, ui.layout.viewport.y + 8));
  ImGui::SetNextWindowBgAlpha(0.55f);
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                 ImGuiWindowFlags_NoSavedSettings |
                                 ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav |
                                 ImGuiWindowFlags_NoMove;
  if (ImGui::Begin("##viewport_toolbar", nullptr, flags)) {
    int mode = static_cast<int>(ui.gizmo);
    ImGui::RadioButton("Move (W)", &mode, 0);
    ImGui::SameLine();
    ImGui::RadioButton("Rotate (E)", &mode, 1);
    ImGui::SameLine();
    ImGui::RadioButton("Size (R)", &mode, 2);
    ui.gizmo = static_cast<GizmoMode>(mode);
    ImGui::SameLine();
    if (ImGui::Button("Frame all (F)")) queue.request(AppAction::Kind::fit_view);
    ImGui::SameLine();
    ImGui::Checkbox("wireframes", &ui.show_wireframes);
    ImGui::SameLine();
    ImGui::Checkbox("limits preview", &ui.limits_preview);
  }
  ImGui::End();
}

}  // namespace

void draw_viewport(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  draw_toolbar(ui, queue);
  ImGuiIO& io = ImGui::GetIO();
  const Rect& vp = ui.layout.viewport;
  const glm::mat4 view_proj = projection_matrix(ui.camera, vp.w / vp.h) * view_matrix(ui.camera);
  const std::vector<Placement> placed = place_objects(doc, ui);
  const Handles handles = compute_handles(doc, ui, view_proj, placed);
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  const ImVec2 mouse = io.MousePos;
  const bool hover_view = vp.contains(mouse) && !io.WantCaptureMouse;

  handle_keys(doc, ui, queue);

  // Which handle is under the mouse.
  int hovered = -1;
  if (handles.valid && hover_view && !ui.drag.active && !ui.orbiting && !ui.panning)
    for (int k = 0; k < 3; ++k)
      if (distance_to_segment(mouse, handles.center, handles.tips[k]) < 7.f) hovered = k;

  // Start of a drag.
  if (hover_view && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    if (hovered >= 0) {
      const Selection sel = doc.selection();
      ui.drag = {true, hovered, mouse, doc.spec().objects[sel.object].primitives[sel.primitive],
                 sel};
    } else if (io.KeyCtrl) {
      ui.box_dragging = true;
      ui.box_start = ui.box_end = mouse;
    } else {
      ui.orbiting = true;
      ui.press_pos = mouse;
    }
  }
  if (hover_view && (ImGui::IsMouseClicked(ImGuiMouseButton_Right) ||
                     ImGui::IsMouseClicked(ImGuiMouseButton_Middle)))
    ui.panning = true;

  if (ui.drag.active) {
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left) && handles.valid &&
        doc.selection() == ui.drag.target) {
      if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) drag_handle(doc, ui, queue, handles);
    } else {
      ui.drag.active = false;
      queue.push(cmd::EndEdit{});
    }
  }
  if (ui.orbiting) {
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
      ui.camera.yaw_deg -= io.MouseDelta.x * 0.4f;
      ui.camera.pitch_deg = std::clamp(ui.camera.pitch_deg + io.MouseDelta.y * 0.4f, -89.f, 89.f);
    } else {
      ui.orbiting = false;
      // A click (no drag) on an object selects it.
      const float dx = mouse.x - ui.press_pos.x, dy = mouse.y - ui.press_pos.y;
      if (dx * dx + dy * dy < 9.f) {
        const int picked = pick_object(doc, ui, mouse);
        if (picked >= 0 && picked != doc.selection().object) queue.push(cmd::Select{{picked, -1}});
      }
    }
  }
  if (ui.panning) {
    if (ImGui::IsMouseDown(ImGuiMouseButton_Right) || ImGui::IsMouseDown(ImGuiMouseButton_Middle)) {
      const glm::mat4 v = view_matrix(ui.camera);
      const glm::vec3 right(v[0][0], v[1][0], v[2][0]), up(v[0][1], v[1][1], v[2][1]);
      const float scale =
          ui.camera.distance_m * 2.f * std::tan(glm::radians(ui.camera.fov_deg) / 2) / vp.h;
      const glm::vec3 move = (-io.MouseDelta.x * right + io.MouseDelta.y * up) * scale;
      for (int k = 0; k < 3; ++k) ui.camera.target[k] += move[k];
    } else {
      ui.panning = false;
    }
  }
  if (ui.box_dragging) {
    ui.box_end = mouse;
    if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
      ui.box_dragging = false;
      select_box(doc, ui, ui.box_start, ui.box_end);
    }
  }
  if (hover_view && io.MouseWheel != 0)
    ui.camera.distance_m =
        std::clamp(ui.camera.distance_m * std::pow(0.88f, io.MouseWheel), 0.02f, 100.f);

  // Overlay: labels, box selection, handles, status.
  dl->PushClipRect(ImVec2(vp.x, vp.y), ImVec2(vp.x + vp.w, vp.y + vp.h), true);
  for (const Placement& p : placed) {
    ImVec2 s;
    if (!project(view_proj, vp, glm::vec3(p.model * glm::vec4(0, 0, 0, 1)), s)) continue;
    const VirtualObject& o = doc.spec().objects[p.object];
    const char* text = p.label != nullptr ? p.label : o.name.c_str();
    const ImVec2 size = ImGui::CalcTextSize(text);
    const ImU32 color = p.ghost
                            ? IM_COL32(255, 210, 120, 255)
                            : (doc.selection().object == p.object ? IM_COL32(255, 230, 90, 255)
                                                                  : IM_COL32(220, 220, 220, 220));
    dl->AddText(ImVec2(s.x - size.x / 2, s.y + 8), color, text);
  }
  if (ui.box_dragging)
    dl->AddRect(ui.box_start, ui.box_end, IM_COL32(255, 220, 60, 255), 0, 0, 1.5f);
  if (ui.box_object == doc.selection().object && !ui.box_points.empty()) {
    for (const Placement& p : placed) {
      if (p.object != ui.box_object || p.ghost) continue;
      const glm::mat4 mvp = view_proj * p.model;
      const std::size_t step = std::max<std::size_t>(1, ui.box_points.size() / 4000);
      for (std::size_t i = 0; i < ui.box_points.size(); i += step) {
        ImVec2 s;
        const Vec3& v = ui.box_points[i];
        if (project(mvp, vp, glm::vec3(v.x, v.y, v.z), s))
          dl->AddRectFilled(ImVec2(s.x - 1, s.y - 1), ImVec2(s.x + 1, s.y + 1),
                            IM_COL32(255, 220, 60, 200));
      }
    }
  }
  if (handles.valid) {
    for (int k = 0; k < 3; ++k) {
      const bool hot = hovered == k || (ui.drag.active && ui.drag.axis == k);
      const ImU32 c = hot ? IM_COL32(255, 255, 255, 255) : kAxisColors[k];
      dl->AddLine(handles.center, handles.tips[k], c, hot ? 4.f : 2.5f);
      const ImVec2 t = handles.tips[k];
      if (ui.gizmo == GizmoMode::move)
        dl->AddCircleFilled(t, 6.f, c);
      else if (ui.gizmo == GizmoMode::rotate)
        dl->AddCircle(t, 7.f, c, 16, 2.5f);
      else
        dl->AddRectFilled(ImVec2(t.x - 5, t.y - 5), ImVec2(t.x + 5, t.y + 5), c);
    }
    dl->AddCircleFilled(handles.center, 3.5f, IM_COL32(255, 255, 255, 255));
  }
  std::size_t tris = 0;
  for (const Placement& p : placed)
    if (const MeshData* m = doc.mesh_for(p.object)) tris += m->triangle_count();
  char line[320];
  std::snprintf(
      line, sizeof line,
      "%zu triangles   %.1f ms/frame   LMB orbit, RMB pan, wheel zoom, Ctrl+LMB box select   %s",
      tris, ui.frame_ms, ui.status.c_str());
  dl->AddText(ImVec2(vp.x + 10, vp.y + vp.h - 22), IM_COL32(200, 200, 200, 230), line);
  dl->PopClipRect();
}

void section(const char* title) {
  ImGui::Spacing();
  ImGui::TextColored(ImVec4(0.55f, 0.75f, 1.0f, 1.0f), "%s", title);
  ImGui::Separator();
}

void place_next_window(const Rect& r) {
  ImGui::SetNextWindowPos(ImVec2(r.x, r.y));
  ImGui::SetNextWindowSize(ImVec2(r.w, r.h));
}

void draw_editor(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  const ImGuiIO& io = ImGui::GetIO();
  draw_menu_bar(doc, ui, queue);
  const float menu_h = ImGui::GetFrameHeight();
  ui.layout = compute_layout(io.DisplaySize.x, io.DisplaySize.y, menu_h);
  draw_outline(doc, ui, queue);
  draw_priorities(doc, ui, queue);
  draw_inspector(doc, ui, queue);
  draw_limits(doc, ui, queue);
  draw_match_preview(doc, ui, queue);
  draw_viewport(doc, ui, queue);
  draw_dialogs(doc, ui, queue);
}

}  // namespace annex::authoring
