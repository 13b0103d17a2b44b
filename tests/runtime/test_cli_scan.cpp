// annex-runtime scan as a user runs it: output lines, files, --repeat, exit codes.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "annex/formats/scene_format.h"
#include "annex/runtime/depth_noise.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/synthetic_scene.h"
#include "cli_runner.h"
#include "temp_dir.h"

namespace annex {
namespace {

using test::run_cli;
using test::shell_quote;

// This program's temporary folder, removed when it ends.
const std::filesystem::path& temp_dir() {
  return test::process_temp_dir();
}

// A generated tabletop frame written as PCD.
std::filesystem::path scene_pcd() {
  const auto path = temp_dir() / "scene.pcd";
  if (std::filesystem::exists(path)) return path;
  SyntheticSceneParams p;
  p.seed = 5;
  const Result<SyntheticScene> scene = generate_scene(p);
  EXPECT_TRUE(scene.ok());
  const Status s = write_pcd(path, render_scene(*scene).frame);
  EXPECT_TRUE(s.ok());
  return path;
}

TEST(CliScan, ExplainListsEveryCandidateUnderItsObject) {
  const auto r = run_cli("scan " + shell_quote(scene_pcd().string()) + " --explain");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::regex candidate(
      "\nobject p1 [^\n]*\n(  candidate p1 (sphere|cylinder|cone|torus|box)( [a-z_]+=[0-9.]+)+ "
      "center=\\S+ axis=\\S+ coverage=[0-9.]+ rms_mm=[0-9.]+\n)+object p2 ");
  EXPECT_TRUE(std::regex_search(r.output, candidate)) << r.output;
}

TEST(CliScan, PrintsPlaneThenObjects) {
  const auto r = run_cli("scan " + shell_quote(scene_pcd().string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(std::regex_search(r.output, std::regex("^plane normal=-?[0-9.]+,-?[0-9.]+,-?[0-9.]+ d=")))
      << r.output;
  const std::regex object(
      "\nobject p1 (sphere|cylinder|cone|torus|box)( [a-z_]+=[0-9.]+)+ center=\\S+ axis=\\S+ "
      "points=[0-9]+ fit=[0-9.]+ support=s[0-9]+( partial=1)?\n");
  EXPECT_TRUE(std::regex_search(r.output, object)) << r.output;
  EXPECT_NE(r.output.find("\nobject p2 "), std::string::npos);
  // One line per support, the first the plane's.
  const std::regex support("\nsupport s1 normal=-?[0-9.]+,-?[0-9.]+,-?[0-9.]+ d=[0-9.]+ points=[0-9]+\n");
  EXPECT_TRUE(std::regex_search(r.output, support)) << r.output;
}

TEST(CliScan, SupportsOptionChoosesAndNamesBadChoices) {
  const auto r = run_cli("scan " + shell_quote(scene_pcd().string()) + " --supports largest");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\nsupport s1 "), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("\nsupport s2 "), std::string::npos) << r.output;
  const auto bad = run_cli("scan " + shell_quote(scene_pcd().string()) + " --supports tallest");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("supports must be all, nearest, highest, largest or a support id"),
            std::string::npos)
      << bad.output;
  const auto missing = run_cli("scan " + shell_quote(scene_pcd().string()) + " --supports s9");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find("no support 's9' in this frame (found: s1"), std::string::npos)
      << missing.output;
}

// Lines of `output` that start with `prefix`.
int lines_starting(const std::string& output, const std::string& prefix) {
  int n = 0;
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);) n += line.rfind(prefix, 0) == 0;
  return n;
}

