// Virtual panels through `annex-runtime run` and the OSC stream on the three real
// Kinect frames of the laptop scene (../shared/data/real, skipped when absent): a
// screen on the laptop's lid and a keyboard on the table in front, in poses.txt frame
// by frame and in /annex/object messages.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "annex/formats/haptic_format.h"
#include "annex/runtime/annex_session.h"
#include "annex/runtime/osc_stream.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/scanner.h"
#include "cli_runner.h"
#include "temp_dir.h"

namespace annex::test {
namespace {

const std::filesystem::path kReal = std::filesystem::path(ANNEX_SHARED_DIR) / "data" / "real";
const char* const kFrames[] = {"frame_20121214T142255.814212.pcd",
                               "frame_20121214T142256.068683.pcd",
                               "frame_20121214T142256.332395.pcd"};
constexpr const char* kPanels =
    "annex-haptic 1\n"
    "object screen\n  primitive face plane\n    size_x 0.35\n    size_y 0.24\n  end\nend\n"
    "object keyboard\n  primitive keys plane\n    size_x 0.45\n    size_y 0.14\n  end\nend\n";

bool have_frames() {
  for (const char* f : kFrames)
    if (!std::filesystem::exists(kReal / f)) return false;
  return true;
}

// poses.txt's t= of one line.
Vec3 translation_of(const std::string& line) {
  const size_t at = line.find(" t=");
  Vec3 t;
  std::sscanf(line.c_str() + at + 3, "%lf,%lf,%lf", &t.x, &t.y, &t.z);
  return t;
}

TEST(CliSurfaces, RunWritesThePanelsPosesFrameByFrame) {
  if (!have_frames()) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  const TempDir dir("cli_surfaces");
  std::filesystem::create_directories(dir / "frames");
  for (const char* f : kFrames) std::filesystem::create_symlink(kReal / f, dir / "frames" / f);
  std::ofstream(dir / "panels.haptic") << kPanels;
  const CliRun r = run_cli("run " + shell_quote((dir / "panels.haptic").string()) + " --source " +
                           shell_quote((dir / "frames").string()) + " --no-overlays --out " +
                           shell_quote((dir / "out").string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("frame 0 match screen p1.face "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("frame 0 match keyboard s1.free "), std::string::npos) << r.output;
  std::ifstream in(dir / "out" / "poses.txt");
  std::map<std::string, std::vector<std::string>> lines;  // "screen p1.face" -> per frame
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string frame, index, name, id;
    words >> frame >> index >> name >> id;
    lines[name + " " + id].push_back(line);
  }
  ASSERT_EQ(lines["screen p1.face"].size(), 3u);
  ASSERT_EQ(lines["keyboard s1.free"].size(), 3u);
  // The screen rides on the lid: at the last frame it is where that frame's scan sees
  // the lid's face, within 1 cm.
  Result<Frame> last = read_pcd(kReal / kFrames[2]);
  ASSERT_TRUE(last.ok());
  Result<ScanResult> scan = scan_frame(*last);
  ASSERT_TRUE(scan.ok());
  const auto lid = std::find_if(scan->surfaces.begin(), scan->surfaces.end(),
                                [](const PhysicalObject& o) { return o.id == "p1.face"; });
  ASSERT_NE(lid, scan->surfaces.end());
  EXPECT_LT(norm(translation_of(lines["screen p1.face"][2]) - lid->primitives[0].center), 0.01)
      << lines["screen p1.face"][2];
  EXPECT_NE(lines["keyboard s1.free"][2].find(" state=tracking "), std::string::npos);
}

TEST(CliSurfaces, OscObjectMessagesCarryThePanels) {
  if (!have_frames()) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  Result<HapticSpec> spec = parse_haptic(kPanels, "panels.haptic");
  ASSERT_TRUE(spec.ok());
  AnnexSession session(*spec, {});
  FrameReport report;
  for (int k = 0; k < 3; ++k) {
    Result<Frame> f = read_pcd(kReal / kFrames[k]);
    ASSERT_TRUE(f.ok());
    report = session.process(*f, k);
  }
  ASSERT_EQ(report.objects.size(), 2u);
  const std::vector<OscMessage> m = frame_messages(*spec, report, 0.1);
  std::map<std::string, const OscMessage*> by_id;
  for (const OscMessage& msg : m)
    if (msg.address == "/annex/object") by_id[std::get<std::string>(msg.args[1])] = &msg;
  ASSERT_EQ(by_id.size(), 2u);
  for (const AnnexedObject& o : report.objects) {
    ASSERT_TRUE(by_id.count(o.physical_id)) << o.physical_id;
    const OscMessage& msg = *by_id[o.physical_id];
    EXPECT_EQ(std::get<std::string>(msg.args[0]), o.virtual_name);
    const Vec3 t = decompose_model_transform(world_from_model(*spec, o)).translation;
    EXPECT_NEAR(std::get<float>(msg.args[4]), t.x, 1e-5);
    EXPECT_NEAR(std::get<float>(msg.args[5]), t.y, 1e-5);
    EXPECT_NEAR(std::get<float>(msg.args[6]), t.z, 1e-5);
  }
  EXPECT_TRUE(by_id.count("p1.face") && by_id.count("s1.free"));
}

}  // namespace
}  // namespace annex::test
