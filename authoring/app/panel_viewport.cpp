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
    case ShapeKind::plane:  // no thickness: the normal's handle (k = 2) sizes nothing
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

namespace {

// A vertex of the selected object on screen: pixels, and 1/w (linear across a
// triangle on screen, so depths interpolate exactly).
struct ScreenPoint {
  float x = 0, y = 0, inv_w = 0;
  bool ok = false;
};

ScreenPoint to_screen(const glm::mat4& mvp, const Rect& vp, glm::vec3 p) {
  const glm::vec4 c = mvp * glm::vec4(p, 1.f);
  ScreenPoint s;
  if (c.w <= 1e-6f) return s;
  s.x = vp.x + (c.x / c.w * 0.5f + 0.5f) * vp.w;
  s.y = vp.y + (1.f - (c.y / c.w * 0.5f + 0.5f)) * vp.h;
  s.inv_w = 1.f / c.w;
  s.ok = true;
  return s;
}

// The nearest surface of one mesh under each pixel of a screen rectangle, as 1/w
// (larger is nearer): what the user sees there, so a selection can skip the back.
struct DepthBuffer {
  float x0 = 0, y0 = 0, step = 1;
  int w = 0, h = 0;
  std::vector<float> inv_w;  // 0: no surface

  float at(float x, float y) const {
    const int i = static_cast<int>((x - x0) / step), j = static_cast<int>((y - y0) / step);
    if (i < 0 || j < 0 || i >= w || j >= h) return 0;
    return inv_w[static_cast<std::size_t>(j) * w + i];
  }

  void add_triangle(const ScreenPoint& a, const ScreenPoint& b, const ScreenPoint& c) {
    const float area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (std::abs(area) < 1e-9f) return;
    const int i0 = std::max(0, static_cast<int>((std::min({a.x, b.x, c.x}) - x0) / step));
    const int i1 = std::min(w - 1, static_cast<int>((std::max({a.x, b.x, c.x}) - x0) / step));
    const int j0 = std::max(0, static_cast<int>((std::min({a.y, b.y, c.y}) - y0) / step));
    const int j1 = std::min(h - 1, static_cast<int>((std::max({a.y, b.y, c.y}) - y0) / step));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const float px = x0 + (i + 0.5f) * step, py = y0 + (j + 0.5f) * step;
        const float l1 = ((px - a.x) * (c.y - a.y) - (c.x - a.x) * (py - a.y)) / area;
        const float l2 = ((b.x - a.x) * (py - a.y) - (px - a.x) * (b.y - a.y)) / area;
        const float l0 = 1 - l1 - l2;
        if (l0 < 0 || l1 < 0 || l2 < 0) continue;
        float& d = inv_w[static_cast<std::size_t>(j) * w + i];
        d = std::max(d, l0 * a.inv_w + l1 * b.inv_w + l2 * c.inv_w);
      }
  }
};

}  // namespace

