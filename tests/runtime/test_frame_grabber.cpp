// Frame sources: PCD reading/writing, directory and file grabbers, the OpenNI2
// failure paths (no sensor here) and the depth-to-cloud conversion.
#include "annex/runtime/frame_grabber.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

#include "annex/runtime/pcd_io.h"
#include "temp_dir.h"

// OpenNI2's own drivers (PS1080, PSLink) leak a few bytes while initializing; under
// ANNEX_SANITIZE LeakSanitizer would fail the OpenNI2 tests for it. This hook is how
// LSan takes built-in suppressions; it is inert in other builds.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libPS1080.so\nleak:libPSLink.so\nleak:libOniFile.so\nleak:libOpenNI2.so\n";
}

namespace annex {
namespace {

namespace fs = std::filesystem;

const fs::path kRealDir = fs::path(ANNEX_SHARED_DIR) / "data" / "real";

#define SKIP_WITHOUT_REAL_DATA()                                                         \
  if (!fs::is_directory(kRealDir))                                                       \
  GTEST_SKIP() << "real scans not found at " << kRealDir.string()                        \
               << " (the ../shared data directory is not part of the repository)"

using test::read_bytes;
using test::TempDir;
using test::write_bytes;

Frame small_frame(int w, int h, float z0) {
  Frame f;
  f.width = w;
  f.height = h;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      f.points.push_back({0.01f * u, 0.02f * v, z0 + 0.001f * (u + v),
                          static_cast<std::uint8_t>(u * 10), static_cast<std::uint8_t>(v * 20), 7});
  return f;
}

int finite_count(const Frame& f) {
  int n = 0;
  for (const auto& p : f.points) n += std::isfinite(p.z) ? 1 : 0;
  return n;
}

// ---- depth_to_frame ----

TEST(DepthToFrame, FrontoParallelPlaneBackProjectsThroughThePinholeModel) {
  const CameraIntrinsics k;
  DepthImage d{k.width, k.height, std::vector<std::uint16_t>(k.width * k.height, 1000)};
  const Result<Frame> f = depth_to_frame(d, nullptr, k);
  ASSERT_TRUE(f.ok()) << f.error().format();
  ASSERT_EQ(f->width, 640);
  ASSERT_EQ(f->height, 480);
  for (int v : {0, 100, 239, 479}) {
    for (int u : {0, 320, 639}) {
      const PointXYZRGB& p = f->points[v * 640 + u];
      EXPECT_FLOAT_EQ(p.z, 1.0f);
      EXPECT_NEAR(p.x, (u - 319.5) / 525.0, 1e-6);
      EXPECT_NEAR(p.y, (v - 239.5) / 525.0, 1e-6);
      EXPECT_EQ(p.r, 128);  // no colour: grey
    }
  }
}

// The frame keeps the camera its pixels went through: the scanner's pixel-size rules
// count with it (frame.h, grid_intrinsics).
TEST(DepthToFrame, TheFrameCarriesTheIntrinsicsItWasBackProjectedWith) {
  const CameraIntrinsics k{320, 240, 291.3, 290.8, 157.25, 121.5};
  DepthImage d{k.width, k.height, std::vector<std::uint16_t>(k.width * k.height, 1500)};
  const Result<Frame> f = depth_to_frame(d, nullptr, k);
  ASSERT_TRUE(f.ok()) << f.error().format();
  EXPECT_EQ(f->intrinsics.width, 320);
  EXPECT_EQ(f->intrinsics.height, 240);
  EXPECT_DOUBLE_EQ(f->intrinsics.fx, 291.3);
  EXPECT_DOUBLE_EQ(f->intrinsics.fy, 290.8);
  EXPECT_DOUBLE_EQ(f->intrinsics.cx, 157.25);
  EXPECT_DOUBLE_EQ(f->intrinsics.cy, 121.5);
  EXPECT_DOUBLE_EQ(focal_px(*f), 291.3);
}

// A frame whose source set no intrinsics has the Kinect's, scaled to its grid with the
// pixel centres kept (pixel u of a half-size grid spans the full grid's 2u and 2u + 1).
TEST(GridIntrinsics, DefaultsScaleToTheFramesResolution) {
  Frame f;
  f.width = 640;
  f.height = 480;
  EXPECT_DOUBLE_EQ(grid_intrinsics(f).fx, 525.0);
  EXPECT_DOUBLE_EQ(grid_intrinsics(f).cx, 319.5);
  f.width = 320;
  f.height = 240;
  const CameraIntrinsics half = grid_intrinsics(f);
  EXPECT_EQ(half.width, 320);
  EXPECT_EQ(half.height, 240);
  EXPECT_DOUBLE_EQ(half.fx, 262.5);
  EXPECT_DOUBLE_EQ(half.fy, 262.5);
  EXPECT_DOUBLE_EQ(half.cx, 159.5);
  EXPECT_DOUBLE_EQ(half.cy, 119.5);
  EXPECT_DOUBLE_EQ(focal_px(f), 262.5);
  f.intrinsics = {320, 240, 300, 301, 160, 120};  // carried at the grid's size: as is
  EXPECT_DOUBLE_EQ(grid_intrinsics(f).fx, 300);
  EXPECT_DOUBLE_EQ(grid_intrinsics(f).cy, 120);
}

TEST(DepthToFrame, TiltedPlaneAndSphereComeBackOnTheirSurfaces) {
  // Depth of each pixel's ray against a sphere (centre (0.1, -0.05, 1.5), r 0.25) in
  // front of a tilted plane z = 2 + 0.5 y, rounded to millimetres as a sensor does.
  const CameraIntrinsics k;
  DepthImage d{k.width, k.height, std::vector<std::uint16_t>(k.width * k.height, 0)};
  const double cx = 0.1, cy = -0.05, cz = 1.5, r = 0.25;
  std::vector<int> kind(d.depth_mm.size(), 0);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const double rx = (u - k.cx) / k.fx, ry = (v - k.cy) / k.fy;  // ray (rx, ry, 1)
      const double a = rx * rx + ry * ry + 1, b = -(rx * cx + ry * cy + cz);
      const double c = cx * cx + cy * cy + cz * cz - r * r;
      const double disc = b * b - a * c;
      double z = 0;
      int what = 0;
      if (disc >= 0) {
        z = (-b - std::sqrt(disc)) / a;
        what = 1;
      } else if (u < 600) {  // leave a strip with no depth
        z = 2.0 / (1 - 0.5 * ry);
        what = 2;
      }
      d.depth_mm[v * k.width + u] = static_cast<std::uint16_t>(std::lround(z * 1000));
      kind[v * k.width + u] = what;
    }
  }
  const Result<Frame> f = depth_to_frame(d, nullptr, k);
  ASSERT_TRUE(f.ok()) << f.error().format();
  int sphere = 0, plane = 0, empty = 0;
  for (std::size_t i = 0; i < f->points.size(); ++i) {
    const PointXYZRGB& p = f->points[i];
    if (kind[i] == 0) {
      EXPECT_TRUE(std::isnan(p.x) && std::isnan(p.y) && std::isnan(p.z));
      ++empty;
    } else if (kind[i] == 1) {
      const double dist = std::sqrt((p.x - cx) * (p.x - cx) + (p.y - cy) * (p.y - cy) +
                                    (p.z - cz) * (p.z - cz));
      // 0.5 mm rounding along a ray; grazing pixels see it magnified.
      if (std::abs(dist - r) > 0.0006) ADD_FAILURE() << "sphere point off by " << dist - r;
      ++sphere;
    } else {
      EXPECT_NEAR(p.z - 0.5 * p.y, 2.0, 0.0007);
      ++plane;
    }
  }
  EXPECT_GT(sphere, 10000);
  EXPECT_GT(plane, 100000);
  EXPECT_EQ(empty, 40 * 480 - 0);  // the strip u >= 600 (the sphere is far from it)
}

