// What a newcomer meets first on the command line: check's warnings, did-you-mean for
// options and commands, --version, plurals, and the per-object minimum vote and
// scaling limits acting in matching.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_runner.h"
#include "temp_dir.h"

namespace annex::test {
namespace {

std::string temp_spec(const std::string& name, const std::string& content) {
  const auto dir = process_temp_dir() / "cli_newcomer";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << content;
  return path.string();
}

TEST(CliCheckWarnings, MissingMeshIsAWarningWithItsLineAndColumn) {
  const std::string path = temp_spec("missing_mesh.haptic",
                                     "annex-haptic 1\n"
                                     "object cup\n"
                                     "  mesh ../models/nope.obj\n"
                                     "  primitive body cylinder\n"
                                     "    radius 0.04\n"
                                     "    height 0.1\n"
                                     "  end\n"
                                     "end\n");
  const CliRun r = run_cli("check " + shell_quote(path));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(path + ":3:8: warning: object 'cup': mesh '../models/nope.obj' does "
                                 "not exist"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("ok: 1 virtual object (1 annexable), 1 primitive\n"), std::string::npos)
      << r.output;
}

TEST(CliCheckWarnings, NoAnnexableObjectAndEmptySpec) {
  const std::string none = temp_spec("none.haptic",
                                     "annex-haptic 1\n\n"
                                     "object dragon\n"
                                     "  annexable no\n"
                                     "end\n");
  CliRun r = run_cli("check " + shell_quote(none));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(none + ":3:1: warning: no object is annexable"), std::string::npos)
      << r.output;
  const std::string empty = temp_spec("empty.haptic", "annex-haptic 1\n");
  r = run_cli("check " + shell_quote(empty));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(empty + ":1:1: warning: the spec has no virtual objects"),
            std::string::npos)
      << r.output;
  // The bundled specs have none of these mistakes.
  r = run_cli("check " + shell_quote(source_path("samples/specs/study.haptic")));
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
}

TEST(CliNewcomer, DidYouMeanForOptionsAndCommands) {
  CliRun r = run_cli("match --explian a b");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown option '--explian'; did you mean '--explain'?"),
            std::string::npos)
      << r.output;
  r = run_cli("chek x.haptic");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown command 'chek'; did you mean 'check'?"), std::string::npos)
      << r.output;
  // Nothing close: no guess.
  r = run_cli("match --zzzzzzzz a b");
  EXPECT_EQ(r.output.find("did you mean"), std::string::npos) << r.output;
}

TEST(CliNewcomer, VersionPrintsTheProjectVersion) {
  const CliRun r = run_cli("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.output.rfind("annex-runtime ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find('.'), std::string::npos) << r.output;
}

// One cylinder prop 2.5 times the virtual radius: it wins by default (drawn clamped),
// loses to the object's min_vote, and to --within-limits.
const char* kScene =
    "annex-scene 1\n"
    "support 0 -1 0 0\n"
    "object p1\n"
    "  cylinder radius 0.1 height 0.2 center 0 -0.1 1 axis 0 -1 0 fit 0.9\n"
    "end\n";

std::string spec_with(const std::string& extra) {
  return "annex-haptic 1\n"
         "object cup\n" +
         extra +
         "  primitive body cylinder\n"
         "    radius 0.04 scale 0.7 1.4\n"
         "    height 0.2\n"
         "  end\n"
         "end\n";
}

TEST(CliMatchLimits, MinVoteAndWithinLimitsKeepABadPropFromWinning) {
  const std::string scene = temp_spec("one.scene", kScene);
  const std::string plain = temp_spec("plain.haptic", spec_with(""));
  CliRun r = run_cli("match " + shell_quote(plain) + " " + shell_quote(scene));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output, "match cup p1 70.00\n");  // 0.5 * 0.4 + 0.5 * 1
  r = run_cli("match --within-limits " + shell_quote(plain) + " " + shell_quote(scene));
  EXPECT_EQ(r.output, "virtual-only cup\n") << r.output;
  r = run_cli("match --min-vote 70 " + shell_quote(plain) + " " + shell_quote(scene));
  EXPECT_EQ(r.output, "virtual-only cup\n") << r.output;

  const std::string strict = temp_spec("strict.haptic", spec_with("  min_vote 75\n"));
  r = run_cli("match " + shell_quote(strict) + " " + shell_quote(scene));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output, "virtual-only cup\n") << r.output;
  const std::string loose = temp_spec("loose.haptic", spec_with("  min_vote 70\n"));
  r = run_cli("match " + shell_quote(loose) + " " + shell_quote(scene));
  EXPECT_EQ(r.output, "match cup p1 70.00\n") << r.output;  // at the minimum still matches
}

