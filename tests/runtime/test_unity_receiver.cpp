// docs/streaming.md's Unity receiver, as printed there, compiled with Mono's C# compiler
// against a stub of the UnityEngine types it uses (tests/runtime/unity/) and run while
// `run` streams the bundled recording: every virtual object ends where poses.txt puts
// it, converted to Unity's left-handed, y-up frame. Skipped when Mono is not installed.
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "cli_runner.h"
#include "temp_dir.h"

namespace annex {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool have(const char* tool) {
  return std::system(("command -v " + std::string(tool) + " >/dev/null 2>&1").c_str()) == 0;
}

std::vector<double> numbers(const std::string& csv) {
  std::vector<double> out;
  std::stringstream s(csv);
  std::string n;
  while (std::getline(s, n, ',')) out.push_back(std::stod(n));
  return out;
}

TEST(UnityReceiver, PlacesTheObjectsWherePosesTxtSays) {
  if (!have("mcs") || !have("mono")) GTEST_SKIP() << "Mono (mono-mcs, mono-runtime) not installed";
  const test::TempDir dir("test_unity");
  // The script exactly as the documentation prints it.
  const std::string doc = slurp(test::source_path("docs/streaming.md"));
  const size_t start = doc.find("```csharp\n");
  ASSERT_NE(start, std::string::npos) << "no C# block in docs/streaming.md";
  const size_t end = doc.find("\n```", start + 10);
  ASSERT_NE(end, std::string::npos);
  std::ofstream(dir / "AnnexReceiver.cs") << doc.substr(start + 10, end - start - 10 + 1);
  const std::string unity = test::source_path("tests/runtime/unity");
  const std::string compile = "mcs -out:" + (dir / "receiver.exe").string() + " " +
                              (dir / "AnnexReceiver.cs").string() + " " + unity +
                              "/UnityEngineStub.cs " + unity + "/ReceiverDriver.cs 2>&1";
  ASSERT_EQ(std::system((compile + " > " + (dir / "mcs.txt").string()).c_str()), 0)
      << slurp(dir / "mcs.txt");

  // Port 0: the receiver binds one the OS picks and names it.
  const std::string receiver =
      "mono " + (dir / "receiver.exe").string() + " 0 3 champagne_bottle lamp 2>&1";
  FILE* pipe = popen(receiver.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  char line[512];
  ASSERT_NE(fgets(line, sizeof line, pipe), nullptr);
  std::cmatch listening;
  ASSERT_TRUE(std::regex_match(line, listening, std::regex("listening ([1-9][0-9]*)\n"))) << line;
  const int port = std::stoi(listening[1]);
  const test::CliRun run = test::run_cli(
      "run " + test::source_path("samples/specs/study.haptic") + " --source " +
      test::source_path("samples/recordings/tabletop") + " --out " + (dir / "out").string() +
      " --no-overlays --stream osc.udp://127.0.0.1:" + std::to_string(port));
  std::string output;
  while (fgets(line, sizeof line, pipe)) output += line;
  const int status = pclose(pipe);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ASSERT_EQ(status, 0) << output;
  EXPECT_NE(output.find("last_frame 3\n"), std::string::npos) << output;

  std::map<std::string, std::vector<double>> expected;  // t, q (w x y z), scale
  std::ifstream poses(dir / "out" / "poses.txt");
  const std::regex pose(R"(frame 3 (\S+) \S+ state=\S+ t=(\S+) q=(\S+) scale=(\S+).*)");
  std::string text;
  while (std::getline(poses, text)) {
    std::smatch m;
    if (!std::regex_match(text, m, pose)) continue;
    std::vector<double> v = numbers(m[2]);
    for (double q : numbers(m[3])) v.push_back(q);
    for (double s : numbers(m[4])) v.push_back(s);
    expected[m[1]] = v;
  }
  ASSERT_EQ(expected.size(), 2u);
  const std::regex object(R"(object (\S+) active=(\d) p=(\S+) q=(\S+) s=(\S+))");
  int seen = 0;
  for (std::sregex_iterator it(output.begin(), output.end(), object), stop; it != stop; ++it) {
    const std::string name = (*it)[1];
    ASSERT_EQ(expected.count(name), 1u) << name;
    const std::vector<double>& e = expected[name];
    EXPECT_EQ((*it)[2], "1") << name << " hidden";
    const std::vector<double> p = numbers((*it)[3]), q = numbers((*it)[4]), s = numbers((*it)[5]);
    ASSERT_EQ(p.size(), 3u);
    ASSERT_EQ(q.size(), 4u);
    ASSERT_EQ(s.size(), 3u);
    // Unity: y up (y mirrored), quaternion x y z w with x and z negated.
    EXPECT_NEAR(p[0], e[0], 1e-4) << name;
    EXPECT_NEAR(p[1], -e[1], 1e-4) << name;
    EXPECT_NEAR(p[2], e[2], 1e-4) << name;
    EXPECT_NEAR(q[0], -e[4], 2e-5) << name;
    EXPECT_NEAR(q[1], e[5], 2e-5) << name;
    EXPECT_NEAR(q[2], -e[6], 2e-5) << name;
    EXPECT_NEAR(q[3], e[3], 2e-5) << name;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(s[k], e[7 + k], 1e-4) << name;
    ++seen;
  }
  EXPECT_EQ(seen, 2) << output;
}

}  // namespace
}  // namespace annex