TEST(DepthToFrame, CopiesRegisteredColourAndSamplesOtherResolutions) {
  CameraIntrinsics k;
  k.width = 4;
  k.height = 2;
  k.cx = 1.5;
  k.cy = 0.5;
  DepthImage d{4, 2, {500, 0, 700, 800, 900, 1000, 1100, 1200}};
  ColorImage same{4, 2, {}};
  for (int i = 0; i < 8; ++i) same.rgb.insert(same.rgb.end(), {std::uint8_t(i), std::uint8_t(10 + i), std::uint8_t(20 + i)});
  Result<Frame> f = depth_to_frame(d, &same, k);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->points[5].r, 5);
  EXPECT_EQ(f->points[5].g, 15);
  EXPECT_EQ(f->points[5].b, 25);
  EXPECT_TRUE(std::isnan(f->points[1].z));
  EXPECT_EQ(f->points[1].r, 1);  // colour is kept even where depth is missing

  ColorImage half{2, 1, {1, 2, 3, 4, 5, 6}};
  f = depth_to_frame(d, &half, k);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->points[0].r, 1);
  EXPECT_EQ(f->points[3].r, 4);
  EXPECT_EQ(f->points[7].r, 4);
}

TEST(DepthToFrame, RejectsMismatchedSizesAndShortBuffers) {
  const CameraIntrinsics k;
  DepthImage wrong{320, 240, std::vector<std::uint16_t>(320 * 240, 1000)};
  Result<Frame> f = depth_to_frame(wrong, nullptr, k);
  ASSERT_FALSE(f.ok());
  EXPECT_NE(f.error().message.find("320x240"), std::string::npos) << f.error().message;

  DepthImage short_buffer{640, 480, std::vector<std::uint16_t>(100, 1000)};
  EXPECT_FALSE(depth_to_frame(short_buffer, nullptr, k).ok());

  DepthImage ok{640, 480, std::vector<std::uint16_t>(640 * 480, 1000)};
  ColorImage short_colour{640, 480, std::vector<std::uint8_t>(10, 0)};
  EXPECT_FALSE(depth_to_frame(ok, &short_colour, k).ok());
}

