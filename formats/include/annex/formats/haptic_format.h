#pragma once
/// \file
/// The `.haptic` spec: Annex's line-oriented text format for haptic models
/// (grammar and a complete example in docs/haptic-format.md). Lengths are metres.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "annex/common/haptic_model.h"
#include "annex/common/result.h"

namespace annex {

/// A warning that does not stop reading, e.g. an unknown key inside a block that
/// has a did-you-mean suggestion. Same location style as errors.
struct Diagnostic {
  std::string message;
  Location location;
  /// "file:line:col: warning: message"
  std::string format() const;
};

/// Parses spec text. Pure: no file IO. `origin` names the text in messages
/// (usually the file path). Every error carries a 1-based line and column.
Result<HapticSpec> parse_haptic(std::string_view text, std::string_view origin,
                                std::vector<Diagnostic>* warnings = nullptr);

/// Checks a spec built in memory (the editor's) with the same rules and words the
/// reader applies; the location names the object and primitive instead of a line.
Status validate_haptic(const HapticSpec& spec, std::string_view origin = "<spec>");

/// Canonical text: parse_haptic(write_haptic(s)) == s, and a canonical file reads
/// and writes back byte for byte.
std::string write_haptic(const HapticSpec& spec);

/// Reads and parses a file (size-limited; see kMaxSpecBytes).
Result<HapticSpec> read_haptic_file(const std::filesystem::path& path,
                                    std::vector<Diagnostic>* warnings = nullptr);

/// Writes atomically: a temporary file beside the target, flushed, then renamed over it,
/// so a crash never leaves a half-written spec.
Status write_haptic_file(const std::filesystem::path& path, const HapticSpec& spec);

}  // namespace annex
