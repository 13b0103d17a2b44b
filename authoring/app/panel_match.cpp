// Match preview: for the spec being edited against a library or recorded scene,
// each virtual object's ranked candidates with votes and per-dimension terms, and
// the Hungarian assignment. Recomputed whenever the document or scene changes.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "panels.h"

namespace annex::authoring {

namespace {

void refresh(const EditorDocument& doc, UiState& ui) {
  if (!ui.scene || (!ui.preview_dirty && ui.preview_revision == doc.revision())) return;
  ui.preview = preview_match(doc.spec(), *ui.scene);
  ui.preview_revision = doc.revision();
  ui.preview_dirty = false;
}

// One line per dimension: ImGui wraps after a '.', so one long line would break inside
// a number ("w0." / "50") in a narrow column.
std::vector<std::string> terms_lines(const VoteExplanation& e) {
  std::vector<std::string> lines;
  char buf[160];
  for (const DimensionTerm& t : e.terms) {
    std::snprintf(buf, sizeof buf, "%s %.1f/%.1f cm x%.2f w%.2f", t.name.c_str(),
                  t.virtual_m * 100, t.physical_m * 100, t.ratio, t.weight);
    lines.push_back(buf);
  }
  return lines;
}

}  // namespace

void draw_match_preview(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  place_next_window(ui.layout.match);
  if (!ImGui::Begin(
          "Match preview", nullptr,
          ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
              ImGuiWindowFlags_HorizontalScrollbar)) {
    ImGui::End();
    return;
  }
  const std::string current = ui.scene_path.empty()
                                  ? std::string("(choose a scene)")
                                  : std::filesystem::path(ui.scene_path).filename().string();
  ImGui::SetNextItemWidth(240);
  if (ImGui::BeginCombo("scene", current.c_str())) {
    const std::string lib = ui.samples_dir + "/library/household.scene";
    const std::string fig3 = ui.samples_dir + "/figure3/figure3.scene";
    if (ImGui::Selectable("household library", ui.scene_path == lib))
      queue.request(AppAction::Kind::open_scene, lib);
    if (ImGui::Selectable("paper Figure 3 scene", ui.scene_path == fig3))
      queue.request(AppAction::Kind::open_scene, fig3);
    if (ImGui::Selectable("Open a .scene..."))
      open_file_dialog(ui, AppAction::Kind::open_scene, doc);
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  if (!ui.scene_error.empty()) {
    ImGui::TextColored(ImVec4(1, 0.45f, 0.4f, 1), "%s", ui.scene_error.c_str());
  } else if (ui.scene) {
    refresh(doc, ui);
    ImGui::TextDisabled("%zu physical objects; total vote %.2f (C = 100)", ui.scene->objects.size(),
                        ui.preview.total_vote);
  }
  if (!ui.scene) {
    ImGui::TextWrapped(
        "Choose a scene to see what the runtime's ObjectFinder would match. "
        "The preview follows every edit.");
    ImGui::End();
    return;
  }
  ImGui::BeginChild("preview", ImVec2(0, 0), false, ImGuiWindowFlags_HorizontalScrollbar);
  for (const ObjectPreview& o : ui.preview.objects) {
    ImGui::PushID(o.object);
    if (!o.voted) {
      ImGui::TextDisabled("%s: virtual-only (not annexable)", o.name.c_str());
      ImGui::PopID();
      continue;
    }
    char head[256];
    if (o.assigned)
      std::snprintf(head, sizeof head, "%s  ->  %s   (vote %.2f)", o.name.c_str(),
                    o.assigned_id.c_str(), o.assigned_vote);
    else
      std::snprintf(head, sizeof head, "%s  ->  stays virtual-only", o.name.c_str());
    const bool selected = doc.selection().object == o.object;
    if (ImGui::TreeNodeEx("obj", selected ? ImGuiTreeNodeFlags_DefaultOpen : 0, "%s", head)) {
      // The per-dimension breakdown wraps in its column, so nothing is cut.
      if (ImGui::BeginTable("cands", 5, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit)) {
        ImGui::TableSetupColumn("#");
        ImGui::TableSetupColumn("prop");
        ImGui::TableSetupColumn("vote", ImGuiTableColumnFlags_WidthFixed, 110);
        ImGui::TableSetupColumn("via");
        ImGui::TableSetupColumn("per dimension: virtual/physical, ratio, w_h",
                                ImGuiTableColumnFlags_WidthStretch);
        ImGui::TableHeadersRow();
        const VirtualObject& vo = doc.spec().objects[o.object];
        for (std::size_t r = 0; r < o.ranked.size(); ++r) {
          const Candidate& c = o.ranked[r];
          const VoteExplanation& e = c.explanation;
          const bool chosen = o.assigned && *o.assigned == c.physical;
          ImGui::TableNextRow();
          if (!c.excluded_by.empty()) {
            // Greyed, with the rule that keeps it out.
            ImGui::TableNextColumn();
            ImGui::TextDisabled("%zu", r + 1);
            ImGui::TableNextColumn();
            ImGui::TextDisabled("%s  (excluded)", c.id.c_str());
            ImGui::TableNextColumn();
            ImGui::TextDisabled("vote %.1f", e.vote);
            ImGui::TableNextColumn();
            ImGui::TextDisabled("-");
            ImGui::TableNextColumn();
            ImGui::TextDisabled("exclude rule %s", c.excluded_by.c_str());
            continue;
          }
          if (chosen) ImGui::TableSetBgColor(ImGuiTableBgTarget_RowBg0, IM_COL32(40, 110, 60, 160));
          ImGui::TableNextColumn();
          ImGui::Text("%zu", r + 1);
          ImGui::TableNextColumn();
          ImGui::Text("%s%s", c.id.c_str(), chosen ? "  (assigned)" : "");
          ImGui::TableNextColumn();
          char vote[32];
          std::snprintf(vote, sizeof vote, "%.2f", e.vote);
          ImGui::ProgressBar(static_cast<float>(e.vote / 100.0), ImVec2(100, 0), vote);
          ImGui::TableNextColumn();
          if (e.virtual_primitive >= 0 &&
              e.virtual_primitive < static_cast<int>(vo.primitives.size()))
            ImGui::Text("%s (%s)", vo.primitives[e.virtual_primitive].name.c_str(),
                        std::string(shape_name(vo.primitives[e.virtual_primitive].kind)).c_str());
          else
            ImGui::TextDisabled("no shared shape");
          ImGui::TableNextColumn();
          for (const std::string& line : terms_lines(e)) ImGui::TextUnformatted(line.c_str());
        }
        ImGui::EndTable();
      }
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
  ImGui::EndChild();
  ImGui::End();
}

}  // namespace annex::authoring
