#pragma once
/// \file
/// File helpers shared by the readers and writers: bounded reads, atomic writes.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "annex/common/result.h"

namespace annex {

/// Text files larger than this are refused before they are read.
inline constexpr std::size_t kMaxTextFileBytes = 16u << 20;

/// Reads a whole file; errors name the path.
Result<std::string> read_text_file(const std::filesystem::path& path,
                                   std::size_t max_bytes = kMaxTextFileBytes);

/// Writes `content` to a temporary file in the same directory (`.NAME.tmp-XXXXXX`),
/// flushes it to disk, then renames it over `path`. The old file survives any
/// failure. The temporary is flock()ed until it is renamed or removed.
Status write_file_atomically(const std::filesystem::path& path, std::string_view content);

/// True when `candidate` is named like a temporary file of write_file_atomically(path).
bool is_temporary_of(const std::filesystem::path& candidate, const std::filesystem::path& path);

/// Removes the temporary files of `path` that a killed write_file_atomically left
/// behind: named like one, plain files, last written before `older_than` (pass the
/// time the calling program started) and not locked by any process (a save in
/// progress holds its lock). Returns the files removed.
std::vector<std::filesystem::path> remove_stale_temporaries(
    const std::filesystem::path& path, std::filesystem::file_time_type older_than);

}  // namespace annex