// The box selection is the surface the user sees inside the rectangle: triangles
// facing the camera, sampled evenly by area and kept where no nearer part of the mesh
// hides them. Taking every vertex whose projection falls inside (as a screen test
// alone does) adds the bottom disc and the back, whose outline perspective cuts at
// another height, and tilts and widens the fit. Selecting through (like Blender's
// X-ray box select) keeps them, for a part hidden behind another.
void select_box(const EditorDocument& doc, UiState& ui, ImVec2 a, ImVec2 b, bool through) {
  ui.box_start = a;
  ui.box_end = b;
  const Rect& vp = ui.layout.viewport;
  const glm::mat4 view_proj = projection_matrix(ui.camera, vp.w / vp.h) * view_matrix(ui.camera);
  const std::vector<Placement> placed = place_objects(doc, ui);
  ui.box_points.clear();
  ui.box_normals.clear();
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
  const glm::vec3 eye = glm::vec3(glm::inverse(pl->model) * glm::vec4(camera_position(ui.camera), 1));
  std::vector<ScreenPoint> screen(mesh->vertex_count());
  for (std::size_t i = 0; i < screen.size(); ++i) {
    const Vec3 v = mesh->vertex(i);
    screen[i] = to_screen(mvp, vp, glm::vec3(v.x, v.y, v.z));
  }
  // At most 512 depth cells across the rectangle: a pixel's worth for any viewport.
  DepthBuffer depth;
  depth.x0 = x0;
  depth.y0 = y0;
  depth.step = std::max({1.f, (x1 - x0) / 512.f, (y1 - y0) / 512.f});
  depth.w = static_cast<int>((x1 - x0) / depth.step) + 1;
  depth.h = static_cast<int>((y1 - y0) / depth.step) + 1;
  depth.inv_w.assign(static_cast<std::size_t>(depth.w) * depth.h, 0.f);
  const std::size_t tris = mesh->triangle_count();
  for (std::size_t t = 0; t < tris; ++t) {
    const ScreenPoint& pa = screen[mesh->indices[3 * t]];
    const ScreenPoint& pb = screen[mesh->indices[3 * t + 1]];
    const ScreenPoint& pc = screen[mesh->indices[3 * t + 2]];
    if (!through && pa.ok && pb.ok && pc.ok) depth.add_triangle(pa, pb, pc);
  }
  // Samples about one per two pixels of the mesh's size on screen.
  glm::vec3 lo(mesh->min.x, mesh->min.y, mesh->min.z), hi(mesh->max.x, mesh->max.y, mesh->max.z);
  const float spacing = std::max(1e-4f, glm::length(hi - lo) / 400.f);
  float carry = 0;
  std::uint32_t rng = 12345;
  auto uniform = [&rng] {
    rng = rng * 1664525u + 1013904223u;
    return static_cast<float>(rng >> 8) / 16777216.f;
  };
  for (std::size_t t = 0; t < tris; ++t) {
    const std::uint32_t ia = mesh->indices[3 * t], ib = mesh->indices[3 * t + 1],
                        ic = mesh->indices[3 * t + 2];
    const Vec3 va = mesh->vertex(ia), vb = mesh->vertex(ib), vc = mesh->vertex(ic);
    const glm::vec3 A(va.x, va.y, va.z), B(vb.x, vb.y, vb.z), C(vc.x, vc.y, vc.z);
    const glm::vec3 n = glm::cross(B - A, C - A);
    const float len = glm::length(n);
    if (len <= 0) continue;
    const glm::vec3 unit = n / len;
    // Faces turned away from the eye are the back (winding is counter-clockwise seen
    // from outside; the vertex normals break ties on meshes wound the other way).
    const glm::vec3 vn(mesh->normals[3 * ia] + mesh->normals[3 * ib] + mesh->normals[3 * ic],
                       mesh->normals[3 * ia + 1] + mesh->normals[3 * ib + 1] +
                           mesh->normals[3 * ic + 1],
                       mesh->normals[3 * ia + 2] + mesh->normals[3 * ib + 2] +
                           mesh->normals[3 * ic + 2]);
    const glm::vec3 outward = glm::dot(vn, unit) < 0 ? -unit : unit;
    if (!through && glm::dot(outward, eye - (A + B + C) / 3.f) <= 0) continue;
    const ScreenPoint &pa = screen[ia], &pb = screen[ib], &pc = screen[ic];
    if (!pa.ok || !pb.ok || !pc.ok) continue;
    if (std::max({pa.x, pb.x, pc.x}) < x0 || std::min({pa.x, pb.x, pc.x}) > x1 ||
        std::max({pa.y, pb.y, pc.y}) < y0 || std::min({pa.y, pb.y, pc.y}) > y1)
      continue;
    carry += 0.5f * len / (spacing * spacing);
    // Every triangle inside gets at least its centroid, so small ones are not lost.
    int count = static_cast<int>(carry);
    carry -= static_cast<float>(count);
    if (count == 0) count = 1;
    for (int k = 0; k < count; ++k) {
      float u = k == 0 ? 1.f / 3 : uniform(), v = k == 0 ? 1.f / 3 : uniform();
      if (u + v > 1) u = 1 - u, v = 1 - v;
      const glm::vec3 p = A + (B - A) * u + (C - A) * v;
      const ScreenPoint s = to_screen(mvp, vp, p);
      if (!s.ok || s.x < x0 || s.x > x1 || s.y < y0 || s.y > y1) continue;
      // Hidden when a nearer surface covers it by more than 1 % of its distance.
      if (!through && s.inv_w < depth.at(s.x, s.y) * 0.99f) continue;
      ui.box_points.push_back({p.x, p.y, p.z});
      ui.box_normals.push_back({outward.x, outward.y, outward.z});
    }
  }
  char buf[140];
  std::snprintf(buf, sizeof buf, "Box selection: %zu points of the %s (Inspector > Fit to selection).",
                ui.box_points.size(),
                through ? "surface through the whole depth" : "visible surface");
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
  if (ImGui::IsKeyPressed('F')) {
    if (ImGui::GetIO().KeyShift)
      frame_selected(doc, ui);
    else
      queue.request(AppAction::Kind::fit_view);
  }
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

void draw_toolbar(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  ImGui::SetNextWindowPos(ImVec2(ui.layout.viewport.x + 8, ui.layout.viewport.y + 8));
  ImGui::SetNextWindowBgAlpha(0.55f);
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                 ImGuiWindowFlags_NoSavedSettings |
                                 ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav |
                                 ImGuiWindowFlags_NoMove;
  if (ImGui::Begin("##viewport_toolbar", nullptr, flags)) {
    // Items go on one line while it fits in the viewport, then on the next (1280x720).
    const ImGuiStyle& style = ImGui::GetStyle();
    const float right_edge = ui.layout.viewport.x + ui.layout.viewport.w - 16;
    const float box = ImGui::GetFrameHeight() + style.ItemInnerSpacing.x;  // radio, checkbox
    const float pad = 2 * style.FramePadding.x;                            // button
    auto beside = [&](const char* next, float extra) {
      if (ImGui::GetItemRectMax().x + style.ItemSpacing.x + ImGui::CalcTextSize(next).x + extra +
              style.WindowPadding.x <=
          right_edge)
        ImGui::SameLine();
    };
    int mode = static_cast<int>(ui.gizmo);
    ImGui::RadioButton("Move (W)", &mode, 0);
    beside("Rotate (E)", box);
    ImGui::RadioButton("Rotate (E)", &mode, 1);
    beside("Size (R)", box);
    ImGui::RadioButton("Size (R)", &mode, 2);
    ui.gizmo = static_cast<GizmoMode>(mode);
    beside("Frame all (F)", pad);
    if (ImGui::Button("Frame all (F)")) queue.request(AppAction::Kind::fit_view);
    beside("Frame selected", pad);
    ImGui::BeginDisabled(doc.selection().object < 0);
    if (ImGui::Button("Frame selected")) frame_selected(doc, ui);
    ImGui::EndDisabled();
    beside("wireframes", box);
    ImGui::Checkbox("wireframes", &ui.show_wireframes);
    beside("limits preview", box);
    ImGui::Checkbox("limits preview", &ui.limits_preview);
  }
  ImGui::End();
}

}  // namespace

