// libFuzzer target for the editor's script language (annex-author --script): any
// input must parse or fail with a located error, and every document command of a
// parsed script runs on a document or fails cleanly. Verbs that touch files (open,
// recover, import, save, autosave) are skipped: the fuzzer must not write files.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "annex/authoring/editor_document.h"
#include "annex/authoring/script.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto script = annex::authoring::parse_script(text, "fuzz.script");
  if (!script.ok()) {
    const auto& loc = script.error().location;
    if (loc.origin != "fuzz.script" || loc.line < 1 || loc.column < 1) std::abort();
    return 0;
  }
  annex::authoring::EditorDocument doc;
  int run = 0;
  for (const annex::authoring::ScriptLine& line : *script) {
    if (line.line < 1) std::abort();
    if (line.words.empty()) continue;
    const std::string_view verb = line.words[0];
    if (verb == "open" || verb == "recover" || verb == "import" || verb == "save" ||
        verb == "autosave")
      continue;
    if (++run > 16) break;  // long scripts add time, not coverage
    (void)annex::authoring::run_document_command(doc, line, "fuzz.script");
  }
  return 0;
}