// ---- timestamps from names ----

TEST(FrameNames, TimestampsParseFromPclGrabberNames) {
  const auto t0 = timestamp_from_frame_name("frame_20121214T142255.814212.pcd");
  const auto t1 = timestamp_from_frame_name("frame_20121214T142256.068683.pcd");
  ASSERT_TRUE(t0 && t1);
  EXPECT_NEAR(*t0, 1355494975.814212, 1e-5);
  EXPECT_NEAR(*t1 - *t0, 0.254471, 1e-5);
  EXPECT_TRUE(timestamp_from_frame_name("cloud_20000101T000000.pcd").has_value());
  EXPECT_FALSE(timestamp_from_frame_name("scene_0001.pcd").has_value());
  EXPECT_FALSE(timestamp_from_frame_name("T142255.pcd").has_value());
  EXPECT_FALSE(timestamp_from_frame_name("frame_20121314T142255.pcd").has_value());  // month 13
}

// ---- PCD reading and writing ----

TEST(Pcd, WriteThenReadRoundTripsAnOrganizedFrameWithNaN) {
  TempDir dir("roundtrip");
  Frame f = small_frame(5, 4, 1.0f);
  f.points[3].x = f.points[3].y = f.points[3].z = std::numeric_limits<float>::quiet_NaN();
  ASSERT_TRUE(write_pcd(dir.path() / "a.pcd", f).ok());
  const Result<Frame> back = read_pcd(dir.path() / "a.pcd");
  ASSERT_TRUE(back.ok()) << back.error().format();
  EXPECT_EQ(back->width, 5);
  EXPECT_EQ(back->height, 4);
  EXPECT_TRUE(back->organized());
  ASSERT_EQ(back->points.size(), f.points.size());
  for (std::size_t i = 0; i < f.points.size(); ++i) {
    if (i == 3) {
      EXPECT_TRUE(std::isnan(back->points[i].z));
      continue;
    }
    EXPECT_EQ(back->points[i].x, f.points[i].x);
    EXPECT_EQ(back->points[i].z, f.points[i].z);
    EXPECT_EQ(back->points[i].r, f.points[i].r);
    EXPECT_EQ(back->points[i].g, f.points[i].g);
    EXPECT_EQ(back->points[i].b, f.points[i].b);
  }
  // The header is the real scans' layout.
  EXPECT_NE(read_bytes(dir.path() / "a.pcd").find("\nFIELDS x y z rgba\nSIZE 4 4 4 4\nTYPE F F F U\n"),
            std::string::npos);
}

TEST(Pcd, RejectsAFrameWhoseSizeDisagreesWithItsPoints) {
  TempDir dir("badsize");
  Frame f = small_frame(5, 4, 1.0f);
  f.points.pop_back();
  EXPECT_FALSE(write_pcd(dir.path() / "a.pcd", f).ok());
}

