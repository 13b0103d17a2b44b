// annex-runtime match SPEC.haptic SCENE.scene: the match simulator.
#include <charconv>
#include <cmath>
#include <iostream>

#include "annex/common/object_finder.h"
#include "annex/formats/haptic_format.h"
#include "annex/formats/scene_format.h"
#include "annex/runtime/match_report.h"
#include "commands.h"

namespace annex::cli {
namespace {

std::optional<double> parse_non_negative(std::string_view option, const std::string& text) {
  double x = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(x) || x < 0) {
    std::cerr << "annex-runtime match: error: --" << option
              << " expects a finite number >= 0, got '" << text << "'\n";
    return std::nullopt;
  }
  return x;
}

int run_match(const std::vector<std::string>& args) {
  const auto parsed = parse_args("match", args, {{"explain"}, {"min-vote", "max-vote"}});
  if (!parsed) return kExitBadInput;
  if (parsed->positional.size() != 2) {
    std::cerr << "annex-runtime match: error: expected SPEC.haptic and SCENE.scene (see --help)\n";
    return kExitBadInput;
  }
  MatchParams params;
  if (auto v = parsed->get("min-vote")) {
    const auto x = parse_non_negative("min-vote", *v);
    if (!x) return kExitBadInput;
    params.min_vote = *x;
  }
  if (auto v = parsed->get("max-vote")) {
    const auto x = parse_non_negative("max-vote", *v);
    if (!x) return kExitBadInput;
    params.vote.max_vote = *x;
  }

  std::vector<Diagnostic> warnings;
  const Result<HapticSpec> spec = read_haptic_file(parsed->positional[0], &warnings);
  const Result<PhysicalScene> scene = read_scene_file(parsed->positional[1], &warnings);
  for (const Diagnostic& w : warnings) std::cerr << w.format() << "\n";
  if (!spec) std::cerr << spec.error().format() << "\n";
  if (!scene) std::cerr << scene.error().format() << "\n";
  if (!spec || !scene) return kExitBadInput;

  const MatchResult result = match_objects(*spec, *scene, params);
  if (parsed->has("explain")) std::cout << format_vote_table(*spec, *scene, result) << "\n";
  std::cout << format_match_lines(*spec, *scene, result);
  return kExitOk;
}

}  // namespace

const Command kMatchCommand{
    "match", "vote and match a spec against a scene (the match simulator)",
    "usage: annex-runtime match SPEC.haptic SCENE.scene [--explain] [--min-vote X] [--max-vote C]\n"
    "\n"
    "Every annexable virtual object votes for every physical object (the paper's\n"
    "voting equation) and the Hungarian method picks the assignment with the highest\n"
    "total vote. Prints one line per virtual object, in spec order:\n"
    "  match <virtual-name> <physical-id> <vote>\n"
    "  virtual-only <virtual-name>\n"
    "\n"
    "  --explain      print the vote table and each pair's breakdown first\n"
    "  --min-vote X   never match a pair voting X or less (default 0)\n"
    "  --max-vote C   the constant C, the highest possible vote (default 100)\n"
    "\n"
    "Exit 0 on success, 2 on bad arguments or an invalid file (file:line:col: error: ...).\n",
    run_match};

}  // namespace annex::cli
