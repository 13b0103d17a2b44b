// Flat surfaces for virtual panels (plane_candidates.h) on real Kinect frames of
// ../shared/data/real (skipped when absent): a support's free rectangle, a box's top,
// a slab's face; a plane primitive matched to them; the objects' votes untouched.
#include "annex/runtime/plane_candidates.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <utility>
#include <vector>

#include "annex/common/object_finder.h"
#include "annex/formats/haptic_format.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/scanner.h"

namespace annex {
namespace {

const std::filesystem::path kReal = std::filesystem::path(ANNEX_SHARED_DIR) / "data" / "real";

std::optional<ScanResult> scan_real(const std::string& name) {
  const auto path = kReal / name;
  if (!std::filesystem::exists(path)) return std::nullopt;
  Result<Frame> f = read_pcd(path);
  EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().format());
  if (!f.ok()) return std::nullopt;
  Result<ScanResult> scan = scan_frame(*f);
  EXPECT_TRUE(scan.ok()) << (scan.ok() ? "" : scan.error().format());
  if (!scan.ok()) return std::nullopt;
  return std::move(*scan);
}

const PhysicalObject* surface(const ScanResult& scan, const std::string& id) {
  for (const PhysicalObject& o : scan.surfaces)
    if (o.id == id) return &o;
  return nullptr;
}

constexpr const char* kLaptopFrame = "frame_20121214T142255.814212.pcd";

TEST(PlaneCandidates, EverySurfaceIsAWellFormedRectangle) {
  for (const char* name : {kLaptopFrame, "milk_cartoon_all_small_clorox.pcd", "office1.pcd"}) {
    const auto scan = scan_real(name);
    if (!scan) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
    EXPECT_FALSE(scan->surfaces.empty()) << name;
    for (const PhysicalObject& o : scan->surfaces) {
      ASSERT_EQ(o.primitives.size(), 1u) << o.id;
      const PhysicalPrimitive& p = o.primitives[0];
      EXPECT_EQ(p.kind, ShapeKind::plane);
      ASSERT_EQ(p.dimensions_m.size(), 2u);
      EXPECT_GE(p.dimensions_m[0], p.dimensions_m[1]) << o.id;
      EXPECT_GE(p.dimensions_m[1], PlaneCandidateParams{}.min_side_m) << o.id;
      EXPECT_NEAR(norm(p.axis), 1, 1e-9);
      EXPECT_NEAR(norm(p.x_axis), 1, 1e-9);
      EXPECT_NEAR(dot(p.axis, p.x_axis), 0, 1e-9) << o.id;
      EXPECT_GT(o.point_count, 0) << o.id;
      EXPECT_FALSE(o.support_id.empty()) << o.id;
      // Each faces the camera (at the origin): a hand reaches its seen side.
      EXPECT_LT(dot(p.axis, p.center), 0) << name << " " << o.id;
    }
  }
}

// The free rectangle of the table holds none of the objects' points: a panel laid on
// it does not cut through the laptop or the box.
TEST(PlaneCandidates, TheFreeRegionKeepsClearOfEveryObject) {
  const auto scan = scan_real(kLaptopFrame);
  if (!scan) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  const PhysicalObject* free = surface(*scan, "s1.free");
  ASSERT_NE(free, nullptr);
  const PhysicalPrimitive& p = free->primitives[0];
  EXPECT_GT(p.dimensions_m[0], 0.4);  // the table is open in front of the laptop
  const Vec3 y = cross(p.axis, p.x_axis);
  int inside = 0;
  for (const ScanCluster& c : scan->clusters)
    for (const Vec3& q : c.points) {
      const Vec3 r = q - p.center;
      inside += std::abs(dot(r, p.x_axis)) < p.dimensions_m[0] / 2 &&
                std::abs(dot(r, y)) < p.dimensions_m[1] / 2 && dot(r, p.axis) < 0.6;
    }
  EXPECT_EQ(inside, 0);
}

// The free rectangle lies where the user's hand reaches: on the near part of the table,
// in front of the objects, not on the larger open area behind them that the largest
// rectangle anywhere finds (reach_m unbounded).
TEST(PlaneCandidates, TheFreeRegionIsWithinReach) {
  for (const char* name : {kLaptopFrame, "milk_cartoon_all_small_clorox.pcd"}) {
    const auto path = kReal / name;
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "../shared/data/real is absent";
    Result<Frame> f = read_pcd(path);
    ASSERT_TRUE(f.ok());
    ScanParams unbounded;
    unbounded.planes.reach_m = 100;
    Result<ScanResult> near = scan_frame(*f), anywhere = scan_frame(*f, unbounded);
    ASSERT_TRUE(near.ok() && anywhere.ok()) << name;
    const PhysicalObject* a = surface(*near, "s1.free");
    const PhysicalObject* b = surface(*anywhere, "s1.free");
    ASSERT_TRUE(a && b) << name;
    const PhysicalPrimitive& p = a->primitives[0];
    const PhysicalPrimitive& q = b->primitives[0];
    EXPECT_LT(norm(p.center), 0.9) << name;
    EXPECT_GT(norm(q.center), norm(p.center) + 0.4) << name;
    EXPECT_GE(q.dimensions_m[0] * q.dimensions_m[1], p.dimensions_m[0] * p.dimensions_m[1]);
    // The nearest objects' points lie beyond it or beside it, never on it.
    EXPECT_GE(std::min(p.dimensions_m[0], p.dimensions_m[1]), PlaneCandidateParams{}.min_side_m);
  }
}

// The laptop's lid (a slab facing the camera) and the carton's top are surfaces; the
// carton's top, also found as a support, is reported once.
TEST(PlaneCandidates, SlabFacesAndBoxTopsOnce) {
  const auto scan = scan_real(kLaptopFrame);
  if (!scan) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  const PhysicalObject* lid = surface(*scan, "p1.face");
  ASSERT_NE(lid, nullptr);
  EXPECT_NEAR(lid->primitives[0].dimensions_m[0], 0.37, 0.03);
  EXPECT_NEAR(lid->primitives[0].dimensions_m[1], 0.25, 0.03);
  int carton_tops = 0;
  for (const PhysicalObject& o : scan->surfaces) {
    const Vec3 c = o.primitives[0].center;
    carton_tops += std::abs(c.x - 0.19) < 0.05 && std::abs(c.z - 0.91) < 0.05;
  }
  EXPECT_EQ(carton_tops, 1);
}

// A virtual keyboard panel of a laptop lid's size is matched to the lid; the objects'
// own votes are those of a scan without surfaces.
TEST(PlaneCandidates, APlanePrimitiveMatchesARealFlatSurface) {
  const auto scan = scan_real(kLaptopFrame);
  if (!scan) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  const auto spec = parse_haptic(
      "annex-haptic 1\n"
      "object screen\n"
      "  primitive face plane\n"
      "    size_x 0.35\n"
      "    size_y 0.24\n"
      "  end\n"
      "end\n"
      "object crate\n"
      "  primitive body box\n"
      "    size_x 0.24\n    size_y 0.16\n    size_z 0.09\n"
      "  end\n"
      "end\n",
      "panel.haptic");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  const PhysicalScene scene = scene_with_surfaces(*scan);
  ASSERT_EQ(scene.objects.size(), scan->scene.objects.size() + scan->surfaces.size());
  const MatchResult m = match_objects(*spec, scene);
  ASSERT_TRUE(m.matches[0].physical_index.has_value());
  EXPECT_EQ(scene.objects[static_cast<size_t>(*m.matches[0].physical_index)].id, "p1.face");
  EXPECT_GT(m.matches[0].vote, 90);
  // The crate still goes to the carton (p3), as it does without surfaces.
  const MatchResult without = match_objects(*spec, scan->scene);
  ASSERT_TRUE(m.matches[1].physical_index && without.matches[1].physical_index);
  EXPECT_EQ(scene.objects[static_cast<size_t>(*m.matches[1].physical_index)].id,
            scan->scene.objects[static_cast<size_t>(*without.matches[1].physical_index)].id);
  EXPECT_DOUBLE_EQ(m.matches[1].vote, without.matches[1].vote);
}

// A support whose hull reaches far beyond what the camera saw of it (the floor margin,
// the camera's foot): the free rectangle is the seen patch less the clearance around
// what stands on it, wherever the patch lies in the hull. A 60 x 40 cm patch, 1 m
// below the camera, 2.5 m of hull on every side; a 10 cm block on its left end.
TEST(PlaneCandidates, TheFreeRectangleIsTheSeenPatchInAWideHull) {
  const Vec3 up{0, -1, 0};
  const double d = 1.0;  // the plane y = 1 (n = up): n.p + d = 0
  for (const double x0 : {-0.3, 0.45}) {
    Frame f;
    auto add = [&](double x, double y, double z) {
      PointXYZRGB p;
      p.x = static_cast<float>(x), p.y = static_cast<float>(y), p.z = static_cast<float>(z);
      f.points.push_back(p);
    };
    for (double x = x0; x <= x0 + 0.6 + 1e-9; x += 0.004)
      for (double z = 1.8; z <= 2.2 + 1e-9; z += 0.004) add(x, d, z);
    for (double x = x0; x <= x0 + 0.1 + 1e-9; x += 0.004)  // the block's top, 8 cm up
      for (double z = 1.95; z <= 2.05 + 1e-9; z += 0.004) add(x, d - 0.08, z);
    f.width = static_cast<int>(f.points.size());
    f.height = 1;
    ScanResult scan;
    ScanSupport sp;
    sp.surface.id = "s1";
    sp.surface.plane = {up, d};
    sp.selected = true;
    for (const auto& [x, z] : std::vector<std::pair<double, double>>{
             {x0 - 2.5, -0.5}, {x0 + 3.1, -0.5}, {x0 + 3.1, 4.5}, {x0 - 2.5, 4.5}})
      sp.hull.push_back({x, d, z});
    scan.supports.push_back(sp);
    PlaneCandidateParams planes;
    planes.reach_m = 10;  // the whole patch within reach: this tests the grid's cut
    const std::vector<PhysicalObject> out = find_plane_candidates(f, scan, ScanParams{}, planes);
    ASSERT_EQ(out.size(), 1u) << x0;
    ASSERT_EQ(out[0].id, "s1.free");
    const PhysicalPrimitive& p = out[0].primitives[0];
    // Right of the block and its 3 cm clearance: 60 - 10 - 3 = 47 cm by 40 cm, give or
    // take the 1 cm cells and the closing at the patch's edges.
    EXPECT_NEAR(p.dimensions_m[0], 0.47, 0.025) << x0;
    EXPECT_NEAR(p.dimensions_m[1], 0.40, 0.025) << x0;
    EXPECT_NEAR(p.center.x, x0 + 0.1 + 0.03 + 0.235, 0.015) << x0;
    EXPECT_NEAR(p.center.z, 2.0, 0.015) << x0;
    EXPECT_NEAR(p.center.y, d, 1e-6) << x0;
    EXPECT_GT(out[0].point_count, 0);
  }
}

// scan.conf's plane_* keys: the sample file holds the defaults, values are read, bad
// ones are errors at their line and column, `plane_candidates 0` leaves no surfaces.
TEST(PlaneCandidates, ScanConfigKeys) {
  const Result<ScanParams> sample =
      read_scan_config_file(std::filesystem::path(ANNEX_SOURCE_DIR) / "samples/config/scan.conf");
  ASSERT_TRUE(sample.ok()) << sample.error().format();
  const PlaneCandidateParams d;
  const PlaneCandidateParams& s = sample->planes;
  EXPECT_TRUE(sample->plane_candidates);
  EXPECT_EQ(s.min_side_m, d.min_side_m);
  EXPECT_EQ(s.clearance_m, d.clearance_m);
  EXPECT_EQ(s.cell_m, d.cell_m);
  EXPECT_EQ(s.reach_m, d.reach_m);
  EXPECT_EQ(s.max_face_tilt_deg, d.max_face_tilt_deg);
  EXPECT_EQ(s.min_face_share, d.min_face_share);
  EXPECT_EQ(s.slab_ratio, d.slab_ratio);

  const Result<ScanParams> p = parse_scan_config(
      "plane_candidates 0\nplane_min_side_m 0.08\nplane_clearance_m 0\nplane_cell_m 0.02\n"
      "plane_reach_m 0.7\nplane_max_face_tilt_deg 10\nplane_min_face_share 0.3\n"
      "plane_slab_ratio 0.2\n",
      "t.conf");
  ASSERT_TRUE(p.ok()) << p.error().format();
  EXPECT_FALSE(p->plane_candidates);
  EXPECT_EQ(p->planes.min_side_m, 0.08);
  EXPECT_EQ(p->planes.clearance_m, 0);
  EXPECT_EQ(p->planes.cell_m, 0.02);
  EXPECT_EQ(p->planes.reach_m, 0.7);
  EXPECT_EQ(p->planes.max_face_tilt_deg, 10);
  EXPECT_EQ(p->planes.min_face_share, 0.3);
  EXPECT_EQ(p->planes.slab_ratio, 0.2);

  for (const auto& [text, column] : std::vector<std::pair<std::string, int>>{
           {"\nplane_cell_m 0\n", 14}, {"\nplane_reach_m -1\n", 15},
           {"\nplane_min_face_share 1.5\n", 22}, {"\nplane_max_face_tilt_deg 95\n", 25}}) {
    const Result<ScanParams> bad = parse_scan_config(text, "t.conf");
    ASSERT_FALSE(bad.ok()) << text;
    EXPECT_EQ(bad.error().location, (Location{"t.conf", 2, column})) << bad.error().format();
  }

  const auto path = kReal / kLaptopFrame;
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "../shared/data/real is absent";
  Result<Frame> f = read_pcd(path);
  ASSERT_TRUE(f.ok());
  Result<ScanResult> off = scan_frame(*f, *p), on = scan_frame(*f);
  ASSERT_TRUE(off.ok() && on.ok());
  EXPECT_TRUE(off->surfaces.empty());
  EXPECT_FALSE(on->surfaces.empty());
}

}  // namespace
}  // namespace annex
