// Our PCD decoder against PCL's reader (the reference: both must read every real
// frame, in every PCD encoding PCL writes, bit for bit alike), and hostile headers
// whose promise the file cannot hold: refused before anything is allocated for it.
#include "annex/runtime/pcd_io.h"
#include "annex/reference/pcd_io_pcl_reference.h"
#include "temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace annex {
namespace {

namespace fs = std::filesystem;

const fs::path kRealDir = fs::path(ANNEX_SHARED_DIR) / "data" / "real";

class PcdIoTest : public ::testing::Test {
 protected:
  fs::path write(const std::string& name, const std::string& bytes) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  const test::TempDir tmp_{"pcd_io"};
  const fs::path dir_ = tmp_.path();
};

// Same size, and every point the same bits (NaN pixels are NaN in both).
void expect_identical(const Frame& a, const Frame& b, const std::string& what) {
  ASSERT_EQ(a.width, b.width) << what;
  ASSERT_EQ(a.height, b.height) << what;
  ASSERT_EQ(a.points.size(), b.points.size()) << what;
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const PointXYZRGB &p = a.points[i], &q = b.points[i];
    const bool same_xyz = std::memcmp(&p.x, &q.x, 12) == 0 ||
                          (std::isnan(p.x) && std::isnan(q.x) && std::isnan(p.y) &&
                           std::isnan(q.y) && std::isnan(p.z) && std::isnan(q.z));
    if (!same_xyz || p.r != q.r || p.g != q.g || p.b != q.b) ++differing;
  }
  EXPECT_EQ(differing, 0u) << what;
}

TEST_F(PcdIoTest, ReadsEveryRealFrameAsPclDoes) {
  if (!fs::is_directory(kRealDir))
    GTEST_SKIP() << "real scans not found at " << kRealDir.string()
                 << " (the ../shared data directory is not part of the repository)";
  int files = 0;
  for (const auto& entry : fs::directory_iterator(kRealDir)) {
    if (entry.path().extension() != ".pcd") continue;
    ++files;
    const Result<Frame> ours = read_pcd(entry.path());
    const Result<Frame> pcl = read_pcd_pcl(entry.path());
    ASSERT_TRUE(ours) << ours.error().format();
    ASSERT_TRUE(pcl) << pcl.error().format();
    expect_identical(*ours, *pcl, entry.path().filename().string());
  }
  EXPECT_GE(files, 6);
}

TEST_F(PcdIoTest, ReadsEveryEncodingPclWritesAsPclDoes) {
  if (!fs::is_directory(kRealDir))
    GTEST_SKIP() << "real scans not found at " << kRealDir.string();
  const Result<Frame> real = read_pcd(kRealDir / "milk_cartoon_all_small_clorox.pcd");
  ASSERT_TRUE(real) << real.error().format();
  const std::pair<PcdHeader::Data, const char*> encodings[] = {
      {PcdHeader::Data::ascii, "ascii"},
      {PcdHeader::Data::binary, "binary"},
      {PcdHeader::Data::binary_compressed, "binary_compressed"}};
  for (const auto& [data, name] : encodings) {
    const fs::path p = dir_ / (std::string(name) + ".pcd");
    ASSERT_TRUE(write_pcd_pcl(p, *real, data)) << name;
    const Result<Frame> ours = read_pcd(p);
    const Result<Frame> pcl = read_pcd_pcl(p);
    ASSERT_TRUE(ours) << ours.error().format();
    ASSERT_TRUE(pcl) << pcl.error().format();
    expect_identical(*ours, *pcl, name);
    // Colour and finite points survive every encoding.
    expect_identical(*ours, *real, std::string(name) + " vs the original");
  }
}

// The file: 151 bytes of ascii whose header claims 8192 x 8192 points.
std::string lying_ascii(const char* fields, const char* sizes, const char* types,
                        const char* counts) {
  return std::string("# .PCD v0.7\nVERSION 0.7\nFIELDS ") + fields + "\nSIZE " + sizes +
         "\nTYPE " + types + "\nCOUNT " + counts +
         "\nWIDTH 8192\nHEIGHT 8192\nPOINTS 67108864\nDATA ascii\n0 0 1\n0 0 1.5\n";
}

