// annex-runtime synth, run as a user runs it: files written, ground truth readable,
// the same seed giving the same bytes, bad arguments refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#include "annex/formats/scene_format.h"
#include "annex/runtime/pcd_io.h"
#include "cli_runner.h"
#include "temp_dir.h"

namespace annex::test {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = process_temp_dir() / ("cli_synth_" + name);
  fs::remove_all(dir);
  return dir;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(CliSynth, WritesFramesWithReadableGroundTruth) {
  const fs::path dir = fresh_dir("one");
  const CliRun r = run_cli("synth --seed 3 --objects 3 --out " + shell_quote(dir.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Result<Frame> frame = read_pcd(dir / "scene_0000.pcd");
  ASSERT_TRUE(frame.ok()) << frame.error().format();
  EXPECT_EQ(frame->width, 640);
  EXPECT_EQ(frame->height, 480);
  const Result<PhysicalScene> truth = read_scene_file(dir / "scene_0000.scene");
  ASSERT_TRUE(truth.ok()) << truth.error().format();
  EXPECT_EQ(truth->objects.size(), 3u);
  EXPECT_TRUE(truth->support.has_value());

  const fs::path again = fresh_dir("again");
  ASSERT_EQ(run_cli("synth --seed 3 --objects 3 --out " + shell_quote(again.string())).exit_code, 0);
  EXPECT_EQ(bytes_of(dir / "scene_0000.pcd"), bytes_of(again / "scene_0000.pcd"));
  EXPECT_EQ(bytes_of(dir / "scene_0000.scene"), bytes_of(again / "scene_0000.scene"));
  fs::remove_all(dir);
  fs::remove_all(again);
}

// The robust spread (median absolute height over 0.6745) of the table's points around
// the truth's table plane: the depth noise across it.
double table_spread(const fs::path& dir) {
  const Result<Frame> frame = read_pcd(dir / "scene_0000.pcd");
  const Result<PhysicalScene> truth = read_scene_file(dir / "scene_0000.scene");
  EXPECT_TRUE(frame.ok() && truth.ok() && truth->support.has_value());
  if (!frame || !truth || !truth->support) return 0;
  const Plane& table = *truth->support;
  std::vector<double> h;
  for (const PointXYZRGB& p : frame->points) {
    if (!(p.z > 0)) continue;
    const double d = dot(table.normal, Vec3{p.x, p.y, p.z}) + table.d;
    if (std::abs(d) < 0.05) h.push_back(std::abs(d));
  }
  if (h.empty()) return 0;
  std::nth_element(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(h.size() / 2), h.end());
  return h[h.size() / 2] / 0.6745;
}

TEST(CliSynth, DepthNoiseRendersAnotherCamerasNoise) {
  // An active stereo camera's noise is about twice the Kinect's at a metre.
  const fs::path kinect = fresh_dir("kinect"), stereo = fresh_dir("stereo");
  ASSERT_EQ(run_cli("synth --seed 3 --objects 0 --out " + shell_quote(kinect.string())).exit_code,
            0);
  const CliRun r = run_cli("synth --seed 3 --objects 0 --depth-noise stereo --out " +
                           shell_quote(stereo.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const double k = table_spread(kinect), st = table_spread(stereo);
  EXPECT_GT(k, 0.0005);
  EXPECT_GT(st, 1.5 * k) << "kinect " << k << " m, stereo " << st << " m";
  const CliRun bad = run_cli("synth --depth-noise lidar --out " + shell_quote(stereo.string()));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("--depth-noise expects one of kinect, stereo, tof, got 'lidar'"),
            std::string::npos)
      << bad.output;
  fs::remove_all(kinect);
  fs::remove_all(stereo);
}

// --stacked puts objects on boxes' and cylinders' tops, and the truth says which (the
// scene file's on_object); --flying takes a share; bad shares are errors naming them.
TEST(CliSynth, StackedObjectsAndFlyingPixelsAreOptions) {
  const fs::path dir = fresh_dir("stacked");
  const CliRun r = run_cli(
      "synth --seed 5 --scenes 6 --objects 6 --kinds box,cylinder --stacked 1 "
      "--flying 0.5 --out " +
      shell_quote(dir.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  int stacked = 0;
  for (int i = 0; i < 6; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "scene_%04d.scene", i);
    const Result<PhysicalScene> truth = read_scene_file(dir / name);
    ASSERT_TRUE(truth.ok()) << truth.error().format();
    for (const PhysicalObject& o : truth->objects) stacked += !o.on_object.empty();
  }
  EXPECT_GE(stacked, 3);
  const CliRun everyday =
      run_cli("synth --seed 5 --objects 6 --kinds cylinder --everyday 1 --out " +
              shell_quote(dir.string()));
  EXPECT_EQ(everyday.exit_code, 0) << everyday.output;
  for (const char* bad : {"--stacked 1.5", "--flying -0.1", "--stacked half", "--everyday 2"}) {
    const CliRun b = run_cli(std::string("synth ") + bad + " --out " + shell_quote(dir.string()));
    EXPECT_EQ(b.exit_code, 2) << bad;
    EXPECT_NE(b.output.find("expects a share from 0 to 1"), std::string::npos) << b.output;
  }
  fs::remove_all(dir);
}

TEST(CliSynth, SequencesAndSceneSetsAreNumbered) {
  const fs::path dir = fresh_dir("seq");
  ASSERT_EQ(run_cli("synth --objects 2 --frames 3 --occluder --out " + shell_quote(dir.string())).exit_code, 0);
  for (const char* name : {"scene_0000", "scene_0001", "scene_0002"}) {
    EXPECT_TRUE(fs::exists(dir / (std::string(name) + ".pcd"))) << name;
    EXPECT_TRUE(fs::exists(dir / (std::string(name) + ".scene"))) << name;
  }
  EXPECT_FALSE(fs::exists(dir / "scene_0003.pcd"));
  fs::remove_all(dir);
  ASSERT_EQ(run_cli("synth --scenes 2 --kinds sphere,box --out " + shell_quote(dir.string())).exit_code, 0);
  EXPECT_TRUE(fs::exists(dir / "scene_0001.scene"));
  fs::remove_all(dir);
}

TEST(CliSynth, BadArgumentsExitTwo) {
  const fs::path dir = fresh_dir("bad");
  EXPECT_EQ(run_cli("synth").exit_code, 2);
  EXPECT_EQ(run_cli("synth --objects many --out " + shell_quote(dir.string())).exit_code, 2);
  EXPECT_EQ(run_cli("synth --frames 2 --scenes 2 --out " + shell_quote(dir.string())).exit_code, 2);
  const CliRun r = run_cli("synth --kinds cube --out " + shell_quote(dir.string()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown shape 'cube'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir));
}

}  // namespace
}  // namespace annex::test
