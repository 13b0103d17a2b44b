// annex-runtime check SPEC.haptic: validate a spec and summarise it.
#include <filesystem>
#include <iostream>

#include "annex/formats/file_io.h"
#include "annex/formats/haptic_format.h"
#include "annex/formats/spec_warnings.h"
#include "commands.h"

namespace annex::cli {
namespace {

int run_check(const std::vector<std::string>& args) {
  const auto parsed = parse_args("check", args, {});
  if (!parsed) return kExitBadInput;
  if (parsed->positional.size() != 1) {
    std::cerr << "annex-runtime check: error: expected one SPEC.haptic (see --help)\n";
    return kExitBadInput;
  }
  const std::string& path = parsed->positional[0];
  std::vector<Diagnostic> warnings;
  const auto text = read_text_file(path);
  if (!text) {
    std::cerr << text.error().format() << "\n";
    return kExitBadInput;
  }
  const Result<HapticSpec> spec = parse_haptic(*text, path, &warnings);
  if (spec) {
    const auto more = spec_warnings(*spec, *text, path, std::filesystem::path(path).parent_path());
    warnings.insert(warnings.end(), more.begin(), more.end());
  }
  for (const Diagnostic& w : warnings) std::cerr << w.format() << "\n";
  if (!spec) {
    std::cerr << spec.error().format() << "\n";
    return kExitBadInput;
  }
  int annexable = 0, primitives = 0;
  for (const VirtualObject& o : spec->objects) {
    annexable += o.annexable ? 1 : 0;
    primitives += static_cast<int>(o.primitives.size());
  }
  std::cout << path << ": ok: " << plural(spec->objects.size(), "virtual object") << " ("
            << annexable << " annexable), " << plural(primitives, "primitive") << "\n";
  for (const VirtualObject& o : spec->objects) {
    std::cout << "  " << o.name << (o.annexable ? "" : " (virtual-only)");
    for (size_t i = 0; i < o.primitives.size(); ++i)
      std::cout << (i ? ", " : ": ") << shape_name(o.primitives[i].kind) << " '"
                << o.primitives[i].name << "'";
    std::cout << "\n";
  }
  return kExitOk;
}

}  // namespace

const Command kCheckCommand{
    "check", "validate a .haptic spec and summarise it",
    "usage: annex-runtime check SPEC.haptic\n"
    "\n"
    "Reads and validates a haptic spec. On success prints a summary and exits 0.\n"
    "On error prints 'file:line:col: error: message' and exits 2.\n"
    "Warnings ('file:line:col: warning: ...') go to stderr and do not fail the check.\n",
    run_check};

}  // namespace annex::cli