TEST(CliScan, DepthNoiseOptionNamesTheCamera) {
  // A held-out scene seen by an active stereo camera (a RealSense's noise): scanned as a
  // Kinect frame it falls apart into dozens of pieces; --depth-noise stereo keeps one
  // object per object on the table.
  const auto path = temp_dir() / "stereo.pcd";
  const Result<SyntheticScene> scene = generate_scene(world_scene_params(5010u));
  ASSERT_TRUE(scene.ok());
  SensorNoiseParams noise;
  noise.axial = *depth_noise_named("stereo");
  ASSERT_TRUE(write_pcd(path, render_scene(*scene, noise).frame).ok());
  const int truth = static_cast<int>(scene->objects.size());
  const auto own = run_cli("scan " + shell_quote(path.string()) + " --depth-noise stereo");
  ASSERT_EQ(own.exit_code, 0) << own.output;
  EXPECT_LE(lines_starting(own.output, "object "), truth + 1) << own.output;
  const auto kinect = run_cli("scan " + shell_quote(path.string()));
  ASSERT_EQ(kinect.exit_code, 0) << kinect.output;
  EXPECT_GT(lines_starting(kinect.output, "object "), 2 * truth) << kinect.output;
  const auto bad = run_cli("scan " + shell_quote(path.string()) + " --depth-noise lidar");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("--depth-noise expects one of kinect, stereo, tof, got 'lidar'"),
            std::string::npos)
      << bad.output;
}

TEST(CliScan, WritesSceneAndPng) {
  const auto scene = temp_dir() / "out.scene", png = temp_dir() / "out.png";
  const auto r = run_cli("scan " + shell_quote(scene_pcd().string()) + " --scene " +
                         shell_quote(scene.string()) + " --png " + shell_quote(png.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Result<PhysicalScene> s = read_scene_file(scene);
  ASSERT_TRUE(s.ok()) << s.error().format();
  EXPECT_TRUE(s->support.has_value());
  EXPECT_GE(s->objects.size(), 2u);
  std::ifstream in(png, std::ios::binary);
  std::string head(8, '\0');
  in.read(head.data(), 8);
  EXPECT_EQ(head.substr(1, 3), "PNG");
}

TEST(CliScan, RepeatPrintsStageMedians) {
  const auto r = run_cli("scan " + shell_quote(scene_pcd().string()) + " --repeat 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* stage : {"plane", "prism", "clusters", "mls", "shapes"})
    EXPECT_TRUE(std::regex_search(
        r.output, std::regex(std::string("\nstage ") + stage + " median_ms=[0-9.]+\n")))
        << stage << "\n" << r.output;
  EXPECT_TRUE(std::regex_search(r.output, std::regex("\ntotal median_ms=[0-9.]+\n")));
}

TEST(CliScan, BadInputExitsTwo) {
  EXPECT_EQ(run_cli("scan /nonexistent.pcd").exit_code, 2);
  EXPECT_EQ(run_cli("scan").exit_code, 2);
  EXPECT_EQ(run_cli("scan a.pcd b.pcd").exit_code, 2);
  EXPECT_EQ(run_cli("scan " + shell_quote(scene_pcd().string()) + " --repeat x").exit_code, 2);
  EXPECT_EQ(run_cli("scan " + shell_quote(scene_pcd().string()) + " --bogus").exit_code, 2);
  const auto conf = temp_dir() / "bad.conf";
  std::ofstream(conf) << "pixel_stride 2\nnot_a_key 1\n";
  const auto r = run_cli("scan " + shell_quote(scene_pcd().string()) + " --config " +
                         shell_quote(conf.string()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("bad.conf:2:1: error: unknown key 'not_a_key'"), std::string::npos)
      << r.output;
  const auto garbage = temp_dir() / "garbage.pcd";
  std::ofstream(garbage) << "not a point cloud\n";
  EXPECT_EQ(run_cli("scan " + shell_quote(garbage.string())).exit_code, 2);
}

TEST(CliScan, NoPlaneExitsOne) {
  // A wall seen head-on: valid depth, no horizontal support.
  Frame f;
  f.width = 64;
  f.height = 48;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      PointXYZRGB p;
      p.z = 1.5f;
      p.x = static_cast<float>((x - 32) * 0.03);
      p.y = static_cast<float>((y - 24) * 0.03);
      f.points.push_back(p);
    }
  const auto path = temp_dir() / "wall.pcd";
  ASSERT_TRUE(write_pcd(path, f).ok());
  const auto r = run_cli("scan " + shell_quote(path.string()));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("no horizontal plane"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace annex
