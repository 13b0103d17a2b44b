#pragma once
// Temporary folders of the tests that no other process picks: several checkouts and
// build trees run ctest at once on one machine, and a fixed name under /tmp would let
// one run delete or read another's files. Every name holds the process id and a random
// suffix. A folder is removed when its owner ends, unless a test failed: then it is kept
// (and named on stderr) so its files can be looked at.

#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <system_error>

namespace annex::test {

// <temp>/annex_<name>_<pid>_<8 random hex digits>; not created.
inline std::filesystem::path unique_temp_path(const std::string& name) {
  std::random_device device;
  char suffix[16];
  std::snprintf(suffix, sizeof suffix, "%08x", static_cast<unsigned>(device()));
  return std::filesystem::temp_directory_path() /
         ("annex_" + name + "_" + std::to_string(::getpid()) + "_" + suffix);
}

// True when the running test failed (inside a test) or any test of the program failed
// (outside one, as at the program's end).
inline bool some_test_failed() {
  const ::testing::UnitTest* unit = ::testing::UnitTest::GetInstance();
  return unit->current_test_info() != nullptr ? ::testing::Test::HasFailure() : unit->Failed();
}

// A fresh, empty folder named by unique_temp_path, removed with everything in it when
// the object ends unless a test failed.
class TempDir {
 public:
  explicit TempDir(const std::string& name) : path_(unique_temp_path(name)) {
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    if (some_test_failed()) {
      std::fprintf(stderr, "kept %s (a test failed)\n", path_.c_str());
      return;
    }
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  std::string string() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

// One folder for the whole test program (annex_tests_<pid>_<random>), for files several
// tests share or that outlive a helper's scope; created on first use and removed when the
// program ends unless a test failed.
inline const std::filesystem::path& process_temp_dir() {
  static const TempDir dir("tests");
  return dir.path();
}

}  // namespace annex::test