TEST_F(PcdIoTest, RefusesAHeaderPromisingMoreThanTheFileHolds) {
  const std::string text = lying_ascii("x y z", "4 4 4", "F F F", "1 1 1");
  const fs::path p = write("lying.pcd", text);
  const Result<Frame> f = read_pcd(p);
  ASSERT_FALSE(f);
  EXPECT_EQ(f.error().location.origin, p.string());
  EXPECT_NE(f.error().message.find("67108864 points"), std::string::npos) << f.error().message;
  EXPECT_NE(f.error().message.find("the file holds"), std::string::npos) << f.error().message;
  // The same from memory.
  EXPECT_FALSE(decode_pcd(text, "mem.pcd"));

  // Binary: 12 bytes a point.
  std::string binary =
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 8192\nHEIGHT 8192\nDATA binary\n";
  binary += std::string(24, '\0');
  Result<Frame> b = decode_pcd(binary, "bin.pcd");
  ASSERT_FALSE(b);
  EXPECT_NE(b.error().message.find("truncated"), std::string::npos) << b.error().message;

  // Compressed: sizes that fit the file but claim more than LZF can unpack them to.
  std::string compressed =
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 8192\nHEIGHT 8192\nDATA binary_compressed\n";
  const std::uint32_t sizes[2] = {16, 8192u * 8192u * 12u};
  compressed.append(reinterpret_cast<const char*>(sizes), 8);
  compressed += std::string(16, '\x1f');
  Result<Frame> c = decode_pcd(compressed, "lzf.pcd");
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().message.find("LZF expands at most 88"), std::string::npos)
      << c.error().message;
}

// Peak memory of a fresh child that reads `path`, in KiB above what it used before.
long child_rss_growth_kib(const fs::path& path) {
  int fds[2];
  if (::pipe(fds) != 0) return -1;
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    rusage before{}, after{};
    ::getrusage(RUSAGE_SELF, &before);
    const Result<Frame> f = read_pcd(path);
    ::getrusage(RUSAGE_SELF, &after);
    const long growth = f ? -2 : after.ru_maxrss - before.ru_maxrss;
    (void)!::write(fds[1], &growth, sizeof growth);
    ::_exit(0);
  }
  ::close(fds[1]);
  long growth = -1;
  if (::read(fds[0], &growth, sizeof growth) != sizeof growth) growth = -1;
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return growth;
}

TEST_F(PcdIoTest, HostileHeadersCostMemoryOfTheFileNotOfThePromise) {
  // PCL allocated 850 MB to 1.1 GB for these before refusing them.
  const fs::path xyz = write("xyz.pcd", lying_ascii("x y z", "4 4 4", "F F F", "1 1 1"));
  const fs::path rgba =
      write("rgba.pcd", lying_ascii("x y z rgba", "4 4 4 4", "F F F U", "1 1 1 1"));
  EXPECT_LE(fs::file_size(xyz), 151u);
  for (const fs::path& p : {xyz, rgba}) {
    const long growth = child_rss_growth_kib(p);
    ASSERT_GE(growth, 0) << p << (growth == -2 ? ": was read, not refused" : ": child failed");
    EXPECT_LT(growth, 8 * 1024) << p << ": peak RSS grew by " << growth << " KiB";
  }
}

TEST_F(PcdIoTest, AsciiBodyErrorsCarryLineAndColumn) {
  const std::string header =
      "VERSION .7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 2\n"
      "HEIGHT 1\nPOINTS 2\nDATA ascii\n";
  struct Case {
    std::string body;
    int line, column;
    const char* message_part;
  };
  const Case cases[] = {
      {"0 0 1 255\n0 0 x 255\n", 11, 5, "field 'z' expects a number"},
      {"0 0 1 255\n0 0 1 4294967296\n", 11, 7, "field 'rgb' expects a whole number"},
      {"0 0 1 255\n0 0 1\n", 11, 6, "expected 4 values"},
      {"0 0 1 255 7\n0 0 1 2\n", 10, 11, "expected 4 values"},
      {"0 0 1 255\n\n0 0 1 1\n0 0 1 1\n", 13, 1, "more points than POINTS 2"},
      {"0 0 1 255     \n             \n", 12, 1, "the body holds 1 of POINTS 2"},
  };
  for (const Case& c : cases) {
    const Result<Frame> f = decode_pcd(header + c.body, "a.pcd");
    ASSERT_FALSE(f) << c.body;
    EXPECT_EQ(f.error().location.origin, "a.pcd");
    EXPECT_EQ(f.error().location.line, c.line) << c.body << " -> " << f.error().format();
    EXPECT_EQ(f.error().location.column, c.column) << c.body << " -> " << f.error().format();
    EXPECT_NE(f.error().message.find(c.message_part), std::string::npos) << f.error().format();
  }
  // The same body, well formed, with CRLF line ends and a '+'.
  const Result<Frame> ok = decode_pcd(header + "0 0 +1 16711680\r\n0.5 0 2 255\r\n", "a.pcd");
  ASSERT_TRUE(ok) << ok.error().format();
  EXPECT_FLOAT_EQ(ok->points[0].z, 1.0f);
  EXPECT_EQ(ok->points[0].r, 255);
  EXPECT_EQ(ok->points[1].b, 255);
}

