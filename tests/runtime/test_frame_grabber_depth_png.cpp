// Depth PNG sources: the TUM list parser, TUM RGB-D sequences and folders of depth
// PNGs built here from generated scenes (16-bit PNGs written by the test's own
// encoder), their errors, and `scan` / `run` on them as a user would call them.
#include "annex/runtime/frame_grabber_depth_png.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "annex/common/haptic_model.h"
#include "annex/formats/haptic_format.h"
#include "annex/formats/png_io.h"
#include "annex/runtime/synthetic_scene.h"
#include "cli_runner.h"
#include "png_test_encoder.h"
#include "temp_dir.h"

namespace annex {
namespace {

namespace fs = std::filesystem;

using test::TempDir;
using test::write_bytes;

// A frame's depth as a 16-bit PNG with `scale` units per metre (0 where NaN).
std::string depth_png(const Frame& f, double scale) {
  std::vector<std::uint16_t> px(f.points.size(), 0);
  for (std::size_t i = 0; i < px.size(); ++i)
    if (std::isfinite(f.points[i].z))
      px[i] = static_cast<std::uint16_t>(std::lround(f.points[i].z * scale));
  return test::encode_grey_png(f.width, f.height, 16, px);
}

void write_color_png(const fs::path& p, const Frame& f) {
  std::vector<std::uint8_t> rgb;
  for (const PointXYZRGB& q : f.points) rgb.insert(rgb.end(), {q.r, q.g, q.b});
  fs::create_directories(p.parent_path());
  ASSERT_TRUE(write_png_file(p, f.width, f.height, 3, rgb.data()));
}

SyntheticScene test_scene() {
  SyntheticSceneParams p;
  p.seed = 33;
  p.object_count = 3;
  p.kinds = {ShapeKind::cylinder, ShapeKind::sphere, ShapeKind::box};
  Result<SyntheticScene> s = generate_scene(p);
  if (!s) ADD_FAILURE() << s.error().format();
  return s ? *s : SyntheticScene{};
}

// A TUM RGB-D folder of `frames` frames of the scene: depth at TUM's 5000 per metre,
// colour 10 ms after each depth image, as the TUM recorder's lists have them.
std::vector<Frame> write_tum_folder(const fs::path& dir, const SyntheticScene& scene, int frames) {
  std::string depth_list = "# depth maps\n# file: 'annex_test.bag'\n# timestamp filename\n";
  std::string rgb_list = "# color images\n# file: 'annex_test.bag'\n# timestamp filename\n";
  std::vector<Frame> out;
  for (int k = 0; k < frames; ++k) {
    const Frame f = render_scene(scene, {}, k).frame;
    char t[32], tc[32];
    std::snprintf(t, sizeof t, "%.6f", 1305031102.160407 + k / 30.0);
    std::snprintf(tc, sizeof tc, "%.6f", 1305031102.170407 + k / 30.0);
    write_bytes(dir / "depth" / (std::string(t) + ".png"), depth_png(f, 5000));
    write_color_png(dir / "rgb" / (std::string(tc) + ".png"), f);
    depth_list += std::string(t) + " depth/" + t + ".png\n";
    rgb_list += std::string(tc) + " rgb/" + tc + ".png\n";
    out.push_back(f);
  }
  write_bytes(dir / "depth.txt", depth_list);
  write_bytes(dir / "rgb.txt", rgb_list);
  return out;
}

TEST(TumList, ParsesCommentsBlanksAndCrlf) {
  const Result<std::vector<TumListEntry>> l = parse_tum_list(
      "# depth maps\n# timestamp filename\n\n1305031102.160407 depth/1305031102.160407.png\r\n"
      "  1305031102.194330\t depth/1305031102.194330.png  \n",
      "depth.txt");
  ASSERT_TRUE(l) << l.error().format();
  ASSERT_EQ(l->size(), 2u);
  EXPECT_DOUBLE_EQ((*l)[0].timestamp_s, 1305031102.160407);
  EXPECT_EQ((*l)[0].file, "depth/1305031102.160407.png");
  EXPECT_EQ((*l)[0].line, 4);
  EXPECT_EQ((*l)[1].file, "depth/1305031102.194330.png");
  EXPECT_TRUE(parse_tum_list("", "depth.txt")->empty());
}

TEST(TumList, MalformedLinesCarryLineAndColumn) {
  struct Case {
    const char* text;
    int line, column;
    const char* message_part;
  };
  const Case cases[] = {
      {"# c\n1.5\n", 2, 4, "the file name is missing"},
      {"1.5 a.png\n  x1.5 b.png\n", 2, 3, "expected a timestamp"},
      {"1.5 a.png extra\n", 1, 11, "more after the file name"},
      {"-2 a.png\n", 1, 1, "expected a timestamp"},
      {"nan a.png\n", 1, 1, "expected a timestamp"},
      {"1.5e400 a.png\n", 1, 1, "expected a timestamp"},
  };
  for (const Case& c : cases) {
    const Result<std::vector<TumListEntry>> l = parse_tum_list(c.text, "rgb.txt");
    ASSERT_FALSE(l) << c.text;
    EXPECT_EQ(l.error().location.origin, "rgb.txt");
    EXPECT_EQ(l.error().location.line, c.line) << c.text << " -> " << l.error().format();
    EXPECT_EQ(l.error().location.column, c.column) << c.text << " -> " << l.error().format();
    EXPECT_NE(l.error().message.find(c.message_part), std::string::npos) << l.error().format();
  }
}

TEST(TumSequence, DeliversEveryDepthFrameWithTheNearestColour) {
  TempDir dir("tum");
  const SyntheticScene scene = test_scene();
  const std::vector<Frame> truth = write_tum_folder(dir.path(), scene, 3);
  FrameSourceParams params;  // TUM's 5000 units a metre by default
  auto g = open_frame_source(dir.path().string(), params);
  ASSERT_TRUE(g) << g.error().format();
  EXPECT_EQ((*g)->frame_count(), 3);
  EXPECT_NE((*g)->describe().find("TUM RGB-D sequence"), std::string::npos) << (*g)->describe();
  EXPECT_NE((*g)->describe().find("3 with colour, depth scale 5000"), std::string::npos)
      << (*g)->describe();
  for (int k = 0; k < 3; ++k) {
    Result<std::optional<Frame>> f = (*g)->next();
    ASSERT_TRUE(f) << f.error().format();
    ASSERT_TRUE(*f);
    const Frame& got = **f;
    EXPECT_EQ(got.index, k);
    EXPECT_NEAR(got.timestamp_s, k / 30.0, 1e-5);
    ASSERT_EQ(got.points.size(), truth[k].points.size());
    // Depth survives to TUM's 0.2 mm step (and the millimetres it is read into);
    // colour is the frame's own.
    int compared = 0;
    for (std::size_t i = 0; i < got.points.size(); i += 97) {
      const PointXYZRGB &a = got.points[i], &b = truth[k].points[i];
      if (!std::isfinite(b.z)) continue;
      ++compared;
      EXPECT_NEAR(a.z, b.z, 0.0006) << i;
      EXPECT_EQ(a.r, b.r) << i;
      EXPECT_EQ(a.g, b.g) << i;
    }
    EXPECT_GT(compared, 1000);
  }
  Result<std::optional<Frame>> end = (*g)->next();
  ASSERT_TRUE(end);
  EXPECT_FALSE(*end);

  // Colour further than max_color_gap_s from a depth image is not paired.
  params.max_color_gap_s = 0.005;
  auto far = open_tum_sequence(dir.path(), params);
  ASSERT_TRUE(far) << far.error().format();
  EXPECT_NE((*far)->describe().find("0 with colour"), std::string::npos) << (*far)->describe();
}

TEST(TumSequence, ErrorsNameTheFileAndLine) {
  TempDir dir("tum_errors");
  const SyntheticScene scene = test_scene();
  write_tum_folder(dir.path(), scene, 2);
  // A listed file that is not there: the list's line.
  std::ofstream(dir.path() / "rgb.txt", std::ios::app) << "1305031109.0 rgb/missing.png\n";
  auto g = open_tum_sequence(dir.path());
  ASSERT_FALSE(g);
  EXPECT_EQ(g.error().location.origin, (dir.path() / "rgb.txt").string());
  EXPECT_EQ(g.error().location.line, 6);
  EXPECT_NE(g.error().message.find("rgb/missing.png"), std::string::npos) << g.error().format();
  // A malformed list line.
  write_bytes(dir.path() / "rgb.txt", "# c\n1305031102.17 rgb/a.png rgb/b.png\n");
  g = open_tum_sequence(dir.path());
  ASSERT_FALSE(g);
  EXPECT_EQ(g.error().format().find((dir.path() / "rgb.txt").string() + ":2:25: error:"), 0u)
      << g.error().format();
  fs::remove(dir.path() / "rgb.txt");  // colour is optional

  // An 8-bit depth image and one of another size, named with their frame.
  std::string list = "1.0 depth/eight.png\n2.0 depth/ok.png\n3.0 depth/small.png\n";
  const std::vector<std::uint16_t> px(4 * 3, 120);
  write_bytes(dir.path() / "depth/eight.png", test::encode_grey_png(4, 3, 8, px));
  write_bytes(dir.path() / "depth/ok.png", test::encode_grey_png(4, 3, 16, px));
  write_bytes(dir.path() / "depth/small.png", test::encode_grey_png(2, 2, 16, px));
  write_bytes(dir.path() / "depth.txt", list);
  FrameSourceParams params;
  params.intrinsics = CameraIntrinsics{.fx = 5, .fy = 5, .cx = 1.5, .cy = 1};
  g = open_frame_source(dir.path().string(), params);
  ASSERT_TRUE(g) << g.error().format();
  Result<std::optional<Frame>> f = (*g)->next();
  ASSERT_FALSE(f);
  EXPECT_NE(f.error().format().find("frame 0 (" + (dir.path() / "depth/eight.png").string()),
            std::string::npos)
      << f.error().format();
  EXPECT_NE(f.error().message.find("8-bit"), std::string::npos);
  f = (*g)->next();
  ASSERT_TRUE(f) << f.error().format();
  EXPECT_EQ((*f)->width, 4);
  f = (*g)->next();
  ASSERT_FALSE(f);
  EXPECT_NE(f.error().message.find("is 2x2 but the sequence's first is 4x3"), std::string::npos)
      << f.error().format();

  // Intrinsics whose principal point lies outside the image, and a bad scale.
  params.intrinsics->cx = 40;
  g = open_frame_source(dir.path().string(), params);
  ASSERT_TRUE(g);
  (void)(*g)->next();
  f = (*g)->next();
  ASSERT_FALSE(f);
  EXPECT_NE(f.error().message.find("principal point 40,1 lies outside the 4x3 image"),
            std::string::npos)
      << f.error().format();
  params.depth_scale = 0;
  EXPECT_FALSE(open_frame_source(dir.path().string(), params));
  EXPECT_FALSE(open_tum_sequence(dir.path() / "nothing_here"));
}

TEST(DepthPngDirectory, PairsDepthAndColourByNameInNaturalOrder) {
  TempDir dir("pngdir");
  const std::vector<std::uint16_t> px(4 * 3, 800);
  for (int i : {10, 2, 1}) {
    const std::string n = "learn" + std::to_string(i);
    write_bytes(dir.path() / (n + "_depth.png"), test::encode_grey_png(4, 3, 16, px));
    const std::uint8_t rgb[36] = {static_cast<std::uint8_t>(i)};
    ASSERT_TRUE(write_png_file(dir.path() / (n + "_color.png"), 4, 3, 3, rgb));
    write_bytes(dir.path() / (n + "_label.png"), test::encode_grey_png(4, 3, 8, px));
  }
  FrameSourceParams params;
  params.intrinsics = CameraIntrinsics{.fx = 5, .fy = 5, .cx = 1.5, .cy = 1};
  auto g = open_frame_source(dir.path().string(), params);
  ASSERT_TRUE(g) << g.error().format();
  EXPECT_EQ((*g)->frame_count(), 3);  // the label images are not frames
  EXPECT_NE((*g)->describe().find("3 with colour"), std::string::npos) << (*g)->describe();
  for (int want : {1, 2, 10}) {
    Result<std::optional<Frame>> f = (*g)->next();
    ASSERT_TRUE(f) << f.error().format();
    EXPECT_EQ((**f).points[0].r, want);
    EXPECT_FLOAT_EQ((**f).points[0].z, 0.8f);
  }
  // Without "depth" in any name every PNG is a depth frame; a single PNG is a source.
  TempDir plain("pngplain");
  write_bytes(plain.path() / "a.png", test::encode_grey_png(4, 3, 16, px));
  write_bytes(plain.path() / "b.png", test::encode_grey_png(4, 3, 16, px));
  g = open_frame_source(plain.path().string(), params);
  ASSERT_TRUE(g) << g.error().format();
  EXPECT_EQ((*g)->frame_count(), 2);
  g = open_frame_source((plain.path() / "a.png").string(), params);
  ASSERT_TRUE(g) << g.error().format();
  EXPECT_EQ((*g)->frame_count(), 1);
}

TEST(IntrinsicsForImage, DefaultsToTheKinectAndChecksThePrincipalPoint) {
  Result<CameraIntrinsics> k = intrinsics_for_image(std::nullopt, 640, 480, "x");
  ASSERT_TRUE(k);
  EXPECT_DOUBLE_EQ(k->fx, 525);
  EXPECT_DOUBLE_EQ(k->cy, 239.5);
  k = intrinsics_for_image(std::nullopt, 320, 240, "x");  // the same field of view
  ASSERT_TRUE(k);
  EXPECT_DOUBLE_EQ(k->fx, 262.5);
  EXPECT_DOUBLE_EQ(k->cx, 159.5);
  EXPECT_FALSE(intrinsics_for_image(CameraIntrinsics{.cx = -1}, 640, 480, "x"));
  EXPECT_FALSE(intrinsics_for_image(CameraIntrinsics{.fx = 0}, 640, 480, "x"));
}

TEST(DepthPngCli, RunAnnexesATumSequence) {
  TempDir dir("cli_run");
  const SyntheticScene scene = test_scene();
  write_tum_folder(dir.path() / "tum", scene, 3);
  HapticSpec spec;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    VirtualObject v;
    v.name = "v" + std::to_string(i);
    Primitive p = make_primitive(scene.objects[i].kind, "body");
    for (std::size_t d = 0; d < p.dimensions.size(); ++d)
      p.dimensions[d].value_m = scene.objects[i].dimensions_m[d];
    v.primitives.push_back(p);
    spec.objects.push_back(v);
  }
  ASSERT_TRUE(write_haptic_file(dir.path() / "spec.haptic", spec));
  const std::string base = "run " + (dir.path() / "spec.haptic").string() + " --source " +
                           (dir.path() / "tum").string() + " --out " +
                           (dir.path() / "out").string() + " --no-overlays";
  const test::CliRun run = test::run_cli(base);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("TUM RGB-D sequence"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("3 frames in"), std::string::npos) << run.output;
  for (const char* v : {"v0", "v1", "v2"})
    EXPECT_NE(run.output.find(std::string("frame 0 match ") + v + " "), std::string::npos)
        << run.output;