TEST(Pcd, ReadsAsciiXyzOnlyAsGreyAndPackedRgbAsColour) {
  TempDir dir("ascii");
  write_bytes(dir.path() / "xyz.pcd",
              "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\n"
              "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n0 0 1\n0.1 0 1\nnan nan nan\n");
  Result<Frame> f = read_pcd(dir.path() / "xyz.pcd");
  ASSERT_TRUE(f.ok()) << f.error().format();
  EXPECT_EQ(f->height, 1);  // unorganized
  EXPECT_FALSE(f->organized());
  EXPECT_EQ(f->points.size(), 3u);
  EXPECT_EQ(f->points[1].r, 128);
  EXPECT_FLOAT_EQ(f->points[1].x, 0.1f);
  EXPECT_TRUE(std::isnan(f->points[2].x));

  // rgb as a packed float: 0x00ff8040 is r = 255, g = 128, b = 64.
  float packed;
  const std::uint32_t bits = 0x00ff8040u;
  std::memcpy(&packed, &bits, 4);
  char number[64];
  std::snprintf(number, sizeof number, "%.9g", static_cast<double>(packed));
  write_bytes(
      dir.path() / "rgb.pcd",
      std::string("VERSION .7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
                  "WIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n0 0 1 ") +
          number + "\n");
  f = read_pcd(dir.path() / "rgb.pcd");
  ASSERT_TRUE(f.ok()) << f.error().format();
  EXPECT_EQ(f->points[0].r, 255);
  EXPECT_EQ(f->points[0].g, 128);
  EXPECT_EQ(f->points[0].b, 64);
}

TEST(PcdHeader, ParsesTheRealScansLayout) {
  const std::string text =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z rgba\n"
      "SIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 640\nHEIGHT 480\n"
      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 307200\nDATA binary_compressed\n\x01\x02";
  const Result<PcdHeader> h = parse_pcd_header(text, "t.pcd");
  ASSERT_TRUE(h.ok()) << h.error().format();
  EXPECT_EQ(h->fields, (std::vector<std::string>{"x", "y", "z", "rgba"}));
  EXPECT_EQ(h->width, 640u);
  EXPECT_EQ(h->height, 480u);
  EXPECT_EQ(h->points, 307200u);
  EXPECT_EQ(h->point_step, 16u);
  EXPECT_EQ(h->data, PcdHeader::Data::binary_compressed);
  EXPECT_EQ(h->data_offset, text.size() - 2);
}

TEST(PcdHeader, ErrorsCarryLineAndColumn) {
  struct Case {
    const char* text;
    int line, column;
    const char* message_part;
  };
  const Case cases[] = {
      {"FIELDS x y z\nSIZE 4 4\n", 2, 1, "SIZE lists 2 values for 3 fields"},
      {"FIELDS x y z\nSIZE 4 4 3\n", 2, 10, "SIZE must be 1, 2, 4 or 8"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F Q\n", 3, 10, "TYPE must be I, U or F"},
      {"FIELDS x\nSIZE 4\nTYPE F\nWIDTH -3\n", 4, 7, "expected a whole number"},
      {"FIELDS x\nSIZE 2\nTYPE F\nWIDTH 1\nDATA ascii\n", 5, 1, "TYPE F but SIZE 2"},
      {"FIELDS x\nSIZE 4\nTYPE F\nWIDTH 2\nPOINTS 3\nDATA ascii\n", 6, 1, "POINTS 3 is not"},
      {"FIELDS x\nSIZE 4\nTYPE F\nWIDTH 2\nDATA zip\n", 5, 6, "DATA must be"},
      {"hello world\n", 1, 1, "unexpected 'hello'"},
      {"FIELDS x\nSIZE 4\n", 3, 1, "ends before its DATA line"},
      {"FIELDS x\nSIZE 4", 2, 1, "ends before its DATA line"},
      // Found by fuzz_pcd: a second FIELDS line once outgrew SIZE and TYPE.
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nFIELDS a b c\n", 4, 1, "FIELDS given twice"},
      {"FIELDS x\nSIZE 4\nTYPE F\nSIZE 4\n", 4, 1, "SIZE given twice"},
  };
  for (const Case& c : cases) {
    const Result<PcdHeader> h = parse_pcd_header(c.text, "t.pcd");
    ASSERT_FALSE(h.ok()) << c.text;
    EXPECT_EQ(h.error().location.origin, "t.pcd");
    EXPECT_EQ(h.error().location.line, c.line) << c.text << " -> " << h.error().format();
    EXPECT_EQ(h.error().location.column, c.column) << c.text << " -> " << h.error().format();
    EXPECT_NE(h.error().message.find(c.message_part), std::string::npos) << h.error().format();
  }
}

TEST(Pcd, ErrorsNameTheFileAndTheProblem) {
  TempDir dir("errors");
  const fs::path missing = dir.path() / "missing.pcd";
  Result<Frame> f = read_pcd(missing);
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.error().location.origin, missing.string());
  EXPECT_NE(f.error().message.find("no such file"), std::string::npos);

  EXPECT_FALSE(read_pcd(dir.path()).ok());

  write_bytes(dir.path() / "garbage.pcd", "this is not a point cloud\n\x01\x02\x03");
  f = read_pcd(dir.path() / "garbage.pcd");
  ASSERT_FALSE(f.ok());
  EXPECT_NE(f.error().format().find("garbage.pcd"), std::string::npos) << f.error().format();

  write_bytes(dir.path() / "empty.pcd", "");
  EXPECT_FALSE(read_pcd(dir.path() / "empty.pcd").ok());

  write_bytes(dir.path() / "noxyz.pcd",
              "VERSION .7\nFIELDS a b c\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\n"
              "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2 3\n");
  f = read_pcd(dir.path() / "noxyz.pcd");
  ASSERT_FALSE(f.ok());
  EXPECT_NE(f.error().message.find("missing field 'x'"), std::string::npos) << f.error().message;

  write_bytes(dir.path() / "nan.pcd",
              "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
              "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\nnan nan nan\nnan nan nan\n");
  f = read_pcd(dir.path() / "nan.pcd");
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.error().message, "all points are NaN");

  write_bytes(dir.path() / "zero.pcd",
              "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 0\nHEIGHT 0\n"
              "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 0\nDATA ascii\n");
  EXPECT_FALSE(read_pcd(dir.path() / "zero.pcd").ok());
}

