#pragma once
// Every edit the editor can make, as plain values. Panels and scripts push them
// into a CommandQueue; the app applies them to the EditorDocument after the frame,
// and the document records an undo step for each.

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "annex/common/haptic_model.h"

namespace annex::authoring {

// object -1: nothing selected; primitive -1: the object itself.
struct Selection {
  int object = -1;
  int primitive = -1;
  bool operator==(const Selection&) const = default;
};

// The three priority levels of the paper: w_o, w_s, w_h.
enum class WeightLevel { object, primitive, dimension };

namespace cmd {

// Adds a virtual object showing the mesh at `mesh` (a path as the spec stores it).
struct ImportMesh {
  std::string mesh;
  std::string name;
};
struct AddObject {
  std::string name;
};
struct RemoveObject {
  int object = -1;
};
struct RenameObject {
  int object = -1;
  std::string name;
};
struct SetAnnexable {
  int object = -1;
  bool annexable = true;
};
// `initial` unset: a primitive of `kind` wrapping the object's mesh, named `name`
// (empty: the shape's name, made unique).
struct AddPrimitive {
  int object = -1;
  ShapeKind kind = ShapeKind::cylinder;
  std::optional<Primitive> initial;
  std::string name;
};
struct RemovePrimitive {
  int object = -1;
  int primitive = -1;
};
struct DuplicatePrimitive {
  int object = -1;
  int primitive = -1;
};
struct RenamePrimitive {
  int object = -1;
  int primitive = -1;
  std::string name;
};
// Changes the shape, keeping pose and weight; dimensions are reset to fit the old size.
struct SetKind {
  int object = -1;
  int primitive = -1;
  ShapeKind kind = ShapeKind::cylinder;
};
struct SetPose {
  int object = -1;
  int primitive = -1;
  Pose pose;
};
struct SetDimension {
  int object = -1;
  int primitive = -1;
  int dimension = -1;
  double value_m = 0;
};
struct SetScaleLimits {
  int object = -1;
  int primitive = -1;
  int dimension = -1;
  double min_scale = 1;
  double max_scale = 1;
};
// Sets w_o (object), w_s (object, primitive) or w_h (object, primitive, dimension).
struct SetWeight {
  WeightLevel level = WeightLevel::object;
  int object = -1;
  int primitive = -1;
  int dimension = -1;
  double weight = 1;
};
// Forced-rank mode: `order` lists the items most important first; weights follow
// rank_weights() (docs/editor.md).
struct SetRank {
  WeightLevel level = WeightLevel::object;
  int object = -1;
  int primitive = -1;
  std::vector<int> order;
};
// Replaces a primitive whole (fit to selection, viewport handles).
struct ReplacePrimitive {
  int object = -1;
  int primitive = -1;
  Primitive value;
};
// Sets the object's model_scale (metres per mesh unit). Its primitives stay attached
// to the mesh: their positions and sizes scale by new / old, in the same undo step.
struct SetModelScale {
  int object = -1;
  double model_scale = 1;
};
struct Select {
  Selection selection;
};
// Closes the current undo step: the next edit starts a new one (sent on
// ImGui::IsItemDeactivatedAfterEdit so a slider drag is one step).
struct EndEdit {};
struct Undo {};
struct Redo {};

}  // namespace cmd

using Command =
    std::variant<cmd::ImportMesh, cmd::AddObject, cmd::RemoveObject, cmd::RenameObject,
                 cmd::SetAnnexable, cmd::AddPrimitive, cmd::RemovePrimitive,
                 cmd::DuplicatePrimitive, cmd::RenamePrimitive, cmd::SetKind, cmd::SetPose,
                 cmd::SetDimension, cmd::SetScaleLimits, cmd::SetWeight, cmd::SetRank,
                 cmd::ReplacePrimitive, cmd::Select, cmd::EndEdit, cmd::Undo, cmd::Redo,
                 cmd::SetModelScale>;

// Things only the app can do (files, dialogs, the window); panels request them.
struct AppAction {
  enum class Kind {
    new_document,
    open,
    save,
    save_as,
    import_mesh,
    open_scene,
    quit,
    fit_view,
    recover,
    discard_recovery,
    choose_source,
    run_preview
  };
  Kind kind = Kind::new_document;
  std::string path;
  bool confirmed = false;  // the user already answered "save changes?"
};

// What one frame's widgets asked for, applied in order after the frame.
struct CommandQueue {
  std::vector<Command> commands;
  std::vector<AppAction> actions;
  void push(Command c) { commands.push_back(std::move(c)); }
  void request(AppAction::Kind kind, std::string path = {}) {
    AppAction a;
    a.kind = kind;
    a.path = std::move(path);
    actions.push_back(std::move(a));
  }
  bool empty() const { return commands.empty() && actions.empty(); }
};

// Short human label for menus ("Undo Set radius").
std::string command_label(const Command& c);

}  // namespace annex::authoring
