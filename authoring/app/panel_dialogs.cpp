// Modal dialogs: a small file chooser, "save changes?" and "recover autosave?".
#include <algorithm>
#include <filesystem>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "panels.h"

namespace annex::authoring {

namespace fs = std::filesystem;

namespace {

bool has_extension(const fs::path& p, const std::vector<std::string>& exts) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return exts.empty() || std::find(exts.begin(), exts.end(), e) != exts.end();
}

void draw_file_dialog(UiState& ui, CommandQueue& queue) {
  FileDialog& d = ui.file_dialog;
  if (d.open_requested) {
    ImGui::OpenPopup("File##dialog");
    d.open_requested = false;
  }
  ImGui::SetNextWindowSize(ImVec2(620, 440), ImGuiCond_Appearing);
  if (!ImGui::BeginPopupModal("File##dialog", nullptr)) return;
  ImGui::TextUnformatted(d.title.c_str());
  ImGui::Separator();
  ImGui::TextDisabled("%s", d.directory.c_str());
  std::vector<fs::directory_entry> entries;
  std::error_code ec;
  for (fs::directory_iterator it(d.directory, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_directory(ec) || has_extension(it->path(), d.extensions)) entries.push_back(*it);
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    if (a.is_directory() != b.is_directory()) return a.is_directory();
    return a.path().filename() < b.path().filename();
  });
  ImGui::BeginChild("entries", ImVec2(0, -70), true);
  if (ImGui::Selectable("../")) d.directory = fs::path(d.directory).parent_path().string();
  for (const auto& e : entries) {
    const std::string name = e.path().filename().string() + (e.is_directory() ? "/" : "");
    if (ImGui::Selectable(name.c_str(), name == d.filename,
                          ImGuiSelectableFlags_AllowDoubleClick)) {
      if (e.is_directory()) {
        d.directory = e.path().string();
      } else {
        d.filename = name;
        if (ImGui::IsMouseDoubleClicked(0)) {
          queue.request(d.purpose, (fs::path(d.directory) / d.filename).string());
          ImGui::CloseCurrentPopup();
        }
      }
    }
  }
  ImGui::EndChild();
  ImGui::SetNextItemWidth(-1);
  ImGui::InputTextWithHint("##name", "file name", &d.filename);
  if (ImGui::Button("OK", ImVec2(120, 0)) && !d.filename.empty()) {
    fs::path p(d.filename);
    if (p.is_relative()) p = fs::path(d.directory) / p;
    if (d.purpose == AppAction::Kind::save_as && p.extension().empty()) p += ".haptic";
    queue.request(d.purpose, p.string());
    ImGui::CloseCurrentPopup();
  }
  ImGui::SameLine();
  if (ImGui::Button("Cancel", ImVec2(120, 0))) ImGui::CloseCurrentPopup();
  ImGui::EndPopup();
}

void draw_unsaved_prompt(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  Prompts& p = ui.prompts;
  if (p.unsaved_open_requested) {
    ImGui::OpenPopup("Unsaved changes");
    p.unsaved_open_requested = false;
  }
  if (!ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize))
    return;
  ImGui::Text("Save the changes to %s first?",
              doc.path().empty() ? "untitled" : doc.path().filename().c_str());
  const Status valid = doc.validate();
  if (!valid)
    ImGui::TextColored(ImVec4(1, 0.45f, 0.4f, 1), "It cannot be saved yet: %s",
                       valid.error().message.c_str());
  ImGui::Separator();
  ImGui::BeginDisabled(!valid || doc.path().empty());
  if (ImGui::Button("Save", ImVec2(120, 0)) && p.unsaved) {
    queue.request(AppAction::Kind::save);
    queue.actions.push_back(*p.unsaved);
    queue.actions.back().confirmed = true;
    p.unsaved.reset();
    ImGui::CloseCurrentPopup();
  }
  ImGui::EndDisabled();
  ImGui::SameLine();
  if (ImGui::Button("Don't save", ImVec2(120, 0)) && p.unsaved) {
    queue.actions.push_back(*p.unsaved);
    queue.actions.back().confirmed = true;
    p.unsaved.reset();
    ImGui::CloseCurrentPopup();
  }
  ImGui::SameLine();
  if (ImGui::Button("Cancel", ImVec2(120, 0))) {
    p.unsaved.reset();
    ImGui::CloseCurrentPopup();
  }
  ImGui::EndPopup();
}

void draw_recover_prompt(UiState& ui, CommandQueue& queue) {
  Prompts& p = ui.prompts;
  if (p.recover_open_requested) {
    ImGui::OpenPopup("Recover unsaved work");
    p.recover_open_requested = false;
  }
  if (!ImGui::BeginPopupModal("Recover unsaved work", nullptr, ImGuiWindowFlags_AlwaysAutoResize))
    return;
  const std::string what = p.recover && !p.recover->empty() ? *p.recover : "an untitled spec";
  ImGui::Text("The editor stopped with unsaved changes to %s.", what.c_str());
  ImGui::Text("An autosave holds them. Recover it?");
  if (ImGui::Button("Recover", ImVec2(140, 0)) && p.recover) {
    queue.request(AppAction::Kind::recover, *p.recover);
    p.recover.reset();
    ImGui::CloseCurrentPopup();
  }
  ImGui::SameLine();
  if (ImGui::Button("Discard autosave", ImVec2(140, 0)) && p.recover) {
    queue.request(AppAction::Kind::discard_recovery, *p.recover);
    p.recover.reset();
    ImGui::CloseCurrentPopup();
  }
  ImGui::EndPopup();
}

// A spec that does not parse: its file:line:column error in red, in full.
void draw_open_error(UiState& ui) {
  Prompts& p = ui.prompts;
  if (p.open_error_requested) {
    ImGui::OpenPopup("Could not open the spec");
    p.open_error_requested = false;
  }
  ImGui::SetNextWindowSizeConstraints(ImVec2(360, 0), ImVec2(760, 600));
  if (!ImGui::BeginPopupModal("Could not open the spec", nullptr,
                              ImGuiWindowFlags_AlwaysAutoResize))
    return;
  ImGui::PushTextWrapPos(ImGui::GetFontSize() * 45);
  ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1), "%s", p.open_error.c_str());
  ImGui::PopTextWrapPos();
  ImGui::TextDisabled("Nothing was opened; fix the file and open it again.");
  if (ImGui::Button("OK", ImVec2(120, 0))) {
    p.open_error.clear();
    ImGui::CloseCurrentPopup();
  }
  ImGui::EndPopup();
}

}  // namespace

void draw_dialogs(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  draw_file_dialog(ui, queue);
  draw_unsaved_prompt(doc, ui, queue);
  draw_recover_prompt(ui, queue);
  draw_open_error(ui);
}

}  // namespace annex::authoring
