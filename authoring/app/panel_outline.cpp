// Scene outline (left): virtual objects and their primitives, annexable or virtual-only.
#include "panels.h"

namespace annex::authoring {

void draw_outline(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  place_next_window(ui.layout.outline);
  if (!ImGui::Begin(
          "Scene outline", nullptr,
          ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
              ImGuiWindowFlags_HorizontalScrollbar)) {
    ImGui::End();
    return;
  }
  if (ImGui::Button("Import mesh...")) open_file_dialog(ui, AppAction::Kind::import_mesh, doc);
  ImGui::SameLine();
  if (ImGui::Button("Empty object")) queue.push(cmd::AddObject{"object"});
  ImGui::Separator();
  const auto& objects = doc.spec().objects;
  if (objects.empty())
    ImGui::TextWrapped(
        "No virtual objects yet. Import a visual mesh (File > Import Mesh) or open a .haptic "
        "spec.");
  const Selection sel = doc.selection();
  for (int o = 0; o < static_cast<int>(objects.size()); ++o) {
    const VirtualObject& obj = objects[o];
    ImGui::PushID(o);
    bool annexable = obj.annexable;
    if (ImGui::Checkbox("##annexable", &annexable)) queue.push(cmd::SetAnnexable{o, annexable});
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(annexable ? "annexable: matched to a physical prop"
                                  : "virtual-only: never matched");
    ImGui::SameLine();
    const ImGuiTreeNodeFlags flags =
        ImGuiTreeNodeFlags_OpenOnArrow | ImGuiTreeNodeFlags_DefaultOpen |
        ImGuiTreeNodeFlags_SpanAvailWidth |
        (sel.object == o && sel.primitive < 0 ? ImGuiTreeNodeFlags_Selected : 0) |
        (obj.primitives.empty() ? ImGuiTreeNodeFlags_Leaf : 0);
    const MeshData* mesh = doc.mesh_for(o);
    const bool open = ImGui::TreeNodeEx("obj", flags, "%s%s", obj.name.c_str(),
                                        obj.annexable ? "" : "  (virtual-only)");
    if (ImGui::IsItemClicked() && !ImGui::IsItemToggledOpen()) queue.push(cmd::Select{{o, -1}});
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("%s\n%zu triangles", obj.mesh.empty() ? "no mesh" : obj.mesh.c_str(),
                        mesh ? mesh->triangle_count() : std::size_t{0});
    if (open) {
      for (int p = 0; p < static_cast<int>(obj.primitives.size()); ++p) {
        const Primitive& prim = obj.primitives[p];
        ImGui::PushID(p);
        const std::string label = prim.name + "  [" + std::string(shape_name(prim.kind)) + "]";
        if (ImGui::Selectable(label.c_str(), sel.object == o && sel.primitive == p))
          queue.push(cmd::Select{{o, p}});
        ImGui::PopID();
      }
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
  ImGui::Separator();
  ImGui::BeginDisabled(sel.object < 0);
  if (ImGui::Button(sel.primitive >= 0 ? "Remove primitive" : "Remove object")) {
    if (sel.primitive >= 0)
      queue.push(cmd::RemovePrimitive{sel.object, sel.primitive});
    else
      queue.push(cmd::RemoveObject{sel.object});
  }
  ImGui::EndDisabled();
  ImGui::End();
}

}  // namespace annex::authoring
