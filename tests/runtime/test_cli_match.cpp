// annex-runtime check and match, run as a user runs them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli_runner.h"
#include "temp_dir.h"

namespace annex::test {
namespace {

std::string temp_file(const std::string& name, const std::string& content) {
  const auto dir = process_temp_dir() / "cli_match";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << content;
  return path.string();
}

TEST(CliMatch, Figure3GivesThePapersAssignment) {
  const CliRun m = run_cli("match " + shell_quote(source_path("samples/figure3/figure3.haptic")) +
                           " " + shell_quote(source_path("samples/figure3/figure3.scene")));
  EXPECT_EQ(m.exit_code, 0) << m.output;
  EXPECT_EQ(m.output, "match v1 p2 34.00\nmatch v2 p3 65.00\nmatch v3 p1 48.00\n");
}

TEST(CliMatch, Figure3ExplainShowsThePapersVotes) {
  const CliRun m = run_cli("match --explain " +
                           shell_quote(source_path("samples/figure3/figure3.haptic")) + " " +
                           shell_quote(source_path("samples/figure3/figure3.scene")));
  ASSERT_EQ(m.exit_code, 0) << m.output;
  EXPECT_NE(m.output.find("v1      55.00   34.00   0.00"), std::string::npos) << m.output;
  EXPECT_NE(m.output.find("total vote 147.00"), std::string::npos) << m.output;
  EXPECT_NE(m.output.find("match v1 p2 34.00"), std::string::npos);
}

TEST(CliMatch, StudySpecsMatchTheHouseholdLibrary) {
  const CliRun m = run_cli("match " + shell_quote(source_path("samples/specs/study.haptic")) +
                           " " + shell_quote(source_path("samples/library/household.scene")));
  ASSERT_EQ(m.exit_code, 0) << m.output;
  // Each annexable study object finds a prop; the decoration stays virtual.
  for (const char* name : {"champagne_bottle", "lightsaber", "lamp", "mug", "ping_pong_paddle", "torch"})
    EXPECT_NE(m.output.find(std::string("match ") + name + " "), std::string::npos) << name << "\n" << m.output;
  EXPECT_NE(m.output.find("virtual-only dragon"), std::string::npos);
  EXPECT_NE(m.output.find("match champagne_bottle champagne_bottle "), std::string::npos)
      << m.output;
}

TEST(CliCheck, ValidSpecSummary) {
  const CliRun r = run_cli("check " + shell_quote(source_path("samples/specs/study.haptic")));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ok: 7 virtual objects (6 annexable), 11 primitives"), std::string::npos)
      << r.output;
}

TEST(CliCheck, ErrorNamesFileLineAndColumn) {
  const std::string path = temp_file("bad.haptic",
                                     "annex-haptic 1\n"
                                     "object a\n"
                                     "  primitive s sphere\n"
                                     "    radius -0.1\n"
                                     "  end\n"
                                     "end\n");
  const CliRun r = run_cli("check " + shell_quote(path));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.output.rfind(path + ":4:12: error: ", 0), 0u) << r.output;
}

TEST(CliCheck, MissingFile) {
  const CliRun r = run_cli("check /nonexistent/x.haptic");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("/nonexistent/x.haptic"), std::string::npos) << r.output;
}

TEST(CliMatch, BadSceneIsReportedWithLocation) {
  const std::string scene = temp_file("bad.scene", "annex-scene 1\nobject p1\n  sphere radius nan\nend\n");
  const CliRun r = run_cli("match " + shell_quote(source_path("samples/figure3/figure3.haptic")) +
                           " " + shell_quote(scene));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find(scene + ":3:17: error: "), std::string::npos) << r.output;
}

TEST(CliMatch, ScansADepthFrameFirst) {
  const std::string cloud =
      std::string(ANNEX_SHARED_DIR) + "/data/real/milk_cartoon_all_small_clorox.pcd";
  if (!std::filesystem::exists(cloud))
    GTEST_SKIP() << "real scans not found at " << cloud << " (../shared is not part of the repo)";
  const CliRun m = run_cli("match " + shell_quote(source_path("samples/specs/study.haptic")) +
                           " " + shell_quote(cloud));
  ASSERT_EQ(m.exit_code, 0) << m.output;
  // The bleach bottle is a cylinder with a neck cone: the champagne bottle's body takes it.
  EXPECT_NE(m.output.find("match champagne_bottle p"), std::string::npos) << m.output;
  EXPECT_NE(m.output.find("virtual-only dragon"), std::string::npos) << m.output;
}

TEST(CliMatch, CorruptDepthFrameIsABadInput) {
  const std::string cloud = temp_file("corrupt.pcd", "# .PCD v0.7\nVERSION 0.7\nFIELDS x y\n");
  const CliRun m = run_cli("match " + shell_quote(source_path("samples/figure3/figure3.haptic")) +
                           " " + shell_quote(cloud));
  EXPECT_EQ(m.exit_code, 2) << m.output;
  EXPECT_NE(m.output.find(cloud), std::string::npos) << m.output;
}

TEST(Cli, HelpOnEveryCommandAndUsageErrors) {
  for (const char* cmd : {"check", "match"}) {
    const CliRun r = run_cli(std::string(cmd) + " --help");
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.output.find("usage: annex-runtime " + std::string(cmd)), std::string::npos);
  }
  EXPECT_EQ(run_cli("--help").exit_code, 0);
  EXPECT_EQ(run_cli("frobnicate").exit_code, 2);
  EXPECT_EQ(run_cli("match only-one-arg").exit_code, 2);
  EXPECT_EQ(run_cli("match --min-vote=abc a b").exit_code, 2);
  EXPECT_EQ(run_cli("match --bogus a b").exit_code, 2);
}

}  // namespace
}  // namespace annex::test
