#include "annex/authoring/recent_files.h"

#include <algorithm>
#include <sstream>

#include "annex/formats/file_io.h"

namespace annex::authoring {

RecentFiles add_recent(RecentFiles recent, const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::path abs = std::filesystem::absolute(path, ec);
  const std::string key = (ec ? path : abs.lexically_normal()).string();
  std::erase(recent.paths, key);
  recent.paths.insert(recent.paths.begin(), key);
  if (recent.paths.size() > kMaxRecent) recent.paths.resize(kMaxRecent);
  return recent;
}

RecentFiles read_recent(const std::filesystem::path& file) {
  RecentFiles recent;
  auto text = read_text_file(file, 1u << 16);
  if (!text) return recent;
  std::istringstream in(*text);
  std::string line;
  while (std::getline(in, line) && recent.paths.size() < kMaxRecent)
    if (!line.empty() &&
        std::find(recent.paths.begin(), recent.paths.end(), line) == recent.paths.end())
      recent.paths.push_back(line);
  return recent;
}

Status write_recent(const std::filesystem::path& file, const RecentFiles& recent) {
  std::error_code ec;
  std::filesystem::create_directories(file.parent_path(), ec);
  std::string text;
  for (const std::string& p : recent.paths) text += p + "\n";
  return write_file_atomically(file, text);
}

}  // namespace annex::authoring
