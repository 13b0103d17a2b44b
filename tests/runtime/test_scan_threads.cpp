// The scan's worker threads change nothing: a frame scanned on one thread and on two or
// three gives the same supports, objects and points, bit for bit (scan_pool.h hands out
// items in any order; scanner.cpp keeps results per item and band).
#include "annex/runtime/scanner.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "annex/formats/scene_format.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/scan_workers.h"
#include "annex/runtime/synthetic_scene.h"

namespace annex {
namespace {

const std::filesystem::path kReal = std::filesystem::path(ANNEX_SHARED_DIR) / "data" / "real";

template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Whether scan `r` (on `threads` threads) is `base` (on one) bit for bit.
bool expect_same(const Result<ScanResult>& r, const Result<ScanResult>& base, const std::string& what,
                 int threads) {
  EXPECT_TRUE(r.ok()) << what << ": " << r.error().format();
  if (!r.ok()) return false;
  // Every field exactly (doubles compared with ==), and the text as a reader sees it.
  EXPECT_TRUE(r->scene == base->scene) << what << ", threads " << threads;
  EXPECT_EQ(write_scene(r->scene), write_scene(base->scene)) << what << ", threads " << threads;
  EXPECT_EQ(r->clusters.size(), base->clusters.size()) << what << ", threads " << threads;
  if (r->clusters.size() != base->clusters.size()) return false;
  for (size_t c = 0; c < r->clusters.size(); ++c) {
    const ScanCluster& a = r->clusters[c];
    const ScanCluster& b = base->clusters[c];
    EXPECT_EQ(a.pixels, b.pixels) << what << ", threads " << threads << ", object " << c;
    EXPECT_TRUE(same_bits(a.points, b.points)) << what << ", threads " << threads << ", object " << c;
    EXPECT_EQ(a.on_object, b.on_object) << what << ", threads " << threads << ", object " << c;
    EXPECT_EQ(a.shape.primitives.size(), b.shape.primitives.size()) << what << ", object " << c;
    if (a.shape.primitives.size() != b.shape.primitives.size()) continue;
    for (size_t k = 0; k < a.shape.primitives.size(); ++k)
      EXPECT_TRUE(a.shape.primitives[k].primitive == b.shape.primitives[k].primitive)
          << what << ", threads " << threads << ", object " << c << ", primitive " << k;
  }
  EXPECT_EQ(r->supports.size(), base->supports.size()) << what << ", threads " << threads;
  if (r->supports.size() != base->supports.size()) return false;
  for (size_t k = 0; k < r->supports.size(); ++k) {
    EXPECT_TRUE(r->supports[k].surface.plane == base->supports[k].surface.plane) << what << ", support " << k;
    EXPECT_EQ(r->supports[k].surface.point_count, base->supports[k].surface.point_count) << what;
    EXPECT_TRUE(same_bits(r->supports[k].hull, base->supports[k].hull)) << what << ", support " << k;
  }
  return true;
}

// Returns the objects of the one-thread scan (0 when it failed).
size_t expect_same_scan(const Frame& frame, const std::string& what) {
  ScanParams one;
  one.threads = 1;
  const Result<ScanResult> base = scan_frame(frame, one);
  if (!base.ok()) {
    // Only the carton model without a table (milk.pcd: its faces are no support, since
    // session 10's first_plane_fits_up) fails, and alike on every thread count.
    EXPECT_EQ(what, "milk.pcd") << base.error().format();
    for (int threads : {2, 3}) {
      ScanParams p = one;
      p.threads = threads;
      const Result<ScanResult> r = scan_frame(frame, p);
      EXPECT_FALSE(r.ok()) << what << ", threads " << threads;
      if (!r.ok()) EXPECT_EQ(r.error().format(), base.error().format()) << what;
    }
    return 0;
  }
  for (int threads : {2, 3}) {
    ScanParams p = one;
    p.threads = threads;
    if (!expect_same(scan_frame(frame, p), base, what, threads)) return 0;
  }
  return base->scene.objects.size();
}

TEST(ScanThreads, RealFramesScanTheSameOnOneTwoAndThreeThreads) {
  if (!std::filesystem::exists(kReal)) GTEST_SKIP() << "../shared/data/real is absent";
  int scanned = 0;
  size_t objects = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kReal)) {
    if (entry.path().extension() != ".pcd") continue;
    Result<Frame> f = read_pcd(entry.path());
    ASSERT_TRUE(f.ok()) << f.error().format();
    objects += expect_same_scan(*f, entry.path().filename().string());
    ++scanned;
  }
  EXPECT_GE(scanned, 7);
  EXPECT_GE(objects, 30u);  // something to compare: the frames hold dozens of objects
}

