// Scaling limits (paper Figure 2b): per dimension the smallest and largest scale the
// developer accepts, with a preview of the object at its min and max scale.
#include <algorithm>

#include "panels.h"

namespace annex::authoring {

void draw_limits(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  place_next_window(ui.layout.limits);
  if (!ImGui::Begin(
          "Scaling limits", nullptr,
          ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
              ImGuiWindowFlags_HorizontalScrollbar)) {
    ImGui::End();
    return;
  }
  ImGui::Checkbox("Preview min and max scale in the viewport", &ui.limits_preview);
  const Selection sel = doc.selection();
  if (sel.object < 0 || sel.primitive < 0) {
    ImGui::TextWrapped(
        "Select a primitive to set how far each of its dimensions may be scaled "
        "when the object is fitted to a prop.");
    ImGui::End();
    return;
  }
  const Primitive& prim = doc.spec().objects[sel.object].primitives[sel.primitive];
  ImGui::Text("%s (%s)", prim.name.c_str(), std::string(shape_name(prim.kind)).c_str());
  const auto names = dimension_names(prim.kind);
  if (ImGui::BeginTable("limits", 4, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerH)) {
    ImGui::TableSetupColumn("dimension", ImGuiTableColumnFlags_WidthFixed, 90);
    ImGui::TableSetupColumn("min .. max", ImGuiTableColumnFlags_WidthStretch);
    ImGui::TableSetupColumn("smallest", ImGuiTableColumnFlags_WidthFixed, 62);
    ImGui::TableSetupColumn("largest", ImGuiTableColumnFlags_WidthFixed, 62);
    ImGui::TableHeadersRow();
    for (int d = 0;
         d < static_cast<int>(prim.dimensions.size()) && d < static_cast<int>(names.size()); ++d) {
      const Dimension& dim = prim.dimensions[d];
      ImGui::PushID(d);
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::Text("%s", std::string(names[d]).c_str());
      ImGui::TableNextColumn();
      float lo = static_cast<float>(dim.min_scale), hi = static_cast<float>(dim.max_scale);
      ImGui::SetNextItemWidth(-1);
      if (ImGui::DragFloatRange2("##range", &lo, &hi, 0.01f, 0.05f, 10.f, "%.2f", "%.2f",
                                 ImGuiSliderFlags_AlwaysClamp)) {
        lo = std::max(lo, 0.05f);
        hi = std::max(hi, lo);
        queue.push(cmd::SetScaleLimits{sel.object, sel.primitive, d, lo, hi});
      }
      if (ImGui::IsItemDeactivatedAfterEdit()) queue.push(cmd::EndEdit{});
      ImGui::TableNextColumn();
      ImGui::Text("%.1f cm", dim.value_m * dim.min_scale * 100);
      ImGui::TableNextColumn();
      ImGui::Text("%.1f cm", dim.value_m * dim.max_scale * 100);
      ImGui::PopID();
    }
    ImGui::EndTable();
  }
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
  ImGui::TextWrapped("Smallest and largest: the sizes the model may be drawn at on a prop.");
  ImGui::PopStyleColor();
  ImGui::End();
}

}  // namespace annex::authoring
