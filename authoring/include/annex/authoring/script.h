#pragma once
// `annex-author --script FILE`: a line-oriented command language that drives the
// editor with no person (docs/editor.md lists every command). Parsing is pure;
// document commands run here, view commands (screenshot, frames) in the app.

#include <filesystem>
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

}  // namespace annex::authoring