TEST_F(PcdIoTest, CorruptLzfStreamsAreErrorsNotCrashes) {
  Frame f;
  f.width = 8;
  f.height = 4;
  f.points.resize(32);
  for (std::size_t i = 0; i < f.points.size(); ++i) f.points[i] = {0.01f * i, 0, 1, 10, 20, 30};
  const fs::path p = dir_ / "c.pcd";
  ASSERT_TRUE(write_pcd_pcl(p, f, PcdHeader::Data::binary_compressed));
  std::ifstream in(p, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const Result<Frame> good = decode_pcd(bytes, "c.pcd");
  ASSERT_TRUE(good) << good.error().format();
  expect_identical(*good, f, "compressed round trip");
  const std::size_t body = bytes.find("DATA binary_compressed\n") + 23;
  // A back reference before the start of the output, then a stream cut short.
  std::string bad = bytes;
  bad[body + 8] = static_cast<char>(0xe0);
  bad[body + 9] = static_cast<char>(0xff);
  const Result<Frame> r = decode_pcd(bad, "c.pcd");
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("does not decode"), std::string::npos) << r.error().message;
  for (std::size_t i = body + 8; i < bytes.size(); ++i) {
    std::string flipped = bytes;
    flipped[i] = static_cast<char>(flipped[i] ^ 0x5a);
    (void)decode_pcd(flipped, "c.pcd");  // any result but a crash (ASan builds check)
  }
}

// A PCD stores points, not the camera: the decoder recovers the pinhole an organized
// cloud was back-projected with, so pixel-size rules count with its focal length.
TEST_F(PcdIoTest, RecoversTheIntrinsicsAnOrganizedCloudFollows) {
  const CameraIntrinsics k{320, 240, 290.0, 291.0, 161.0, 118.5};
  Frame f;
  f.width = k.width;
  f.height = k.height;
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      const double z = 1.0 + 0.002 * u + 0.001 * v;  // a tilted wall, every pixel seen
      f.points.push_back({float((u - k.cx) / k.fx * z), float((v - k.cy) / k.fy * z), float(z)});
    }
  const Result<Frame> back = decode_pcd(pcd_bytes(f), "camera.pcd");
  ASSERT_TRUE(back) << back.error().format();
  EXPECT_NEAR(back->intrinsics.fx, k.fx, 0.05);
  EXPECT_NEAR(back->intrinsics.fy, k.fy, 0.05);
  EXPECT_NEAR(back->intrinsics.cx, k.cx, 0.05);
  EXPECT_NEAR(back->intrinsics.cy, k.cy, 0.05);
  EXPECT_EQ(back->intrinsics.width, k.width);
  EXPECT_EQ(back->intrinsics.height, k.height);
  EXPECT_NEAR(focal_px(*back), k.fx, 0.05);

  // Points that follow no camera (all on one ray) keep the default, scaled to the grid.
  for (PointXYZRGB& p : f.points) p = {0.1f, 0.1f, 1.0f};
  const Result<Frame> lying = decode_pcd(pcd_bytes(f), "lying.pcd");
  ASSERT_TRUE(lying) << lying.error().format();
  EXPECT_DOUBLE_EQ(focal_px(*lying), 525.0 / 2);
}

TEST_F(PcdIoTest, TheNyuFrameReadsWithItsOwnFocalLength) {
  if (!fs::is_directory(kRealDir))
    GTEST_SKIP() << "real scans not found at " << kRealDir.string()
                 << " (the ../shared data directory is not part of the repository)";
  // NYU Depth v2's Kinect was calibrated at fx 582.6 (its toolbox); the TUM-style
  // office frame was back-projected with the default 525.
  const Result<Frame> nyu = read_pcd(kRealDir / "nyu_basement.pcd");
  const Result<Frame> office = read_pcd(kRealDir / "office1.pcd");
  ASSERT_TRUE(nyu) << nyu.error().format();
  ASSERT_TRUE(office) << office.error().format();
  EXPECT_NEAR(nyu->intrinsics.fx, 582.6, 3);
  EXPECT_NEAR(office->intrinsics.fx, 525, 5);
}

}  // namespace
}  // namespace annex
