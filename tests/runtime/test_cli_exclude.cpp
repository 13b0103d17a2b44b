// The spec's exclude rules as `match` and `check` show them: an excluded prop is never
// assigned, `--explain` gives its votes in parentheses and the rule that forbids it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_runner.h"
#include "temp_dir.h"

namespace annex::test {
namespace {

// Each test its own file: ctest runs them in parallel.
std::string figure3_with(const std::string& name, const std::string& rules) {
  std::ifstream in(source_path("samples/figure3/figure3.haptic"));
  std::stringstream text;
  text << in.rdbuf() << "\n" << rules;
  const auto dir = process_temp_dir() / "cli_exclude";
  std::filesystem::create_directories(dir);
  const auto path = dir / (name + ".haptic");
  std::ofstream(path) << text.str();
  return path.string();
}

TEST(CliExclude, MatchLeavesTheTallPropOut) {
  // Figure 3's cylinder p1 is 20 cm tall; the cone and the sphere 10 cm.
  const std::string spec = figure3_with("tall", "exclude tall\n  prop_height min 0.15\nend\n");
  const std::string scene = shell_quote(source_path("samples/figure3/figure3.scene"));
  const CliRun plain = run_cli("match " + shell_quote(spec) + " " + scene);
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_EQ(plain.output.find(" p1 "), std::string::npos) << plain.output;
  EXPECT_NE(plain.output.find("match v1 p2 34.00"), std::string::npos) << plain.output;
  const CliRun explained = run_cli("match --explain " + shell_quote(spec) + " " + scene);
  ASSERT_EQ(explained.exit_code, 0) << explained.output;
  EXPECT_NE(explained.output.find("excluded by the spec (votes in parentheses, never matched)\n"
                                  "  p1: rule 'tall' (shape any, prop_height min 0.15); "
                                  "prop_height 0.200 m\n"),
            std::string::npos)
      << explained.output;
  EXPECT_NE(explained.output.find("(55.00)"), std::string::npos) << explained.output;
  // Without the rule v3 took p1 (Figure 3's assignment).
  EXPECT_EQ(explained.output.find("match v3 p1"), std::string::npos);
}

TEST(CliExclude, CheckReportsABadRuleWithItsPosition) {
  const std::string spec =
      figure3_with("balls", "exclude balls\n  shape sphere\n  height max 1\nend\n");
  const CliRun c = run_cli("check " + shell_quote(spec));
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_NE(c.output.find(":41:3: error: 'height' is not a dimension of a sphere"),
            std::string::npos)
      << c.output;
}

}  // namespace
}  // namespace annex::test
