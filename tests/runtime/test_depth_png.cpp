// Depth and colour PNG reading: 16-bit depth written here by a minimal encoder that
// follows the PNG specification directly (zlib for the IDAT stream), so the reader
// is checked against files it did not write; the OSD learning set when present.
#include "annex/runtime/depth_png.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "annex/formats/png_io.h"
#include "png_test_encoder.h"
#include "temp_dir.h"

namespace annex {
namespace {

namespace fs = std::filesystem;
using test::encode_grey_png;

class DepthPngTest : public ::testing::Test {
 protected:
  fs::path write(const std::string& name, const std::string& bytes) {
    fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  const test::TempDir tmp_{"depth_png"};
  const fs::path dir_ = tmp_.path();
};

TEST_F(DepthPngTest, ReadsSixteenBitDepthWithScale) {
  std::vector<std::uint16_t> px = {0, 1000, 5000, 65535, 2500, 7};
  fs::path p = write("d.png", encode_grey_png(3, 2, 16, px));
  Result<DepthImage> mm = read_depth_png(p);
  ASSERT_TRUE(mm) << mm.error().format();
  EXPECT_EQ(mm->width, 3);
  EXPECT_EQ(mm->height, 2);
  EXPECT_EQ(mm->depth_mm, px);
  // TUM's scale: 5000 units per metre, so 5000 is 1000 mm.
  Result<DepthImage> tum = read_depth_png(p, DepthPngParams{.depth_scale = 5000});
  ASSERT_TRUE(tum);
  EXPECT_EQ(tum->depth_mm[2], 1000);
  EXPECT_EQ(tum->depth_mm[4], 500);
  // A scale of 100 (centimetres) puts 65535 beyond 16-bit millimetres: no measurement.
  Result<DepthImage> cm = read_depth_png(p, DepthPngParams{.depth_scale = 100});
  ASSERT_TRUE(cm);
  EXPECT_EQ(cm->depth_mm[1], 10000);
  EXPECT_EQ(cm->depth_mm[3], 0);
}

TEST_F(DepthPngTest, FrameBackProjectsThroughIntrinsics) {
  std::vector<std::uint16_t> px(4 * 3, 0);
  px[1 * 4 + 2] = 2000;
  fs::path p = write("d.png", encode_grey_png(4, 3, 16, px));
  Result<CameraIntrinsics> k = parse_intrinsics("100,200,1.5,1", 4, 3, "--intrinsics");
  ASSERT_TRUE(k) << k.error().format();
  Result<Frame> f = read_depth_frame(p, std::nullopt, *k);
  ASSERT_TRUE(f) << f.error().format();
  const PointXYZRGB& q = f->points[1 * 4 + 2];
  EXPECT_FLOAT_EQ(q.z, 2.0f);
  EXPECT_FLOAT_EQ(q.x, (2 - 1.5f) * 2.0f / 100);
  EXPECT_FLOAT_EQ(q.y, 0.0f);
  EXPECT_TRUE(std::isnan(f->points[0].z));
}

TEST_F(DepthPngTest, ColourIsPairedPixelForPixel) {
  std::vector<std::uint16_t> px(2 * 2, 1000);
  fs::path d = write("d.png", encode_grey_png(2, 2, 16, px));
  const std::uint8_t rgb[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 9, 9, 9};
  fs::path c = dir_ / "c.png";
  ASSERT_TRUE(write_png_file(c, 2, 2, 3, rgb));
  CameraIntrinsics k{.width = 2, .height = 2, .fx = 2, .fy = 2, .cx = 0.5, .cy = 0.5};
  Result<Frame> f = read_depth_frame(d, c, k);
  ASSERT_TRUE(f) << f.error().format();
  EXPECT_EQ(f->points[1].g, 255);
  EXPECT_EQ(f->points[2].b, 255);
}

TEST_F(DepthPngTest, ClearErrorsNameTheFile) {
  std::vector<std::uint16_t> px(4, 100);
  fs::path eight = write("eight.png", encode_grey_png(2, 2, 8, px));
  Result<DepthImage> e = read_depth_png(eight);
  ASSERT_FALSE(e);
  EXPECT_NE(e.error().message.find("8-bit"), std::string::npos);
  EXPECT_EQ(e.error().location.origin, eight.string());

  EXPECT_FALSE(read_depth_png(dir_ / "missing.png"));
  EXPECT_FALSE(read_depth_png(write("junk.png", "not a png at all")));
  fs::path ok = write("ok.png", encode_grey_png(2, 2, 16, px));
  EXPECT_FALSE(read_depth_png(ok, DepthPngParams{.depth_scale = 0}));
  EXPECT_FALSE(read_depth_png(ok, DepthPngParams{.depth_scale = NAN}));

  // A header that promises 100000 x 100000 pixels is refused before decoding.
  std::string huge = encode_grey_png(2, 2, 16, px);
  const char claim[8] = {0, 1, static_cast<char>(0x86), static_cast<char>(0xa0),
                         0, 1, static_cast<char>(0x86), static_cast<char>(0xa0)};
  huge.replace(16, 8, claim, 8);
  Result<DepthImage> h = read_depth_png(write("huge.png", huge));
  ASSERT_FALSE(h);
  EXPECT_NE(h.error().message.find("100000x100000"), std::string::npos) << h.error().message;

  // Colour and depth of different shapes.
  const std::uint8_t rgb[9] = {};
  fs::path c = dir_ / "c.png";
  ASSERT_TRUE(write_png_file(c, 3, 1, 3, rgb));
  CameraIntrinsics k{.width = 2, .height = 2};
  Result<Frame> f = read_depth_frame(ok, c, k);
  ASSERT_FALSE(f);
  EXPECT_EQ(f.error().location.origin, c.string());
  // Intrinsics for another size.
  Result<Frame> g = read_depth_frame(ok, std::nullopt, CameraIntrinsics{});
  ASSERT_FALSE(g);
  EXPECT_EQ(g.error().location.origin, ok.string());
}

// Found by fuzz_depth_png: stb_image copied from a null buffer for an empty IDAT
// chunk (legal PNG). It is left out now; a chunk longer than the file is an error.
TEST_F(DepthPngTest, EmptyIdatChunksAndTruncatedChunks) {
  std::vector<std::uint16_t> px = {1000, 2000, 3000, 4000};
  std::string png = encode_grey_png(2, 2, 16, px);
  std::string empty_idat;
  test::put_chunk(empty_idat, "IDAT", "");
  std::string with_empty = png;
  with_empty.insert(8 + 25, empty_idat);  // after the 25-byte IHDR chunk
  Result<DepthImage> d = read_depth_png(write("empty_idat.png", with_empty));
  ASSERT_TRUE(d) << d.error().format();
  EXPECT_EQ(d->depth_mm, px);

  std::string cut = png.substr(0, png.size() - 20);
  const fs::path p = write("cut.png", cut);
  Result<DepthImage> t = read_depth_png(p);
  ASSERT_FALSE(t);
  EXPECT_EQ(t.error().location.origin, p.string());
  EXPECT_NE(t.error().message.find("truncated PNG: chunk 'IDAT' claims"), std::string::npos)
      << t.error().message;
}

TEST(ParseIntrinsics, RejectsMalformedLists) {
  EXPECT_FALSE(parse_intrinsics("525,525,319.5", 640, 480, "--intrinsics"));
  EXPECT_FALSE(parse_intrinsics("525,525,319.5,x", 640, 480, "--intrinsics"));
  EXPECT_FALSE(parse_intrinsics("0,525,319.5,239.5", 640, 480, "--intrinsics"));
  EXPECT_FALSE(parse_intrinsics("525,,319.5,239.5", 640, 480, "--intrinsics"));
  Result<CameraIntrinsics> k = parse_intrinsics("525,526,319.5,239.5", 640, 480, "--intrinsics");
  ASSERT_TRUE(k);
  EXPECT_DOUBLE_EQ(k->fy, 526);
}

// The OSD learning set's depth: every labelled pixel has a depth.
TEST(DepthPngReal, OsdLearnSceneHasDepthWhereLabelled) {
  const fs::path dir = fs::path(ANNEX_SHARED_DIR) / "data" / "osd-learn";
  if (!fs::is_directory(dir))
    GTEST_SKIP() << "OSD learning set not found at " << dir.string()
                 << " (the ../shared data directory is not part of the repository)";
  Result<Frame> f = read_depth_frame(dir / "learn0_depth.png", dir / "learn0_color.png",
                                     CameraIntrinsics{});
  ASSERT_TRUE(f) << f.error().format();
  int valid = 0;
  for (const PointXYZRGB& p : f->points)
    if (std::isfinite(p.z)) {
      ++valid;
      EXPECT_GT(p.z, 0.3f);
      EXPECT_LT(p.z, 2.0f);
    }
  EXPECT_GT(valid, 50000);
}

}  // namespace
}  // namespace annex