TEST(CliMatchLimits, ABadMinVoteNamesItsLineAndColumn) {
  const std::string bad = temp_spec("bad_min.haptic", spec_with("  min_vote -3\n"));
  const CliRun r = run_cli("check " + shell_quote(bad));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find(bad + ":3:12: error: min_vote must be a vote from 0 to 1000"),
            std::string::npos)
      << r.output;
}


// The bundled recording's roll of tape for the mug's handle, without the spec's
// min_vote: matched and reported clamped everywhere; --within-limits refuses it.
std::string study_without_min_vote() {
  std::ifstream in(source_path("samples/specs/study.haptic"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = text.find("  min_vote 20\n");
  EXPECT_NE(at, std::string::npos);
  if (at != std::string::npos) text.erase(at, 14);
  return temp_spec("study_no_min_vote.haptic", text);
}

TEST(CliRunLimits, AClampedMatchIsReportedInEveryOutput) {
  const std::string spec = study_without_min_vote();
  const TempDir out("cli_newcomer_clamped");
  std::ofstream(out / "overlay_00099.png") << "stale";
  std::ofstream(out / "keep.png") << "not ours";
  const CliRun r = run_cli("run " + shell_quote(spec) + " --source " +
                           shell_quote(source_path("samples/recordings/tabletop")) + " --out " +
                           shell_quote(out.string()) + " --no-overlays");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("frame 0 match mug p3 9."), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" clamped\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("note: mug on p3 needs major_radius x2.2"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("(limits 0.50..1.50), minor_radius x3."), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("annexed mug p3 state=tracking clamped"), std::string::npos)
      << r.output;
  // The earlier run's overlay is gone, and said so; other files stay.
  EXPECT_NE(r.output.find("removed 1 overlay PNG of an earlier run"), std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(out / "overlay_00099.png"));
  EXPECT_TRUE(std::filesystem::exists(out / "keep.png"));
  std::ifstream poses(out / "poses.txt");
  std::string line;
  int mug = 0, clamped = 0;
  while (std::getline(poses, line)) {
    if (line.find(" mug ") == std::string::npos) continue;
    ++mug;
    clamped += line.ends_with(" clamped");
  }
  EXPECT_GT(mug, 0);
  EXPECT_EQ(clamped, mug);
}

TEST(CliRunLimits, WithinLimitsLeavesTheMugVirtualAndSaysWhy) {
  const std::string spec = study_without_min_vote();
  const CliRun r = run_cli("run " + shell_quote(spec) + " --source " +
                           shell_quote(source_path("samples/recordings/tabletop")) +
                           " --frames 1 --within-limits");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("match mug"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("p3 needs major_radius scaled x2.2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("outside its limits 0.50..1.50"), std::string::npos) << r.output;
  // Neither --out nor --window: a warning says nothing is saved or shown.
  EXPECT_NE(r.output.find("warning: no --out DIR and no --window"), std::string::npos)
      << r.output;
}

TEST(CliRunLimits, NothingAnnexedSaysWhyForEachObject) {
  const std::string spec = temp_spec("huge_min.haptic", spec_with("  min_vote 999\n"));
  const CliRun r = run_cli("run " + shell_quote(spec) + " --source " +
                           shell_quote(source_path("samples/recordings/tabletop")) +
                           " --frames 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("no prop was annexed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("cup: p1 votes"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("under cup's min_vote 999"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace annex::test
