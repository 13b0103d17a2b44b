#pragma once
// `--stereo [--hmd FILE]`, shared by the render and run commands.

#include <iostream>
#include <optional>
#include <vector>

#include "annex/runtime/renderer.h"
#include "cli.h"

namespace annex::cli {

// The HMD to render a stereo pair for (defaults unless --hmd names a file), or none
// without --stereo. False after printing the error: an unreadable HMD file, or --hmd
// without --stereo.
inline bool read_hmd_option(std::string_view command, const ParsedArgs& args,
                            std::vector<Diagnostic>& warnings, std::optional<HmdConfig>& hmd) {
  if (!args.has("stereo")) {
    if (args.has("hmd")) {
      fail(command, "--hmd applies to --stereo", kExitBadInput);
      return false;
    }
    return true;
  }
  hmd = HmdConfig{};
  if (auto path = args.get("hmd")) {
    Result<HmdConfig> read = read_hmd_config(*path, &warnings);
    if (!read) {
      std::cerr << read.error().format() << "\n";
      return false;
    }
    hmd = *read;
  }
  return true;
}

}  // namespace annex::cli