void draw_viewport(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  draw_toolbar(doc, ui, queue);
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
      ui.box_through = io.KeyShift || ui.box_select_through;
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
      select_box(doc, ui, ui.box_start, ui.box_end, ui.box_through);
    }
  }
  if (hover_view && io.MouseWheel != 0)
    ui.camera.distance_m =
        std::clamp(ui.camera.distance_m * std::pow(0.88f, io.MouseWheel), 0.02f, 100.f);

  // Overlay: labels, box selection, handles, status.
  dl->PushClipRect(ImVec2(vp.x, vp.y), ImVec2(vp.x + vp.w, vp.y + vp.h), true);
  // Names under their objects, kept inside the viewport and moved down a line until
  // they overlap no name already placed (side-by-side objects seen at a slant).
  std::vector<ImVec4> taken;
  for (const Placement& p : placed) {
    ImVec2 s;
    if (!project(view_proj, vp, glm::vec3(p.model * glm::vec4(0, 0, 0, 1)), s)) continue;
    if (!vp.contains(s)) continue;  // an object out of view keeps its name out of view too
    const VirtualObject& o = doc.spec().objects[p.object];
    const char* text = p.label != nullptr ? p.label : o.name.c_str();
    const ImVec2 size = ImGui::CalcTextSize(text);
    const ImU32 color = p.ghost
                            ? IM_COL32(255, 210, 120, 255)
                            : (doc.selection().object == p.object ? IM_COL32(255, 230, 90, 255)
                                                                  : IM_COL32(220, 220, 220, 220));
    float x = std::clamp(s.x - size.x / 2, vp.x + 2, std::max(vp.x + 2, vp.x + vp.w - size.x - 2));
    float y = s.y + 8;
    for (int tries = 0; tries < 12; ++tries) {
      bool clear = true;
      for (const ImVec4& t : taken)
        clear = clear && (x + size.x <= t.x || t.z <= x || y + size.y <= t.y || t.w <= y);
      if (clear) break;
      y += size.y + 1;
    }
    y = std::clamp(y, vp.y + 2, std::max(vp.y + 2, vp.y + vp.h - size.y - 2));
    taken.push_back(ImVec4(x, y, x + size.x, y + size.y));
    dl->AddRectFilled(ImVec2(x - 2, y), ImVec2(x + size.x + 2, y + size.y), IM_COL32(0, 0, 0, 110));
    dl->AddText(ImVec2(x, y), color, text);
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
  // The hints on one line and, under them, the status wrapped to the viewport's width,
  // so a long status (a box selection's count) is never cut at 1280x720.
  char line[320];
  std::snprintf(line, sizeof line,
                "%zu triangles   %.1f ms/frame   LMB orbit, RMB pan, wheel zoom, Ctrl+LMB box "
                "select (+Shift: through)",
                tris, ui.frame_ms);
  const float wrap = std::max(50.f, vp.w - 20);
  const float status_h =
      ui.status.empty() ? 0.f : ImGui::CalcTextSize(ui.status.c_str(), nullptr, false, wrap).y;
  const float line_h = ImGui::GetTextLineHeight();
  const float bottom = vp.y + vp.h - 6;
  if (!ui.status.empty())
    dl->AddText(ImGui::GetFont(), ImGui::GetFontSize(), ImVec2(vp.x + 10, bottom - status_h),
                IM_COL32(200, 200, 200, 230), ui.status.c_str(), nullptr, wrap);
  dl->AddText(ImVec2(vp.x + 10, bottom - status_h - line_h), IM_COL32(200, 200, 200, 230), line);
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