// Worker threads kept across scans (scan_workers.h), as a session and the benchmark keep
// them: frame after frame on the same helpers, restarted when the thread count changes,
// each scan is the one-thread scan bit for bit.
TEST(ScanThreads, WorkersKeptAcrossScansScanTheSame) {
  std::vector<std::pair<Frame, std::string>> frames;
  for (std::uint64_t seed : {2001u, 2042u}) {
    const Result<SyntheticScene> scene = generate_scene(world_scene_params(seed));
    ASSERT_TRUE(scene.ok()) << scene.error().format();
    frames.emplace_back(render_scene(*scene).frame, "world seed " + std::to_string(seed));
  }
  if (std::filesystem::exists(kReal / "milk_cartoon_all_small_clorox.pcd")) {
    Result<Frame> f = read_pcd(kReal / "milk_cartoon_all_small_clorox.pcd");
    ASSERT_TRUE(f.ok()) << f.error().format();
    frames.emplace_back(std::move(*f), "milk_cartoon_all_small_clorox.pcd");
  }
  ScanParams one;
  one.threads = 1;
  std::vector<Result<ScanResult>> base;
  for (const auto& [frame, what] : frames) base.push_back(scan_frame(frame, one));
  ScanWorkers workers;
  EXPECT_EQ(workers.threads(), 0);
  int scans = 0;
  for (int threads : {2, 2, 3, 2}) {
    ScanParams p = one;
    p.threads = threads;
    for (size_t k = 0; k < frames.size(); ++k) {
      ASSERT_TRUE(base[k].ok()) << frames[k].second << ": " << base[k].error().format();
      EXPECT_TRUE(expect_same(scan_frame(frames[k].first, p, workers), base[k], frames[k].second, threads));
      EXPECT_EQ(workers.threads(), threads);
      ++scans;
    }
  }
  // A scan that fails after the plane stage (no support within reach) leaves the workers
  // fit for the next scan.
  ScanParams near = one;
  near.threads = 2;
  near.support_reach_m = 0.05;
  EXPECT_FALSE(scan_frame(frames[0].first, near, workers).ok());
  near.support_reach_m = one.support_reach_m;
  EXPECT_TRUE(expect_same(scan_frame(frames[0].first, near, workers), base[0], frames[0].second, 2));
  EXPECT_GE(scans, 8);
}

TEST(ScanThreads, GeneratedWorldScenesScanTheSameOnOneTwoAndThreeThreads) {
  // Seeds of the tuned world set: supports, legs, furniture, objects cut by the border.
  for (std::uint64_t seed : {2001u, 2007u, 2013u, 2042u}) {
    const Result<SyntheticScene> scene = generate_scene(world_scene_params(seed));
    ASSERT_TRUE(scene.ok()) << scene.error().format();
    EXPECT_GT(expect_same_scan(render_scene(*scene).frame, "world seed " + std::to_string(seed)), 0u);
  }
}

