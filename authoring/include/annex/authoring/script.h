#pragma once
// `annex-author --script FILE`: a line-oriented command language that drives the
// editor with no person (docs/editor.md lists every command). Parsing is pure;
// document commands run here, view commands (screenshot, frames) in the app.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "annex/authoring/editor_document.h"
#include "annex/common/result.h"

namespace annex::authoring {

struct ScriptLine {
  int line = 0;
  std::vector<std::string> words;  // first is the verb
};

// Words split on blanks; "double quotes" keep blanks; '#' starts a comment.
// Errors: unterminated quote, with line and column.
Result<std::vector<ScriptLine>> parse_script(std::string_view text, std::string_view origin);

// Runs a document command (new, open, import, select, add, remove, duplicate, set,
// fit, rank, undo, redo, save, validate, print). Returns false in `handled` for verbs
// it does not know so the app can try its own. Errors name origin:line.
struct ScriptResult {
  bool handled = false;
  std::string output;  // text for stdout (print)
};
Result<ScriptResult> run_document_command(EditorDocument& doc, const ScriptLine& line,
                                          std::string_view origin);

// Parses a whole strictly ("1.5" yes, "1.5x" no).
bool parse_double(std::string_view text, double& out);

// Metres per unit of "mm", "cm", "m", "in", "ft"; none for another name.
std::optional<double> metres_per_unit(std::string_view unit);
// A mesh's height in its own units: its extent along the editor's up axis (+Y).
double model_height_units(const MeshData& mesh);
// "model duck: model_scale 0.078; size 0.129 x 0.120 x 0.090 m (x, y up, z); units:
// COLLADA <unit ...>, applied by the importer", what the inspector shows too.
std::string describe_model_size(const EditorDocument& doc, int object);

}  // namespace annex::authoring