TEST(Pcd, TruncatedAndCorruptedBinaryFilesFailCleanly) {
  TempDir dir("truncated");
  // Our own binary writer's output, cut at many lengths and with flipped bytes.
  Frame f = small_frame(40, 30, 1.0f);
  const std::string bytes = pcd_bytes(f);
  const std::size_t header = bytes.find("DATA binary\n") + 12;
  for (std::size_t cut : {std::size_t{0}, std::size_t{10}, header - 3, header, header + 1,
                          header + 100, bytes.size() - 1}) {
    write_bytes(dir.path() / "cut.pcd", bytes.substr(0, cut));
    const Result<Frame> r = read_pcd(dir.path() / "cut.pcd");
    EXPECT_FALSE(r.ok()) << "cut at " << cut;
  }
  std::string lying = bytes;
  lying.replace(lying.find("POINTS 1200"), 11, "POINTS 9999");
  write_bytes(dir.path() / "lying.pcd", lying);
  EXPECT_FALSE(read_pcd(dir.path() / "lying.pcd").ok());
}

TEST(Pcd, TruncatedCompressedRealScanFailsCleanly) {
  SKIP_WITHOUT_REAL_DATA();
  TempDir dir("compressed");
  const std::string bytes = read_bytes(kRealDir / "milk_cartoon_all_small_clorox.pcd");
  const std::size_t header = bytes.find("DATA binary_compressed\n") + 23;
  ASSERT_GT(header, 23u);
  std::uint32_t compressed = 0;
  std::memcpy(&compressed, bytes.data() + header, 4);
  ASSERT_LE(header + 8 + compressed, bytes.size());
  for (std::size_t cut : {header, header + 4, header + 8, header + 1000, bytes.size() / 2,
                          header + 8 + compressed - 1}) {
    write_bytes(dir.path() / "cut.pcd", bytes.substr(0, cut));
    const Result<Frame> r = read_pcd(dir.path() / "cut.pcd");
    EXPECT_FALSE(r.ok()) << "cut at " << cut;
  }
  // Corrupt compressed sizes: an absurd uncompressed size, then garbage in the stream.
  std::string corrupt = bytes;
  for (int i = 4; i < 8; ++i) corrupt[header + i] = '\x7f';
  write_bytes(dir.path() / "sizes.pcd", corrupt);
  EXPECT_FALSE(read_pcd(dir.path() / "sizes.pcd").ok());
  corrupt = bytes;
  for (std::size_t i = header + 8; i < header + 4000; i += 7) corrupt[i] = static_cast<char>(i * 31);
  write_bytes(dir.path() / "stream.pcd", corrupt);
  const Result<Frame> r = read_pcd(dir.path() / "stream.pcd");  // may decode to noise; must not crash
  if (!r.ok()) {
    EXPECT_FALSE(r.error().message.empty());
  }
}

