#pragma once
// Everything about the view that is not the document: camera, panel layout,
// dialogs, viewport drags, the loaded match-preview scene. Panels read the
// EditorDocument, change only this, and ask for edits through the CommandQueue.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <imgui.h>

#include "annex/authoring/commands.h"
#include "annex/authoring/fit.h"
#include "annex/authoring/match_preview.h"
#include "annex/authoring/recent_files.h"
#include "annex/common/physical_scene.h"

namespace annex::authoring {

// Orbit camera around a target point (Y up).
struct Camera {
  float target[3] = {0.f, 0.15f, 0.f};
  float yaw_deg = 35.f;
  float pitch_deg = 22.f;
  float distance_m = 0.9f;
  float fov_deg = 40.f;
};

enum class GizmoMode { move, rotate, size };

// A drag of a viewport handle in progress.
struct HandleDrag {
  bool active = false;
  int axis = -1;  // 0, 1, 2: the primitive's local x, y, z
  ImVec2 start_mouse;
  Primitive start;  // the primitive when the drag began
  Selection target;
};

// Screen rectangle of the 3D viewport (between the panels), in pixels.
struct Rect {
  float x = 0, y = 0, w = 0, h = 0;
  bool contains(ImVec2 p) const { return p.x >= x && p.y >= y && p.x < x + w && p.y < y + h; }
};

// Where the panels and the 3D viewport sit this frame (compute_layout, view.h).
struct Layout {
  Rect outline, priorities, inspector, limits, match, viewport;
};

// A modal asking for a file path (ImGui 1.86 has no file dialog).
struct FileDialog {
  bool open_requested = false;
  AppAction::Kind purpose = AppAction::Kind::open;
  std::string title;
  std::string directory;
  std::string filename;
  std::vector<std::string> extensions;  // e.g. ".haptic"
};

// Actions waiting on "save your changes?" or "recover the autosave?".
struct Prompts {
  std::optional<AppAction> unsaved;  // New/Open/Quit with a dirty document
  bool unsaved_open_requested = false;
  std::optional<std::string> recover;  // spec path with an autosave ("" = untitled)
  bool recover_open_requested = false;
  // A spec that did not open: its file:line:column error, shown until dismissed.
  std::string open_error;
  bool open_error_requested = false;
};

struct UiState {
  Camera camera;
  Layout layout;
  GizmoMode gizmo = GizmoMode::move;
  HandleDrag drag;
  bool orbiting = false;
  ImVec2 press_pos;  // where the left button went down: a release near it is a click
  bool panning = false;

  // Box selection (Ctrl + drag): the visible surface of `box_object`'s mesh inside the
  // rectangle; Ctrl+Shift + drag (or View > Box select through) the whole depth.
  bool box_dragging = false;
  bool box_through = false;          // this drag selects through (Shift held at its start)
  bool box_select_through = false;   // View menu: every box selection selects through
  ImVec2 box_start, box_end;
  int box_object = -1;
  std::vector<Vec3> box_points;   // object frame: samples of the visible surface
  std::vector<Vec3> box_normals;  // their outward normals
  AxisSnap fit_snap = AxisSnap::none;  // Fit to selection: the axis chosen or snapped
  ShapeKind fit_kind = ShapeKind::cylinder;
  Selection fit_kind_for;  // fit_kind follows the selected primitive's shape on selection change

  bool show_wireframes = true;
  bool show_grid = true;
  bool limits_preview = false;  // draw the selected object at min and max scale
  bool rank_mode = false;       // priorities panel: forced rank instead of sliders

  // Match preview.
  std::string scene_path;
  std::optional<PhysicalScene> scene;
  std::string scene_error;
  MatchPreview preview;
  std::uint64_t preview_revision = ~0ull;
  bool preview_dirty = true;

  RecentFiles recent;
  FileDialog file_dialog;
  Prompts prompts;
  std::string status;       // last message, shown in the viewport corner
  std::string samples_dir;  // where the sample models, specs and scenes are
  // The runtime preview: annex-runtime's path when it has a `run` command (empty: not
  // found), and the source it reads (a recording, or "openni2" for the live sensor).
  std::string runtime_path;
  std::string runtime_source;
  bool quit = false;
  float frame_ms = 0;
};

}  // namespace annex::authoring
