// Inspector (right): the selected object or primitive, numeric fields for pose and
// dimensions, shape buttons, fit to selection and the spec's validation message.
#include <cmath>

#include <imgui.h>
#include <imgui_stdlib.h>
#include <glm/gtc/quaternion.hpp>

#include "annex/authoring/fit.h"
#include "annex/authoring/script.h"
#include "panels.h"

namespace annex::authoring {

namespace {

// Sliders and drags send an edit every frame; the step ends when the widget lets go.
void end_step_if_done(CommandQueue& queue) {
  if (ImGui::IsItemDeactivatedAfterEdit()) queue.push(cmd::EndEdit{});
}

void euler_from_quat(const Quat& q, float deg[3]) {
  const glm::vec3 e =
      glm::degrees(glm::eulerAngles(glm::quat(static_cast<float>(q.w), static_cast<float>(q.x),
                                              static_cast<float>(q.y), static_cast<float>(q.z))));
  deg[0] = e.x;
  deg[1] = e.y;
  deg[2] = e.z;
}

Quat quat_from_euler(const float deg[3]) {
  const glm::quat g(glm::radians(glm::vec3(deg[0], deg[1], deg[2])));
  return normalized(Quat{g.w, g.x, g.y, g.z});
}

// Model units and size: what the file states, and three ways to override it.
void draw_model_scale(const EditorDocument& doc, CommandQueue& queue, int o) {
  const VirtualObject& obj = doc.spec().objects[o];
  const MeshData* source = doc.source_mesh_for(o);
  if (source == nullptr) return;
  ImGui::TextDisabled("file units: %s", source->units.note.c_str());
  double scale = obj.model_scale;
  ImGui::SetNextItemWidth(120);
  if (ImGui::InputDouble("model scale (m per mesh unit)", &scale, 0, 0, "%.6g") && scale > 0)
    queue.push(cmd::SetModelScale{o, scale});
  end_step_if_done(queue);
  ImGui::TextUnformatted("mesh units:");
  for (const char* unit : {"mm", "cm", "m", "in", "ft"}) {
    ImGui::SameLine();
    if (ImGui::SmallButton(unit))
      if (const auto metres = metres_per_unit(unit)) {
        queue.push(cmd::SetModelScale{o, *metres});
        queue.push(cmd::EndEdit{});
      }
  }
  if (source->units.stated && obj.model_scale != source->units.metres_per_unit) {
    ImGui::SameLine();
    if (ImGui::SmallButton("as the file states")) {
      queue.push(cmd::SetModelScale{o, source->units.metres_per_unit});
      queue.push(cmd::EndEdit{});
    }
  }
  const double units_high = model_height_units(*source);
  double height_cm = units_high * obj.model_scale * 100;
  ImGui::SetNextItemWidth(120);
  if (ImGui::InputDouble("real height (cm, up +Y)", &height_cm, 0, 0, "%.2f",
                         ImGuiInputTextFlags_EnterReturnsTrue) &&
      height_cm > 0 && units_high > 0) {
    queue.push(cmd::SetModelScale{o, height_cm / 100 / units_high});
    queue.push(cmd::EndEdit{});
  }
}

void draw_object(const EditorDocument& doc, CommandQueue& queue, int o) {
  const VirtualObject& obj = doc.spec().objects[o];
  std::string name = obj.name;
  if (ImGui::InputText("name", &name)) queue.push(cmd::RenameObject{o, name});
  end_step_if_done(queue);
  ImGui::TextDisabled("mesh: %s", obj.mesh.empty() ? "(none)" : obj.mesh.c_str());
  if (const MeshData* m = doc.mesh_for(o)) {
    // The model's size in the AR scene (the mesh at its model_scale); opened, its units.
    if (ImGui::TreeNode("model_size", "in the scene: %.1f x %.1f x %.1f cm (%zu triangles)",
                        (m->max.x - m->min.x) * 100, (m->max.y - m->min.y) * 100,
                        (m->max.z - m->min.z) * 100, m->triangle_count())) {
      draw_model_scale(doc, queue, o);
      ImGui::TreePop();
    }
  }
  bool annexable = obj.annexable;
  if (ImGui::Checkbox("annexable (matched to a physical prop)", &annexable))
    queue.push(cmd::SetAnnexable{o, annexable});
  float w = static_cast<float>(obj.priority);
  if (ImGui::SliderFloat("object priority w_o", &w, 0.f, 1.f, "%.2f"))
    queue.push(cmd::SetWeight{WeightLevel::object, o, -1, -1, w});
  end_step_if_done(queue);
}

void draw_add_buttons(CommandQueue& queue, int o) {
  ImGui::TextUnformatted("Add primitive:");
  // The buttons wrap onto a new line rather than run past a narrow panel's edge.
  const ImGuiStyle& style = ImGui::GetStyle();
  for (ShapeKind k : kAllShapes) {
    const std::string label(shape_name(k));
    const float w = ImGui::CalcTextSize(label.c_str()).x + 2 * style.FramePadding.x;
    const float right = ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x;
    if (ImGui::GetItemRectMax().x + style.ItemSpacing.x + w <= right) ImGui::SameLine();
    if (ImGui::SmallButton(label.c_str())) queue.push(cmd::AddPrimitive{o, k, std::nullopt, ""});
  }
}

void draw_fit(const EditorDocument& doc, UiState& ui, CommandQueue& queue, int o, int p) {
  const Primitive& prim = doc.spec().objects[o].primitives[p];
  const MeshData* mesh = doc.mesh_for(o);
  if (!ImGui::CollapsingHeader("Fit to selection", ImGuiTreeNodeFlags_DefaultOpen)) return;
  if (mesh == nullptr) {
    ImGui::TextDisabled("The object has no mesh to fit to.");
    return;
  }
  if (!(ui.fit_kind_for == Selection{o, p})) {
    ui.fit_kind_for = {o, p};
    ui.fit_kind = prim.kind;
  }
  int kind = static_cast<int>(ui.fit_kind);
  const char* names[] = {"sphere", "cylinder", "cone", "torus", "box", "plane"};
  ImGui::SetNextItemWidth(120);
  if (ImGui::Combo("shape##fit", &kind, names, 6)) ui.fit_kind = static_cast<ShapeKind>(kind);
  ImGui::SameLine();
  int snap = static_cast<int>(ui.fit_snap);
  const char* snaps[] = {"axis from the points", "axis: object up (+Y)",
                         "axis: mesh's principal axis"};
  ImGui::SetNextItemWidth(-1);
  if (ImGui::Combo("##snap", &snap, snaps, 3)) ui.fit_snap = static_cast<AxisSnap>(snap);
  auto fit_to = [&](const std::vector<Vec3>& pts, const std::vector<Vec3>& normals) {
    Primitive base = prim;
    if (base.kind != ui.fit_kind) {
      base = make_primitive(ui.fit_kind, prim.name);
      base.weight = prim.weight;
    }
    FitOptions options;
    options.axis = snap_axis(ui.fit_snap, *mesh);
    options.normals = normals;
    auto fit = fit_primitive(pts, ui.fit_kind, options);
    if (!fit) {
      ui.status = fit.error().message;
      return;
    }
    queue.push(cmd::ReplacePrimitive{o, p, with_fit(base, *fit)});
    queue.push(cmd::EndEdit{});
  };
  if (ImGui::Button("Fit to whole mesh")) fit_to(mesh_points(*mesh), {});
  ImGui::SameLine();
  const bool have_box = ui.box_object == o && !ui.box_points.empty();
  ImGui::BeginDisabled(!have_box);
  const std::string box_label =
      "Fit to box selection (" + std::to_string(have_box ? ui.box_points.size() : 0) + " points)";
  if (ImGui::Button(box_label.c_str())) fit_to(ui.box_points, ui.box_normals);
  ImGui::EndDisabled();
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
  ImGui::TextWrapped("Ctrl + drag in the viewport selects the surface you see; Ctrl + Shift + "
                     "drag selects through (the back and hidden parts too).");
  ImGui::PopStyleColor();
}

void draw_primitive(const EditorDocument& doc, UiState& ui, CommandQueue& queue, int o, int p) {
  const Primitive& prim = doc.spec().objects[o].primitives[p];
  std::string name = prim.name;
  if (ImGui::InputText("primitive", &name)) queue.push(cmd::RenamePrimitive{o, p, name});
  end_step_if_done(queue);
  int kind = static_cast<int>(prim.kind);
  const char* names[] = {"sphere", "cylinder", "cone", "torus", "box", "plane"};
  if (ImGui::Combo("shape", &kind, names, 6))
    queue.push(cmd::SetKind{o, p, static_cast<ShapeKind>(kind)});
  float ws = static_cast<float>(prim.weight);
  if (ImGui::SliderFloat("primitive priority w_s", &ws, 0.f, 1.f, "%.2f"))
    queue.push(cmd::SetWeight{WeightLevel::primitive, o, p, -1, ws});
  end_step_if_done(queue);

  section("Pose (relative to the object)");
  float pos[3] = {static_cast<float>(prim.pose.position.x),
                  static_cast<float>(prim.pose.position.y),
                  static_cast<float>(prim.pose.position.z)};
  if (ImGui::DragFloat3("position m", pos, 0.001f, -10.f, 10.f, "%.3f")) {
    Pose pose = prim.pose;
    pose.position = {pos[0], pos[1], pos[2]};
    queue.push(cmd::SetPose{o, p, pose});
  }
  end_step_if_done(queue);
  float euler[3];
  euler_from_quat(prim.pose.rotation, euler);
  if (ImGui::DragFloat3("rotation deg", euler, 0.5f, -360.f, 360.f, "%.1f")) {
    Pose pose = prim.pose;
    pose.rotation = quat_from_euler(euler);
    queue.push(cmd::SetPose{o, p, pose});
  }
  end_step_if_done(queue);
  const Vec3 axis = prim.pose.axis();
  ImGui::TextDisabled("axis (local +Z): %.2f %.2f %.2f", axis.x, axis.y, axis.z);

  section("Dimensions");
  const auto dim_names = dimension_names(prim.kind);
  for (int d = 0;
       d < static_cast<int>(prim.dimensions.size()) && d < static_cast<int>(dim_names.size());
       ++d) {
    float v = static_cast<float>(prim.dimensions[d].value_m);
    const std::string label = std::string(dim_names[d]) + " m";
    if (ImGui::DragFloat(label.c_str(), &v, 0.0005f, 0.001f, 5.f, "%.4f") && v > 0)
      queue.push(cmd::SetDimension{o, p, d, v});
    end_step_if_done(queue);
  }
  ImGui::Spacing();
  if (ImGui::Button("Duplicate")) queue.push(cmd::DuplicatePrimitive{o, p});
  ImGui::SameLine();
  if (ImGui::Button("Remove")) queue.push(cmd::RemovePrimitive{o, p});
  // On a line of their own: beside the buttons the third option ran past the panel.
  ImGui::TextDisabled("handles:");
  ImGui::SameLine();
  int mode = static_cast<int>(ui.gizmo);
  ImGui::RadioButton("move", &mode, 0);
  ImGui::SameLine();
  ImGui::RadioButton("rotate", &mode, 1);
  ImGui::SameLine();
  ImGui::RadioButton("size", &mode, 2);
  ui.gizmo = static_cast<GizmoMode>(mode);
  draw_fit(doc, ui, queue, o, p);
}

}  // namespace

void draw_inspector(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  place_next_window(ui.layout.inspector);
  if (!ImGui::Begin(
          "Inspector", nullptr,
          ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
              ImGuiWindowFlags_HorizontalScrollbar)) {
    ImGui::End();
    return;
  }
  // Text wraps at the panel's visible right edge: with the horizontal scrollbar (a long
  // mesh path), TextWrapped alone wraps at the content's width, off screen.
  const ImGuiStyle& style = ImGui::GetStyle();
  ImGui::PushTextWrapPos(ImGui::GetScrollX() + ImGui::GetWindowWidth() - style.WindowPadding.x -
                         style.ScrollbarSize);
  ImGui::PushItemWidth(-150);
  const Selection sel = doc.selection();
  if (sel.object < 0) {
    ImGui::TextWrapped("Select an object in the outline.");
  } else {
    draw_object(doc, queue, sel.object);
    ImGui::Separator();
    draw_add_buttons(queue, sel.object);
    if (sel.primitive >= 0) {
      ImGui::Separator();
      draw_primitive(doc, ui, queue, sel.object, sel.primitive);
    }
  }
  ImGui::PopItemWidth();
  ImGui::Separator();
  // The same check and words as `annex-runtime check`.
  const Status valid = doc.validate();
  bool any_annexable = false;
  for (const VirtualObject& o : doc.spec().objects) any_annexable |= o.annexable;
  if (valid && doc.spec().objects.empty()) {
    ImGui::TextWrapped("Empty spec: import a mesh (File > Import Mesh..., Ctrl+I) or open a "
                       "spec (Ctrl+O).");
  } else if (valid && !any_annexable) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.8f, 0.3f, 1));
    ImGui::TextWrapped("Valid, but no object is annexable: annex-runtime run would match no "
                       "prop (the same warning as annex-runtime check).");
    ImGui::PopStyleColor();
  } else if (valid) {
    ImGui::TextColored(ImVec4(0.45f, 0.85f, 0.45f, 1),
                       "Valid: annex-runtime check accepts this spec.");
  } else {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.5f, 0.45f, 1));
    ImGui::TextWrapped("%s", valid.error().format().c_str());
    ImGui::PopStyleColor();
  }
  for (const std::string& w : doc.warnings()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.8f, 0.3f, 1));
    ImGui::TextWrapped("%s", w.c_str());
    ImGui::PopStyleColor();
  }
  ImGui::PopTextWrapPos();
  ImGui::End();
}

}  // namespace annex::authoring
