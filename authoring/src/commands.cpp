#include "annex/authoring/commands.h"

#include <type_traits>

namespace annex::authoring {

std::string command_label(const Command& c) {
  return std::visit(
      [](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, cmd::ImportMesh>)
          return "Import mesh";
        else if constexpr (std::is_same_v<T, cmd::AddObject>)
          return "Add object";
        else if constexpr (std::is_same_v<T, cmd::RemoveObject>)
          return "Remove object";
        else if constexpr (std::is_same_v<T, cmd::RenameObject>)
          return "Rename object";
        else if constexpr (std::is_same_v<T, cmd::SetAnnexable>)
          return "Set annexable";
        else if constexpr (std::is_same_v<T, cmd::AddPrimitive>)
          return "Add primitive";
        else if constexpr (std::is_same_v<T, cmd::RemovePrimitive>)
          return "Remove primitive";
        else if constexpr (std::is_same_v<T, cmd::DuplicatePrimitive>)
          return "Duplicate primitive";
        else if constexpr (std::is_same_v<T, cmd::RenamePrimitive>)
          return "Rename primitive";
        else if constexpr (std::is_same_v<T, cmd::SetKind>)
          return "Change shape";
        else if constexpr (std::is_same_v<T, cmd::SetPose>)
          return "Move primitive";
        else if constexpr (std::is_same_v<T, cmd::SetDimension>)
          return "Set dimension";
        else if constexpr (std::is_same_v<T, cmd::SetScaleLimits>)
          return "Set scale limits";
        else if constexpr (std::is_same_v<T, cmd::SetWeight>)
          return "Set priority";
        else if constexpr (std::is_same_v<T, cmd::SetRank>)
          return "Rank";
        else if constexpr (std::is_same_v<T, cmd::ReplacePrimitive>)
          return "Edit primitive";
        else if constexpr (std::is_same_v<T, cmd::Select>)
          return "Select";
        else if constexpr (std::is_same_v<T, cmd::EndEdit>)
          return "End edit";
        else if constexpr (std::is_same_v<T, cmd::Undo>)
          return "Undo";
        else if constexpr (std::is_same_v<T, cmd::Redo>)
          return "Redo";
        else
          return "Set model scale";
      },
      c);
}

}  // namespace annex::authoring
