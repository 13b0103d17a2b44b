#pragma once
/// \file
/// The `.scene` format: physical objects found by a scan (or measured by hand for
/// the household library), in the same line-oriented style as `.haptic`
/// (docs/scene-format.md).

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "annex/common/physical_scene.h"
#include "annex/common/result.h"
#include "annex/formats/haptic_format.h"

namespace annex {

/// Parses scene text; pure, errors with 1-based line and column.
Result<PhysicalScene> parse_scene(std::string_view text, std::string_view origin,
                                  std::vector<Diagnostic>* warnings = nullptr);

/// Checks a scene built in memory (the scanner's) with the reader's rules and words;
/// the location names the object instead of a line, e.g. "<origin>: object 'p1'".
Status validate_scene(const PhysicalScene& scene, std::string_view origin = "<scene>");

/// Canonical text; parse_scene(write_scene(s)) == s.
std::string write_scene(const PhysicalScene& scene);

Result<PhysicalScene> read_scene_file(const std::filesystem::path& path,
                                      std::vector<Diagnostic>* warnings = nullptr);

/// Atomic, like write_haptic_file; refuses a scene that fails validate_scene.
Status write_scene_file(const std::filesystem::path& path, const PhysicalScene& scene);

}  // namespace annex
