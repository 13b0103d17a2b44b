#pragma once
// The document the editor edits: the haptic spec, the meshes it points at, the
// selection, the file path and the undo history. No GL and no ImGui here, so every
// edit is unit-tested; the UI state (camera, panels) lives in the app's UiState.

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "annex/authoring/commands.h"
#include "annex/authoring/mesh.h"
#include "annex/common/haptic_model.h"
#include "annex/common/result.h"

namespace annex::authoring {

// One undo step: the spec before and after, so undo restores exactly.
struct UndoStep {
  std::string label;
  HapticSpec before;
  HapticSpec after;
  Selection selection_before;
  Selection selection_after;
  std::string merge_key;  // consecutive edits with the same key join this step while open
  bool open = false;
};

class EditorDocument {
 public:
  // An untitled, empty document.
  EditorDocument() = default;

  // Reads a .haptic file and the meshes it names. `recover` reads the autosave
  // sidecar instead (crash recovery) and leaves the document dirty. Meshes that
  // cannot be loaded become warnings(), not errors.
  static Result<EditorDocument> open(const std::filesystem::path& path, bool recover = false);
  // Reads the autosave of an untitled document (its mesh paths are absolute).
  static Result<EditorDocument> recover_untitled();

  const HapticSpec& spec() const { return spec_; }
  const Selection& selection() const { return selection_; }
  const std::filesystem::path& path() const { return path_; }  // empty: untitled
  std::string title() const;
  bool dirty() const { return spec_ != saved_; }
  // Bumped by every change of the spec (caches key on it).
  std::uint64_t revision() const { return revision_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  // What open and save did to files other than the spec, for the editor's log: each
  // stale temporary file of the spec they removed (left by a save that was killed;
  // see remove_stale_temporaries). Returns the lines once and forgets them.
  std::vector<std::string> take_log();

  // The mesh of a virtual object scaled by its model_scale (in metres of the scene,
  // like its primitives), or null when it has none or it failed to load.
  const MeshData* mesh_for(int object) const;
  // The same mesh as the file holds it (its own units; units says what the file states).
  const MeshData* source_mesh_for(int object) const;
  // Absolute path of a mesh as the spec names it (relative to the spec's folder).
  std::filesystem::path resolve_mesh_path(const std::string& mesh) const;
  // How the spec should name a mesh file: relative to the spec's folder, or absolute
  // while the document is untitled.
  std::string mesh_reference(const std::filesystem::path& file) const;
  // Loads a mesh into the cache (no undo step: meshes are not edited).
  Status load_mesh(const std::string& mesh);

  // Applies one command and records an undo step. Errors (an index out of range,
  // a bad value) leave the document unchanged.
  Status apply(const Command& command);
  bool can_undo() const { return undo_pos_ > 0; }
  bool can_redo() const { return undo_pos_ < history_.size(); }
  std::string undo_label() const;
  std::string redo_label() const;
  const std::vector<UndoStep>& history() const { return history_; }

  // The same check `annex-runtime check` runs on a file, with its words.
  Status validate() const;

  // Saves atomically; save_as rewrites mesh paths relative to the new folder.
  // Both remove the autosave sidecar on success.
  Status save();
  Status save_as(const std::filesystem::path& path);

  // Autosave sidecar: "<spec>.autosave" beside the spec, or untitled.haptic.autosave
  // in autosave_dir() for an untitled document.
  std::filesystem::path autosave_path() const;
  Status write_autosave() const;
  void remove_autosave() const;

 private:
  Status apply_edit(const Command& command);
  void mark_changed() { ++revision_; }
  void load_meshes();
  void remove_stale_temporaries_of(const std::filesystem::path& spec_path);

  HapticSpec spec_;
  HapticSpec saved_;
  Selection selection_;
  std::filesystem::path path_;
  std::uint64_t revision_ = 0;
  std::vector<UndoStep> history_;
  std::size_t undo_pos_ = 0;                                       // steps [0, undo_pos_) are done
  std::map<std::string, std::shared_ptr<const MeshData>> meshes_;  // by absolute path
  // mesh_for's scaled copies, by absolute path and scale.
  mutable std::map<std::pair<std::string, double>, std::shared_ptr<const MeshData>> scaled_;
  std::vector<std::string> warnings_;
  std::vector<std::string> log_;
};

// Per-user folder for untitled autosaves and the recent-files list:
// $ANNEX_AUTHOR_STATE_DIR, else $XDG_STATE_HOME/annex-author, else ~/.local/state/annex-author.
std::filesystem::path state_dir();

// The autosave sidecar of a spec file.
std::filesystem::path autosave_path_for(const std::filesystem::path& spec_path);

// True when `spec_path` has an autosave sidecar newer than it whose content differs:
// the editor crashed or was killed with unsaved edits.
bool has_recovery(const std::filesystem::path& spec_path);
bool has_untitled_recovery();

// Default name for a new object or primitive that is not taken yet ("cylinder", "cylinder_2").
std::string unique_primitive_name(const VirtualObject& object, std::string_view base);
std::string unique_object_name(const HapticSpec& spec, std::string_view base);

}  // namespace annex::authoring
