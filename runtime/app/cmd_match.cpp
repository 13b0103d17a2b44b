// annex-runtime match SPEC.haptic SCENE.scene: the match simulator.
#include <charconv>
#include <cmath>
#include <iostream>

#include "annex/common/object_finder.h"
#include "annex/formats/haptic_format.h"
#include "annex/formats/scene_format.h"
#include "annex/runtime/match_report.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/plane_candidates.h"
#include "annex/runtime/scanner.h"
#include "commands.h"
#include "depth_options.h"
#include "scan_options.h"

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

// A .scene file as it is, or a depth frame scanned first (exit code with the error).
Result<PhysicalScene> load_scene(const std::string& path, const ScanParams& params,
                                 const ParsedArgs& args, const FrameSourceParams& depth_params,
                                 std::vector<Diagnostic>& warnings, int& failure_code) {
  failure_code = kExitBadInput;
  if (!path.ends_with(".pcd") && !is_png_path(path)) return read_scene_file(path, &warnings);
  const Result<Frame> frame = read_frame_file(path, args, depth_params);
  if (!frame) return frame.error();
  Result<ScanResult> scan = scan_frame(*frame, params);
  if (!scan) {
    Error e = scan.error();
    e.location.origin = path;
    failure_code = kExitFailure;
    return e;
  }
  return scene_with_surfaces(*scan);  // objects, then flat surfaces for virtual panels
}

int run_match(const std::vector<std::string>& args) {
  const auto parsed = parse_args(
      "match", args,
      {{"explain", "within-limits"},
       {"min-vote", "max-vote", "config", "color", "intrinsics", "depth-scale", "depth-noise"}});
  if (!parsed) return kExitBadInput;
  FrameSourceParams depth_params;
  if (!read_depth_options("match", *parsed, depth_params)) return kExitBadInput;
  const std::optional<ScanParams> scan_params = read_scan_options("match", *parsed);
  if (!scan_params) return kExitBadInput;
  if (parsed->positional.size() != 2) {
    std::cerr << "annex-runtime match: error: expected SPEC.haptic and SCENE.scene or CLOUD.pcd"
                 " (see --help)\n";
    return kExitBadInput;
  }
  MatchParams params;
  if (auto v = parsed->get("min-vote")) {
    const auto x = parse_non_negative("min-vote", *v);
    if (!x) return kExitBadInput;
    params.min_vote = *x;
  }
  params.within_limits = parsed->has("within-limits");
  if (auto v = parsed->get("max-vote")) {
    const auto x = parse_non_negative("max-vote", *v);
    if (!x) return kExitBadInput;
    params.vote.max_vote = *x;
  }

  std::vector<Diagnostic> warnings;
  const Result<HapticSpec> spec = read_haptic_file(parsed->positional[0], &warnings);
  int scene_failure = kExitBadInput;
  const Result<PhysicalScene> scene = load_scene(parsed->positional[1], *scan_params, *parsed,
                                                 depth_params, warnings, scene_failure);
  for (const Diagnostic& w : warnings) std::cerr << w.format() << "\n";
  if (!spec) std::cerr << spec.error().format() << "\n";
  if (!scene) std::cerr << scene.error().format() << "\n";
  if (!spec) return kExitBadInput;
  if (!scene) return scene_failure;

  const MatchResult result = match_objects(*spec, *scene, params);
  if (parsed->has("explain")) std::cout << format_vote_table(*spec, *scene, result) << "\n";
  std::cout << format_match_lines(*spec, *scene, result);
  return kExitOk;
}

}  // namespace

const Command kMatchCommand{
    "match", "vote and match a spec against a scene (the match simulator)",
    "usage: annex-runtime match SPEC.haptic (SCENE.scene | CLOUD.pcd | DEPTH.png)\n"
    "                           [--explain] [--min-vote X] [--within-limits] [--max-vote C]\n"
    "                           [--config SCAN.conf] [--depth-noise NAME] [--color RGB.png]\n"
    "                           [--intrinsics fx,fy,cx,cy] [--depth-scale S]\n"
    "\n"
    "With a depth frame (.pcd, or a 16-bit depth .png with the options of 'scan') the\n"
    "scanner runs first (see 'scan --help') and its\n"
    "objects p1, p2, ... are the physical objects.\n"
    "Every annexable virtual object votes for every physical object (the paper's\n"
    "voting equation) and the Hungarian method picks the assignment with the highest\n"
    "total vote. Prints one line per virtual object, in spec order:\n"
    "  match <virtual-name> <physical-id> <vote>\n"
    "  virtual-only <virtual-name>\n"
    "\n"
    "  --explain      print the vote table and each pair's breakdown first\n"
    "  --min-vote X   never match a pair voting X or less (default 0); a spec's\n"
    "                 per-object 'min_vote V' also never matches a pair voting under V\n"
    "  --within-limits never match a prop that needs a dimension scaled beyond the\n"
    "                 primitive's scaling limits\n"
    "  --max-vote C   the constant C, the highest possible vote (default "
    "100)\n" ANNEX_SCAN_OPTIONS_HELP
    "\n"
    "Exit 0 on success, 1 when a frame has no support plane, 2 on bad arguments or an\n"
    "invalid file (file:line:col: error: ...).\n",
    run_match};

}  // namespace annex::cli
