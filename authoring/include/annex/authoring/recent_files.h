#pragma once
// The File > Recent list: most recent first, no duplicates, at most kMaxRecent,
// stored one path per line in state_dir()/recent.txt.

#include <filesystem>
#include <string>
#include <vector>

#include "annex/common/result.h"

namespace annex::authoring {

inline constexpr std::size_t kMaxRecent = 10;

struct RecentFiles {
  std::vector<std::string> paths;
};

RecentFiles add_recent(RecentFiles recent, const std::filesystem::path& path);
RecentFiles read_recent(const std::filesystem::path& file);  // missing file: empty list
Status write_recent(const std::filesystem::path& file, const RecentFiles& recent);

}  // namespace annex::authoring