TEST(Pcd, ReadsTheRealScans) {
  SKIP_WITHOUT_REAL_DATA();
  for (const char* name : {"milk_cartoon_all_small_clorox.pcd", "frame_20121214T142255.814212.pcd",
                           "office1.pcd"}) {
    const Result<Frame> f = read_pcd(kRealDir / name);
    ASSERT_TRUE(f.ok()) << f.error().format();
    EXPECT_EQ(f->width, 640) << name;
    EXPECT_EQ(f->height, 480) << name;
    EXPECT_GT(finite_count(*f), 100000) << name;
    // Colour came through: not every point is the same grey.
    int coloured = 0;
    for (const auto& p : f->points) coloured += (p.r != p.g || p.g != p.b) ? 1 : 0;
    EXPECT_GT(coloured, 10000) << name;
    // A Kinect frame at about a metre: the median depth is plausible.
    std::vector<float> z;
    for (const auto& p : f->points)
      if (std::isfinite(p.z)) z.push_back(p.z);
    std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
    EXPECT_GT(z[z.size() / 2], 0.5f) << name;
    EXPECT_LT(z[z.size() / 2], 5.0f) << name;
  }
  const Result<Frame> milk = read_pcd(kRealDir / "milk.pcd");  // unorganized, x y z only
  ASSERT_TRUE(milk.ok()) << milk.error().format();
  EXPECT_EQ(milk->width, 13704);
  EXPECT_EQ(milk->height, 1);
  EXPECT_EQ(finite_count(*milk), 13704);
}

// ---- grabbers ----

TEST(FrameGrabber, SinglePcdFileGivesOneFrameThenTheEnd) {
  TempDir dir("single");
  ASSERT_TRUE(write_pcd(dir.path() / "one.pcd", small_frame(4, 3, 1.0f)).ok());
  auto g = open_frame_source((dir.path() / "one.pcd").string());
  ASSERT_TRUE(g.ok()) << g.error().format();
  EXPECT_EQ((*g)->frame_count(), 1);
  EXPECT_NE((*g)->describe().find("one.pcd"), std::string::npos);
  auto f = (*g)->next();
  ASSERT_TRUE(f.ok());
  ASSERT_TRUE(f->has_value());
  EXPECT_EQ((*f)->width, 4);
  auto end = (*g)->next();
  ASSERT_TRUE(end.ok());
  EXPECT_FALSE(end->has_value());
}

TEST(FrameGrabber, DirectoryDeliversFramesInNameOrderWithRecordedTimestamps) {
  TempDir dir("named");
  // Written out of order; a non-PCD file is ignored.
  ASSERT_TRUE(write_pcd(dir.path() / "frame_20121214T142256.068683.pcd", small_frame(2, 2, 2.0f)).ok());
  ASSERT_TRUE(write_pcd(dir.path() / "frame_20121214T142255.814212.pcd", small_frame(2, 2, 1.0f)).ok());
  ASSERT_TRUE(write_pcd(dir.path() / "frame_20121214T142256.332395.pcd", small_frame(2, 2, 3.0f)).ok());
  write_bytes(dir.path() / "notes.txt", "not a frame");
  auto g = open_frame_source(dir.path().string());
  ASSERT_TRUE(g.ok()) << g.error().format();
  EXPECT_EQ((*g)->frame_count(), 3);
  const double expected_t[] = {0.0, 0.254471, 0.518183};
  for (int i = 0; i < 3; ++i) {
    auto f = (*g)->next();
    ASSERT_TRUE(f.ok()) << f.error().format();
    ASSERT_TRUE(f->has_value());
    EXPECT_EQ((*f)->index, i);
    EXPECT_FLOAT_EQ((*f)->points[0].z, 1.0f + i);
    EXPECT_NEAR((*f)->timestamp_s, expected_t[i], 1e-5);
  }
  auto end = (*g)->next();
  ASSERT_TRUE(end.ok());
  EXPECT_FALSE(end->has_value());
}