// Touching bodies are cut in two inside the clusters' fits (touching_split.h), beside
// the other clusters' fits: two held-out rooms where a cut is kept (the scene differs
// from the one with the cut off: the path is exercised) scan the same on one, two and
// three threads.
TEST(ScanThreads, TouchingPairsCutScanTheSameOnOneTwoAndThreeThreads) {
  int cut = 0;
  for (std::uint64_t seed : {5051u, 5118u}) {
    const Result<SyntheticScene> scene = generate_scene(room_scene_params(seed));
    ASSERT_TRUE(scene.ok()) << scene.error().format();
    const Frame frame = render_scene(*scene).frame;
    const std::string what = "room seed " + std::to_string(seed);
    const size_t objects = expect_same_scan(frame, what);
    ScanParams uncut;
    uncut.threads = 1;
    uncut.touching_max_coverage = 0;
    const Result<ScanResult> whole = scan_frame(frame, uncut);
    ASSERT_TRUE(whole.ok()) << what << ": " << whole.error().format();
    EXPECT_GT(objects, 0u) << what;
    ScanParams one;
    one.threads = 1;
    const Result<ScanResult> base = scan_frame(frame, one);
    ASSERT_TRUE(base.ok()) << what << ": " << base.error().format();
    cut += write_scene(base->scene) != write_scene(whole->scene);
  }
  EXPECT_EQ(cut, 2);
}

// A first plane's test against a band cut across a wall (slices_steep_surface) and its
// reach (gap_reach) run as items beside its regions and the pool's compaction: unseen
// seed 3038, whose first plane is such a band (the scene differs with the test off: the
// path is exercised), and two more tuned seeds scan the same on one, two and three
// threads (the real frames' test covers a second support kept within the first's reach).
TEST(ScanThreads, FirstPlaneTestsBesideItsRegionsScanTheSameOnOneTwoAndThreeThreads) {
  const Result<SyntheticScene> wall = generate_scene(world_scene_params(3038));
  ASSERT_TRUE(wall.ok()) << wall.error().format();
  const Frame frame = render_scene(*wall).frame;
  EXPECT_GT(expect_same_scan(frame, "world seed 3038"), 0u);
  ScanParams on, off;
  on.threads = off.threads = 1;
  off.first_plane_fits_up = false;
  const Result<ScanResult> with_test = scan_frame(frame, on);
  const Result<ScanResult> without = scan_frame(frame, off);
  ASSERT_TRUE(with_test.ok() && without.ok());
  EXPECT_NE(write_scene(with_test->scene), write_scene(without->scene));
  for (std::uint64_t seed : {2003u, 2029u}) {
    const Result<SyntheticScene> scene = generate_scene(world_scene_params(seed));
    ASSERT_TRUE(scene.ok()) << scene.error().format();
    EXPECT_GT(expect_same_scan(render_scene(*scene).frame, "world seed " + std::to_string(seed)), 0u);
  }
}

}  // namespace
// The strided pixels are gathered in chunks of grid rows on the scan's threads: frames
// whose grid neither fills the last chunk nor the last column (a crop of a world scene
// to 637 x 473, strides 2 and 3) scan the same on one, two and three threads.
TEST(ScanThreads, OddFrameSizesScanTheSameOnOneTwoAndThreeThreads) {
  const Result<SyntheticScene> scene = generate_scene(world_scene_params(2001));
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  const Frame full = render_scene(*scene).frame;
  Frame crop;
  crop.width = full.width - 3;
  crop.height = full.height - 7;
  for (int y = 0; y < crop.height; ++y)
    for (int x = 0; x < crop.width; ++x)
      crop.points.push_back(full.points[static_cast<size_t>(y) * full.width + x]);
  for (int stride : {2, 3}) {
    ScanParams one;
    one.threads = 1;
    one.pixel_stride = stride;
    const Result<ScanResult> base = scan_frame(crop, one);
    ASSERT_TRUE(base.ok()) << base.error().format();
    EXPECT_GT(base->scene.objects.size(), 0u) << "stride " << stride;
    for (int threads : {2, 3}) {
      ScanParams p = one;
      p.threads = threads;
      EXPECT_TRUE(expect_same(scan_frame(crop, p), base, "crop, stride " + std::to_string(stride), threads));
    }
  }
}

}  // namespace annex
