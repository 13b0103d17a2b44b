#pragma once
// Shared helpers of the authoring tests: a fresh temporary folder per test, running a
// script against a document.

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "../unique_temp_dir.h"

#include "annex/authoring/editor_document.h"
#include "annex/authoring/script.h"

namespace annex::authoring::testing {

inline std::filesystem::path fresh_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  // Under this program's own folder (unique_temp_dir.h): two checkouts running the same
  // test at once never share it.
  std::filesystem::path dir = annex::test::process_temp_dir() /
                              (std::string(info->test_suite_name()) + "." + info->name() + "." +
                               name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

inline std::string sample_model(const std::string& name) {
  return std::string(ANNEX_SOURCE_DIR) + "/samples/models/" + name;
}

// Runs a script against a document; fails the test on the first error.
inline void run(EditorDocument& doc, const std::string& text) {
  auto lines = parse_script(text, "t.script");
  ASSERT_TRUE(lines) << lines.error().format();
  for (const ScriptLine& l : *lines) {
    auto r = run_document_command(doc, l, "t.script");
    ASSERT_TRUE(r) << r.error().format();
    ASSERT_TRUE(r->handled) << l.words[0];
  }
}

}  // namespace annex::authoring::testing