TEST(FrameGrabber, DirectoryWithoutTimestampsRunsAtThirtyHertz) {
  TempDir dir("plain");
  for (int i = 0; i < 3; ++i)
    ASSERT_TRUE(write_pcd(dir.path() / ("scene_000" + std::to_string(i) + ".pcd"), small_frame(2, 2, 1.0f)).ok());
  FrameSourceParams params;
  params.pacing = Pacing::recorded_rate;  // sleeps about 67 ms in all; not timed here
  auto g = open_pcd_directory(dir.path(), params);
  ASSERT_TRUE(g.ok());
  EXPECT_NE((*g)->describe().find("30"), std::string::npos) << (*g)->describe();
  for (int i = 0; i < 3; ++i) {
    auto f = (*g)->next();
    ASSERT_TRUE(f.ok() && f->has_value());
    EXPECT_NEAR((*f)->timestamp_s, i / 30.0, 1e-9);
  }
}

TEST(FrameGrabber, ABadFrameInADirectoryIsAnErrorNamingFrameAndFile) {
  TempDir dir("badframe");
  ASSERT_TRUE(write_pcd(dir.path() / "a.pcd", small_frame(2, 2, 1.0f)).ok());
  write_bytes(dir.path() / "b.pcd",
              "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\n"
              "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\nnan nan nan\n");
  ASSERT_TRUE(write_pcd(dir.path() / "c.pcd", small_frame(2, 2, 3.0f)).ok());
  auto g = open_frame_source(dir.path().string());
  ASSERT_TRUE(g.ok());
  ASSERT_TRUE((*g)->next().ok());
  auto bad = (*g)->next();
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().format(),
            "frame 1 (" + (dir.path() / "b.pcd").string() + "): error: all points are NaN");
  auto after = (*g)->next();  // the source moves on
  ASSERT_TRUE(after.ok());
  ASSERT_TRUE(after->has_value());
  EXPECT_EQ((*after)->index, 2);
}

TEST(FrameGrabber, RealSequenceDirectory) {
  SKIP_WITHOUT_REAL_DATA();
  TempDir dir("realseq");
  for (const char* name : {"frame_20121214T142255.814212.pcd", "frame_20121214T142256.068683.pcd",
                           "frame_20121214T142256.332395.pcd"})
    fs::create_symlink(kRealDir / name, dir.path() / name);
  auto g = open_frame_source(dir.path().string());
  ASSERT_TRUE(g.ok()) << g.error().format();
  int frames = 0;
  double last_t = -1;
  while (true) {
    auto f = (*g)->next();
    ASSERT_TRUE(f.ok()) << f.error().format();
    if (!f->has_value()) break;
    EXPECT_GT((*f)->timestamp_s, last_t);
    last_t = (*f)->timestamp_s;
    EXPECT_EQ((*f)->width, 640);
    ++frames;
  }
  EXPECT_EQ(frames, 3);
  EXPECT_NEAR(last_t, 0.518183, 1e-5);
}

TEST(FrameGrabber, FactoryRejectsBadSpecsClearly) {
  TempDir dir("specs");
  auto r = open_frame_source("");
  EXPECT_FALSE(r.ok());
  r = open_frame_source((dir.path() / "nothing.pcd").string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().format().find("nothing.pcd"), std::string::npos);
  r = open_frame_source((dir.path() / "nothing_at_all").string());
  EXPECT_FALSE(r.ok());
  write_bytes(dir.path() / "x.txt", "hello");
  r = open_frame_source((dir.path() / "x.txt").string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("unknown frame source"), std::string::npos);
  r = open_frame_source(dir.path().string());  // a directory without frames
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("no .pcd files"), std::string::npos);
}

TEST(FrameGrabber, OpenNi2WithoutADeviceFailsWithAClearMessage) {
  auto r = open_frame_source("openni2");
  if (r.ok()) GTEST_SKIP() << "an OpenNI2 device is attached: " << (*r)->describe();
  EXPECT_NE(r.error().message.find("no OpenNI2 device found"), std::string::npos)
      << r.error().format();
  r = open_frame_source("openni2:no-such-device-uri");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("no OpenNI2 device found"), std::string::npos)
      << r.error().format();
}

TEST(FrameGrabber, OniRecordingsThatCannotBeOpenedFailWithAClearMessage) {
  TempDir dir("oni");
  const fs::path missing = dir.path() / "x.oni";
  auto r = open_frame_source(missing.string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("cannot open '" + missing.string() + "'"), std::string::npos)
      << r.error().format();
  write_bytes(dir.path() / "garbage.oni", "not a recording");
  r = open_frame_source((dir.path() / "garbage.oni").string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("cannot open '"), std::string::npos) << r.error().format();
}

}  // namespace
}  // namespace annex
