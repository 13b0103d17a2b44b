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
  EXPECT_GT(p.dimensions_m[1], 0.2);  // the table is wide open behind the laptop
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
    const std::vector<PhysicalObject> out = find_plane_candidates(f, scan, ScanParams{});
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

}  // namespace
}  // namespace annex