  const test::CliRun bad = test::run_cli(base + " --depth-scale 0");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("--depth-scale expects a positive number"), std::string::npos);
  const test::CliRun bad_k = test::run_cli(base + " --intrinsics 525,525,319.5");
  EXPECT_EQ(bad_k.exit_code, 2) << bad_k.output;
  EXPECT_NE(bad_k.output.find("--intrinsics: error:"), std::string::npos) << bad_k.output;
}

TEST(DepthPngCli, ScansAnOsdScene) {
  const fs::path osd = fs::path(ANNEX_SHARED_DIR) / "data" / "osd-learn";
  if (!fs::is_directory(osd))
    GTEST_SKIP() << "OSD learning set not found at " << osd.string()
                 << " (the ../shared data directory is not part of the repository)";
  const std::string depth = (osd / "learn0_depth.png").string();
  const test::CliRun scan =
      test::run_cli("scan " + depth + " --color " + (osd / "learn0_color.png").string() +
                    " --intrinsics 525,525,319.5,239.5 --depth-scale 1000");
  ASSERT_EQ(scan.exit_code, 0) << scan.output;
  // learn0: two boxes on the table, 0.6 to 1.2 m away.
  EXPECT_NE(scan.output.find("\nobject p1 box "), std::string::npos) << scan.output;
  EXPECT_NE(scan.output.find("\nobject p2 box "), std::string::npos) << scan.output;
  // The label image is 8-bit: refused as depth, naming it.
  const std::string label = (osd / "learn0_label.png").string();
  const test::CliRun eight = test::run_cli("scan " + label);
  EXPECT_EQ(eight.exit_code, 2);
  EXPECT_NE(eight.output.find(label + ": error: 8-bit image"), std::string::npos) << eight.output;
  // match scans a depth PNG as it scans a PCD: a cereal box finds the larger box.
  TempDir dir("cli_match");
  HapticSpec spec;
  VirtualObject v;
  v.name = "cereal";
  Primitive p = make_primitive(ShapeKind::box, "body");
  const double sizes[3] = {0.15, 0.06, 0.24};
  for (std::size_t d = 0; d < p.dimensions.size() && d < 3; ++d) p.dimensions[d].value_m = sizes[d];
  v.primitives.push_back(p);
  spec.objects.push_back(v);
  ASSERT_TRUE(write_haptic_file(dir.path() / "box.haptic", spec));
  const test::CliRun match =
      test::run_cli("match " + (dir.path() / "box.haptic").string() + " " + depth);
  EXPECT_EQ(match.exit_code, 0) << match.output;
  EXPECT_NE(match.output.find("match cereal p2 "), std::string::npos) << match.output;
  const test::CliRun pcd_color = test::run_cli(
      "scan " + test::source_path("samples/recordings/tabletop/frame_0000.pcd") + " --color x.png");
  EXPECT_EQ(pcd_color.exit_code, 2) << pcd_color.output;
}

}  // namespace
}  // namespace annex
