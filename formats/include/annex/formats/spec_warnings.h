#pragma once
/// \file
/// What a valid spec may still get wrong: things `annex-runtime check` and the editor
/// warn about (exit 0) because a newcomer meets them first.

#include <filesystem>
#include <string_view>
#include <vector>

#include "annex/common/haptic_model.h"
#include "annex/formats/haptic_format.h"

namespace annex {

/// Warnings for a spec that parsed: no virtual objects at all, no annexable object
/// (`run` would annex nothing), and `mesh` paths that name no file (relative to
/// `spec_dir`, as the runtime and the editor resolve them). `text` and `origin` are
/// what parse_haptic read, so each warning points at its line and column.
std::vector<Diagnostic> spec_warnings(const HapticSpec& spec, std::string_view text,
                                      std::string_view origin,
                                      const std::filesystem::path& spec_dir);

}  // namespace annex
