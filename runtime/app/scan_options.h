#pragma once
// `--config FILE` and `--depth-noise NAME`, shared by scan, match and run: the scan's
// parameters from the file, then the depth camera's noise model by name.

#include <iostream>
#include <optional>
#include <string>
#include <string_view>

#include "annex/runtime/depth_noise.h"
#include "annex/runtime/scanner.h"
#include "cli.h"

namespace annex::cli {

// The --help lines of the two options: a literal, so that each command's usage text,
// itself one literal, can hold it.
#define ANNEX_SCAN_OPTIONS_HELP                                                           \
  "  --config FILE      scan parameters (samples/config/scan.conf, docs/perception.md)\n" \
  "  --depth-noise NAME the depth camera's noise: kinect (structured light, the\n"        \
  "                     default), stereo (RealSense D400) or tof (Kinect v2, Azure\n"     \
  "                     Kinect); over the config's depth_noise\n"

// The scan parameters the options give; nullopt after printing the error.
inline std::optional<ScanParams> read_scan_options(std::string_view command,
                                                   const ParsedArgs& args) {
  ScanParams params;
  if (auto path = args.get("config")) {
    Result<ScanParams> cfg = read_scan_config_file(*path);
    if (!cfg) {
      std::cerr << cfg.error().format() << "\n";
      return std::nullopt;
    }
    params = *cfg;
  }
  if (auto name = args.get("depth-noise")) {
    const std::optional<DepthNoise> noise = depth_noise_named(*name);
    if (!noise) {
      std::cerr << "annex-runtime " << command << ": error: --depth-noise expects one of "
                << kDepthNoiseNames << ", got '" << *name << "'\n";
      return std::nullopt;
    }
    params.depth_noise = *noise;
  }
  return params;
}

}  // namespace annex::cli
