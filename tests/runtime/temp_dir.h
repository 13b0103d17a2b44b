#pragma once
// File fixtures of the frame source tests (test_frame_grabber, test_frame_grabber_depth_png):
// a fresh temporary folder per test (TempDir, unique_temp_dir.h) and whole-file writes
// and reads.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "../unique_temp_dir.h"

namespace annex::test {

// Writes `bytes` as the whole file, creating its folder.
inline void write_bytes(const std::filesystem::path& p, const std::string& bytes) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << bytes;
}

inline std::string read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace annex::test
