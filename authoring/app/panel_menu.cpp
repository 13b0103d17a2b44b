// The menu bar: File, Edit, View, Runtime.
#include <filesystem>

#include "panels.h"

namespace annex::authoring {

namespace {

void ask_path(UiState& ui, AppAction::Kind purpose, std::string title,
              std::vector<std::string> extensions, std::string directory) {
  FileDialog& d = ui.file_dialog;
  d.open_requested = true;
  d.purpose = purpose;
  d.title = std::move(title);
  d.extensions = std::move(extensions);
  if (!directory.empty()) d.directory = std::move(directory);
  if (d.directory.empty()) d.directory = std::filesystem::current_path().string();
  d.filename.clear();
}

}  // namespace

void open_file_dialog(UiState& ui, AppAction::Kind purpose, const EditorDocument& doc) {
  const std::string models = ui.samples_dir.empty() ? "" : ui.samples_dir + "/models";
  const std::string specs = ui.samples_dir.empty() ? "" : ui.samples_dir + "/specs";
  const std::string here = doc.path().empty() ? "" : doc.path().parent_path().string();
  switch (purpose) {
    case AppAction::Kind::open:
      ask_path(ui, purpose, "Open haptic spec", {".haptic"}, here.empty() ? specs : here);
      break;
    case AppAction::Kind::save_as: {
      // A new spec goes where the editor was started (the user's folder), not into the
      // bundled samples.
      std::error_code ec;
      const std::string cwd = std::filesystem::current_path(ec).string();
      ask_path(ui, purpose, "Save haptic spec as", {".haptic"}, here.empty() ? cwd : here);
      break;
    }
    case AppAction::Kind::import_mesh:
      ask_path(ui, purpose, "Import visual mesh",
               {".obj", ".gltf", ".glb", ".fbx", ".ply", ".stl", ".dae"}, models);
      break;
    case AppAction::Kind::choose_source:
      ask_path(ui, purpose,
               "Recording for annex-runtime run (a .pcd file or folder, a TUM RGB-D or depth "
               "PNG folder, a depth .png, or .oni)",
               {".pcd", ".png", ".oni"}, "");
      break;
    case AppAction::Kind::open_scene:
      ask_path(ui, purpose, "Open scene for the match preview", {".scene"},
               ui.samples_dir.empty() ? "" : ui.samples_dir + "/library");
      break;
    default:
      break;
  }
}

void draw_menu_bar(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  if (!ImGui::BeginMainMenuBar()) return;
  if (ImGui::BeginMenu("File")) {
    if (ImGui::MenuItem("New", "Ctrl+N")) queue.request(AppAction::Kind::new_document);
    if (ImGui::MenuItem("Open...", "Ctrl+O")) open_file_dialog(ui, AppAction::Kind::open, doc);
    if (ImGui::BeginMenu("Open Recent", !ui.recent.paths.empty())) {
      for (const std::string& p : ui.recent.paths)
        if (ImGui::MenuItem(p.c_str())) queue.request(AppAction::Kind::open, p);
      ImGui::EndMenu();
    }
    ImGui::Separator();
    if (ImGui::MenuItem("Import Mesh...", "Ctrl+I"))
      open_file_dialog(ui, AppAction::Kind::import_mesh, doc);
    ImGui::Separator();
    if (ImGui::MenuItem("Save", "Ctrl+S")) {
      if (doc.path().empty())
        open_file_dialog(ui, AppAction::Kind::save_as, doc);
      else
        queue.request(AppAction::Kind::save);
    }
    if (ImGui::MenuItem("Save As...")) open_file_dialog(ui, AppAction::Kind::save_as, doc);
    ImGui::Separator();
    if (ImGui::MenuItem("Quit", "Ctrl+Q")) queue.request(AppAction::Kind::quit);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Edit")) {
    const std::string undo = "Undo " + doc.undo_label();
    const std::string redo = "Redo " + doc.redo_label();
    if (ImGui::MenuItem(undo.c_str(), "Ctrl+Z", false, doc.can_undo())) queue.push(cmd::Undo{});
    if (ImGui::MenuItem(redo.c_str(), "Ctrl+Y", false, doc.can_redo())) queue.push(cmd::Redo{});
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("View")) {
    ImGui::MenuItem("Grid", nullptr, &ui.show_grid);
    ImGui::MenuItem("Primitive wireframes", nullptr, &ui.show_wireframes);
    ImGui::MenuItem("Scaling-limits preview", nullptr, &ui.limits_preview);
    ImGui::MenuItem("Box select through", "Ctrl+Shift+drag", &ui.box_select_through);
    if (ImGui::MenuItem("Frame all", "F")) queue.request(AppAction::Kind::fit_view);
    if (ImGui::MenuItem("Frame selected", "Shift+F", false, doc.selection().object >= 0))
      frame_selected(doc, ui);
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Runtime")) {
    // Each reason the preview cannot start is said on the disabled item.
    const char* missing = nullptr;
    if (ui.runtime_path.empty())
      missing = "needs annex-runtime run (runtime issue)";
    else if (doc.path().empty() || doc.dirty())
      missing = "save the spec first: the runtime reads the file";
    else if (ui.runtime_source.empty())
      missing = "choose a recording or the live sensor first";
    if (ImGui::MenuItem("Preview in annex-runtime run", nullptr, false, missing == nullptr))
      queue.request(AppAction::Kind::run_preview);
    if (missing != nullptr && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
      ImGui::SetTooltip("%s", missing);
    ImGui::Separator();
    const std::string source =
        "Source: " + (ui.runtime_source.empty() ? std::string("(none)") : ui.runtime_source);
    ImGui::MenuItem(source.c_str(), nullptr, false, false);
    if (ImGui::MenuItem("Choose recording (.pcd, depth .png, folder, .oni)...", nullptr, false,
                        !ui.runtime_path.empty()))
      open_file_dialog(ui, AppAction::Kind::choose_source, doc);
    if (ImGui::MenuItem("Live sensor (openni2)", nullptr, ui.runtime_source == "openni2",
                        !ui.runtime_path.empty()))
      queue.request(AppAction::Kind::choose_source, "openni2");
    ImGui::EndMenu();
  }
  const Status valid = doc.validate();
  ImGui::SameLine(ImGui::GetWindowWidth() - 330);
  if (valid && doc.spec().objects.empty())
    ImGui::TextDisabled("empty spec");
  else if (valid)
    ImGui::TextColored(ImVec4(0.45f, 0.85f, 0.45f, 1), "spec valid");
  else
    ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1), "spec invalid (see Inspector)");
  ImGui::SameLine();
  ImGui::TextDisabled("%s", doc.title().c_str());
  ImGui::EndMainMenuBar();
}

}  // namespace annex::authoring
