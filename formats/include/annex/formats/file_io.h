#pragma once
/// \file
/// File helpers shared by the readers and writers: bounded reads, atomic writes.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include "annex/common/result.h"

namespace annex {

/// Text files larger than this are refused before they are read.
inline constexpr std::size_t kMaxTextFileBytes = 16u << 20;

/// Reads a whole file; errors name the path.
Result<std::string> read_text_file(const std::filesystem::path& path,
                                   std::size_t max_bytes = kMaxTextFileBytes);

/// Writes `content` to a temporary file in the same directory, flushes it to disk,
/// then renames it over `path`. The old file survives any failure.
Status write_file_atomically(const std::filesystem::path& path, std::string_view content);

}  // namespace annex
