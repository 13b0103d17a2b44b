// Clutter: the object segmenter on analytic depth images (a concave crease splits, a
// convex ridge and a bowl's smooth hollow do not), cylinders lying on their side, and
// OSD learning scenes with fixed expectations (skipped when ../shared is absent).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <functional>
#include <random>

#include "annex/runtime/object_segmenter.h"
#include "annex/runtime/object_shape_recognizer.h"
#include "annex/runtime/scanner.h"
#include "annex/runtime/synthetic_scene.h"
#include "osd_eval.h"

namespace annex {
namespace {

constexpr double kPi = 3.14159265358979323846;

// An organized Kinect frame of a surface given as depth along each pixel's ray:
// depth(u', v') with u' = (u - cx) / fx, v' = (v - cy) / fy; NaN outside the patch.
Frame depth_frame(const std::function<double(double, double)>& depth, double sigma,
                  std::uint64_t seed) {
  const CameraIntrinsics k;
  Frame f;
  f.width = k.width;
  f.height = k.height;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, sigma);
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      const double a = (u - k.cx) / k.fx, b = (v - k.cy) / k.fy;
      double z = depth(a, b);
      PointXYZRGB p;
      if (!std::isfinite(z)) {
        p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
      } else {
        z += noise(rng);
        p.x = static_cast<float>(a * z);
        p.y = static_cast<float>(b * z);
        p.z = static_cast<float>(z);
      }
      f.points.push_back(p);
    }
  return f;
}

// The valid pixels of the frame on the grid of `step`, as the scanner clusters them.
std::vector<int> grid_of(const Frame& f, int step) {
  std::vector<int> out;
  for (int y = 0; y < f.height; y += step)
    for (int x = 0; x < f.width; x += step)
      if (std::isfinite(f.points[static_cast<size_t>(y) * f.width + x].z))
        out.push_back(y * f.width + x);
  return out;
}

// A 20 x 20 cm patch 1 m away (|X|, |Y| < 0.1 m at z ~ 1).
bool in_patch(double a, double b) { return std::abs(a) < 0.1 && std::abs(b) < 0.1; }

TEST(ObjectSegmenter, ConcaveCreaseSplitsTwoFaces) {
  // Two faces at 45 degrees to the view meeting in a valley 1 m away: z = 1 / (1 + |u'|).
  const Frame f = depth_frame(
      [](double a, double b) { return in_patch(a, b) ? 1.0 / (1.0 + std::abs(a)) : NAN; }, 0.001, 1);
  const auto parts = split_cluster(f, grid_of(f, 2), 2, 0.02);
  ASSERT_EQ(parts.size(), 2u);
  // Each part lies on one side of the crease.
  for (const auto& part : parts) {
    int left = 0;
    for (int i : part) left += i % f.width < 320;
    EXPECT_TRUE(left < 0.05 * part.size() || left > 0.95 * part.size());
  }
}

TEST(ObjectSegmenter, ConvexRidgeAndSmoothHollowStayWhole) {
  // A box's edge towards the camera: z = 1 / (1 - |u'|).
  const Frame ridge = depth_frame(
      [](double a, double b) { return in_patch(a, b) ? 1.0 / (1.0 - std::abs(a)) : NAN; }, 0.001, 2);
  EXPECT_EQ(split_cluster(ridge, grid_of(ridge, 2), 2, 0.02).size(), 1u);
  // A bowl's inside, 7 cm radius, seen from above: its rim nearer than its bottom.
  const Frame bowl = depth_frame(
      [](double a, double b) {
        const double r2 = a * a + b * b;
        return r2 < 0.05 * 0.05 ? 0.9 - r2 / (2 * 0.07) + 0.07 : NAN;
      },
      0.001, 3);
  EXPECT_EQ(split_cluster(bowl, grid_of(bowl, 2), 2, 0.02).size(), 1u);
  // Turned off, even the crease stays one cluster.
  const Frame valley = depth_frame(
      [](double a, double b) { return in_patch(a, b) ? 1.0 / (1.0 + std::abs(a)) : NAN; }, 0.001, 4);
  SegmenterParams off;
  off.enabled = false;
  EXPECT_EQ(split_cluster(valley, grid_of(valley, 2), 2, 0.02, off).size(), 1u);
}

TEST(ObjectSegmenter, DepthStepSplitsAnObjectFromTheOneBehind) {
  // A near face 1 cm in front of a far one on the left half: a step under the 2 cm
  // clustering tolerance, so one Euclidean cluster.
  const Frame f = depth_frame(
      [](double a, double b) { return in_patch(a, b) ? (a < 0 ? 0.99 : 1.0) : NAN; }, 0.0005, 5);
  EXPECT_EQ(split_cluster(f, grid_of(f, 2), 2, 0.02).size(), 2u);
}

// The visible side of a cylinder of radius r lying on the table y = 0.4 (camera frame,
// y down) with its axis along `dir` (horizontal), centre of the axis at (x, z).
TEST(ObjectShapeRecognizer, CylinderLyingOnItsSideHasItsAxisAlongTheTable) {
  const Plane table{{0, -1, 0}, 0.4};
  for (const double yaw_deg : {0.0, 35.0, 80.0}) {
    const double yaw = yaw_deg * kPi / 180, r = 0.038, len = 0.22;
    const Vec3 axis{std::cos(yaw), 0, std::sin(yaw)};
    const Vec3 e1{0, -1, 0}, e2 = cross(axis, e1);
    const Vec3 centre{0.05, 0.4 - r, 1.0};
    std::mt19937_64 rng(7);
    std::normal_distribution<double> noise(0, 0.0015);
    std::vector<Vec3> pts, nrm;
    for (int i = 0; i < 90; ++i)
      for (int j = 0; j <= 40; ++j) {
        const double t = 2 * kPi * i / 90, s = len * (j / 40.0 - 0.5);
        const Vec3 radial = e1 * std::cos(t) + e2 * std::sin(t);
        const Vec3 p = centre + axis * s + radial * r;
        if (dot(radial, p) >= 0 || p.y > 0.4 - 0.012) continue;  // hidden, or in the table band
        pts.push_back(p + normalized(p) * noise(rng));
        nrm.push_back(radial);
      }
    const ObjectShape shape = recognize_object_shape(pts, nrm, table);
    ASSERT_FALSE(shape.primitives.empty()) << yaw_deg;
    const PhysicalPrimitive& p = shape.primitives[0].primitive;
    EXPECT_EQ(p.kind, ShapeKind::cylinder) << yaw_deg;
    EXPECT_NEAR(p.dimensions_m[0], r, 0.004) << yaw_deg;
    EXPECT_NEAR(p.dimensions_m[1], len, 0.012) << yaw_deg;
    EXPECT_GT(std::abs(dot(normalized(p.axis), axis)), 0.98) << yaw_deg;
  }
}

// A camera 35 degrees down on a table 1 m ahead: the table's plane in camera coordinates.
struct TiltedTable {
  Vec3 n = normalized(Vec3{0, -std::cos(35 * kPi / 180), -std::sin(35 * kPi / 180)});
  Vec3 foot{0, 0.3, 1.0};  // a point of the table ahead
  Plane plane() const { return {n, -dot(n, foot)}; }
  // A horizontal direction, turned by yaw about up from the one facing the camera.
  Vec3 level(double yaw) const {
    const Vec3 back = normalized(foot * -1.0 - n * dot(n, foot * -1.0));
    const Vec3 side = cross(n, back);
    return back * std::cos(yaw) + side * std::sin(yaw);
  }
};

// A short wide cylinder on its rim (a cookie tin on its edge) seen by its lid and the
// part of its rim that faces the camera, or a box of the same size on its edge.
struct RimScene {
  std::vector<Vec3> pts, nrm;
};
RimScene on_its_edge(bool round, double yaw, std::uint64_t seed) {
  const TiltedTable t;
  const double r = 0.09, len = 0.07;
  const Vec3 axis = t.level(yaw);
  const Vec3 e1 = t.n, e2 = cross(axis, e1);
  const Vec3 centre = t.foot + t.n * r;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, 0.0015), tilt(0, 0.08);
  RimScene out;
  auto add = [&](const Vec3& p, const Vec3& nr) {
    if (dot(t.n, p) + t.plane().d < 0.012) return;  // in the table's band
    if (dot(nr, p) >= 0) return;                     // faces away from the camera
    out.pts.push_back(p + normalized(p) * noise(rng));
    out.nrm.push_back(nr);
  };
  for (int i = -45; i <= 45; ++i)
    for (int j = -45; j <= 45; ++j) {
      const double u = r * i / 45.0, v = r * j / 45.0;
      if (round && u * u + v * v > r * r) continue;
      // The lid, embossed: its normals scatter, its points stay on the plane.
      const Vec3 lid_n = normalized(axis + e1 * tilt(rng) + e2 * tilt(rng));
      add(centre + axis * (len / 2) + e1 * u + e2 * v, lid_n);
    }
  for (int i = 0; i < 180; ++i)
    for (int j = 0; j <= 20; ++j) {
      const double s = len * (j / 20.0 - 0.5);
      if (round) {
        const double a = 2 * kPi * i / 180;
        const Vec3 radial = e1 * std::cos(a) + e2 * std::sin(a);
        add(centre + axis * s + radial * r, radial);
      } else {
        // The box's four side faces, 45 points along each.
        const int face = i / 45;
        const double w = r * ((i % 45) / 22.0 - 1.0);
        const Vec3 fn = face == 0 ? e1 : face == 1 ? e1 * -1.0 : face == 2 ? e2 : e2 * -1.0;
        const Vec3 along = face < 2 ? e2 : e1;
        add(centre + axis * s + fn * r + along * w, fn);
      }
    }
  return out;
}

TEST(ObjectShapeRecognizer, TinOnItsRimIsACylinderAcrossTheTable) {
  const TiltedTable t;
  for (const double yaw_deg : {0.0, 30.0}) {
    const RimScene tin = on_its_edge(true, yaw_deg * kPi / 180, 3);
    const ObjectShape shape = recognize_object_shape(tin.pts, tin.nrm, t.plane());
    ASSERT_FALSE(shape.primitives.empty()) << yaw_deg;
    const PhysicalPrimitive& p = shape.primitives[0].primitive;
    ASSERT_EQ(p.kind, ShapeKind::cylinder) << yaw_deg;
    EXPECT_NEAR(p.dimensions_m[0], 0.09, 0.006) << yaw_deg;
    EXPECT_NEAR(p.dimensions_m[1], 0.07, 0.012) << yaw_deg;
    EXPECT_GT(std::abs(dot(normalized(p.axis), t.level(yaw_deg * kPi / 180))), 0.97) << yaw_deg;
  }
}

TEST(ObjectShapeRecognizer, BoxOnItsEdgeStaysABox) {
  const TiltedTable t;
  for (const double yaw_deg : {0.0, 30.0}) {
    const RimScene box = on_its_edge(false, yaw_deg * kPi / 180, 4);
    const ObjectShape shape = recognize_object_shape(box.pts, box.nrm, t.plane());
    ASSERT_FALSE(shape.primitives.empty()) << yaw_deg;
    EXPECT_EQ(shape.primitives[0].primitive.kind, ShapeKind::box) << yaw_deg;
  }
}

// A bowl (a frustum widening upwards, open) seen from above: its outer front and the
// inner far wall show. A sphere would explain both walls, but a closed sphere never
// shows its far half: the bowl is a cone narrowing down, with its true radii.
TEST(ObjectShapeRecognizer, BowlIsAFrustumNarrowingDownNotASphere) {
  const TiltedTable t;
  const double r_foot = 0.05, r_rim = 0.085, h = 0.07;
  const Vec3 base = t.foot, e1 = t.level(0), e2 = cross(t.n, e1);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0, 0.0012);
  std::vector<Vec3> pts, nrm;
  const double slope = (r_rim - r_foot) / h;
  for (int i = 0; i < 120; ++i)
    for (int j = 0; j <= 30; ++j) {
      const double a = 2 * kPi * i / 120, z = h * j / 30.0;
      if (z < 0.012) continue;  // the table's band
      const double r = r_foot + slope * z;
      const Vec3 radial = e1 * std::cos(a) + e2 * std::sin(a);
      const Vec3 p = base + t.n * z + radial * r;
      const Vec3 out_n = normalized(radial - t.n * slope);
      // Outer wall where it faces the camera; inner wall (normal -out_n) where that does,
      // above the line of sight over the near rim (its upper two thirds).
      Vec3 nr;
      if (dot(out_n, p) < 0)
        nr = out_n;
      else if (z > h / 3)
        nr = out_n * -1.0;
      else
        continue;
      pts.push_back(p + normalized(p) * noise(rng));
      nrm.push_back(nr);
    }
  const ObjectShape shape = recognize_object_shape(pts, nrm, t.plane());
  ASSERT_FALSE(shape.primitives.empty());
  const PhysicalPrimitive& p = shape.primitives[0].primitive;
  ASSERT_EQ(p.kind, ShapeKind::cone);
  EXPECT_LT(dot(normalized(p.axis), t.n), -0.9);  // from the wide rim down to the foot
  EXPECT_NEAR(p.dimensions_m[0], r_rim, 0.008);
  EXPECT_NEAR(p.narrow_radius_m, r_foot + slope * 0.012, 0.012);
  EXPECT_NEAR(p.dimensions_m[1], h, 0.012);
}

// A pot seen from above: an open cylinder (outer front wall, inner far wall) with a
// 1.5 cm rim lip and two handles at its top, flat and facing up. They stand outside the body's
// radius, so they are no cap and no side of it: the pot is still the cylinder of its
// body, not `unknown` (learn36-38's pot).
TEST(ObjectShapeRecognizer, PotWithLipAndHandlesIsACylinderOfItsBody) {
  const TiltedTable t;
  const double r = 0.084, h = 0.10, lip = 0.015, handle = 0.035;
  const Vec3 base = t.foot, e1 = t.level(0), e2 = cross(t.n, e1);
  std::mt19937_64 rng(9);
  std::normal_distribution<double> noise(0, 0.0012);
  std::vector<Vec3> pts, nrm;
  auto add = [&](const Vec3& p, const Vec3& n) {
    pts.push_back(p + normalized(p) * noise(rng));
    nrm.push_back(n);
  };
  for (int i = 0; i < 120; ++i) {
    const double a = 2 * kPi * i / 120;
    const Vec3 radial = e1 * std::cos(a) + e2 * std::sin(a);
    for (int j = 0; j <= 30; ++j) {
      const double z = h * j / 30.0;
      if (z < 0.012) continue;  // the table's band
      const Vec3 p = base + t.n * z + radial * r;
      if (dot(radial, p) < 0)
        add(p, radial);
      else if (z > h / 3)
        add(p, radial * -1.0);
    }
    // The lip is rolled outwards from 3 mm outside the wall and down by 8 mm.
    for (int k = 0; k < 6; ++k) {
      const double f = (k + 0.5) / 6;
      add(base + t.n * (h - 0.008 * f) + radial * (r + 0.003 + lip * f), t.n);
    }
  }
  // The handles: 3 cm wide tabs reaching 3.5 cm out at either side, level with the rim.
  for (const double side : {-1.0, 1.0})
    for (int i = 0; i < 12; ++i)
      for (int k = 0; k < 12; ++k)
        add(base + t.n * (h - 0.004) + e2 * (side * (r + lip + (handle - lip) * k / 11.0)) +
                e1 * (0.03 * (i / 11.0 - 0.5)),
            t.n);
  const ObjectShape shape = recognize_object_shape(pts, nrm, t.plane());
  ASSERT_FALSE(shape.primitives.empty());
  const PhysicalPrimitive& p = shape.primitives[0].primitive;
  ASSERT_EQ(p.kind, ShapeKind::cylinder);
  EXPECT_GT(dot(normalized(p.axis), t.n), 0.97);
  EXPECT_NEAR(p.dimensions_m[0], r, 0.004);
  EXPECT_NEAR(p.dimensions_m[1], h, 0.01);
}

// A generated table seen from 1 m and `tilt_deg` above, with nothing on or around it:
// the stacking tests place their own objects.
Result<SyntheticScene> bare_table(double tilt_deg) {
  SyntheticSceneParams sp;
  sp.seed = 3;
  sp.object_count = 1;
  sp.camera_distance_min_m = sp.camera_distance_max_m = 1.0;
  sp.camera_tilt_min_deg = sp.camera_tilt_max_deg = tilt_deg;
  Result<SyntheticScene> scene = generate_scene(sp);
  if (!scene) return scene;
  scene->objects.clear();
  scene->occluder.reset();
  scene->furniture.clear();
  return scene;
}

// A storage box on the table, wide enough that its top is a support of its own, and a
// can standing on that top: the can stands on the box by the support's id (no geometry
// re-derived), is fitted on the box top, and names that support.
TEST(ClutterStacking, ObjectOnABoxTopSupportStandsOnTheBox) {
  Result<SyntheticScene> scene = bare_table(45);
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  const double box_h = 0.2, can_h = 0.12;
  scene->objects.push_back(resting_object(ShapeKind::box, {0.32, 0.26, box_h}, 0, 0.05));
  SyntheticObject can = resting_object(ShapeKind::cylinder, {0.04, can_h}, 0.02, 0.05);
  can.center.z += box_h;
  scene->objects.push_back(can);
  Result<ScanResult> scan = scan_frame(render_scene(*scene).frame);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  ASSERT_GE(scan->supports.size(), 2u);
  ASSERT_EQ(scan->scene.objects.size(), 2u);
  const PhysicalObject* box = nullptr;
  const PhysicalObject* top = nullptr;
  for (const PhysicalObject& o : scan->scene.objects) {
    ASSERT_FALSE(o.primitives.empty()) << o.id;
    (o.primitives[0].kind == ShapeKind::cylinder ? top : box) = &o;
  }
  ASSERT_TRUE(box && top);
  EXPECT_EQ(box->primitives[0].kind, ShapeKind::box);
  EXPECT_EQ(top->on_object, box->id);
  EXPECT_TRUE(box->on_object.empty());
  EXPECT_NE(top->support_id, box->support_id);  // the box's top, not the table
  EXPECT_NEAR(top->primitives[0].dimensions_m[1], can_h, 0.015);
}

// A tin standing on a tin nearly its width, seen from 1 m and 25 degrees above: the
// crease between the lower lid's rim and the upper tin's side fades where the two
// silhouettes meet, and without the level cut the two are one tall cylinder (with the
// outline's step off too: the outline steps 1.6 cm there, which alone cuts them).
TEST(ClutterStacking, TinOnATinOfItsWidthIsCutAtTheLevelCrease) {
  Result<SyntheticScene> scene = bare_table(25);
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  const double lower_r = 0.05, lower_h = 0.1, upper_r = 0.042, upper_h = 0.12;
  scene->objects.push_back(resting_object(ShapeKind::cylinder, {lower_r, lower_h}, 0, 0.05));
  SyntheticObject upper = resting_object(ShapeKind::cylinder, {upper_r, upper_h}, 0.003, 0.05);
  upper.center.z += lower_h;
  upper.on_object = 0;
  scene->objects.push_back(upper);
  const Frame frame = render_scene(*scene).frame;
  Result<ScanResult> scan = scan_frame(frame);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  ASSERT_EQ(scan->scene.objects.size(), 2u);
  const PhysicalObject* lower = nullptr;
  const PhysicalObject* top = nullptr;
  for (const PhysicalObject& o : scan->scene.objects) {
    ASSERT_FALSE(o.primitives.empty()) << o.id;
    EXPECT_EQ(o.primitives[0].kind, ShapeKind::cylinder) << o.id;
    (o.on_object.empty() ? lower : top) = &o;
  }
  ASSERT_TRUE(lower && top);
  EXPECT_EQ(top->on_object, lower->id);
  EXPECT_NEAR(lower->primitives[0].dimensions_m[0], lower_r, 0.005);
  EXPECT_NEAR(lower->primitives[0].dimensions_m[1], lower_h, 0.015);
  EXPECT_NEAR(top->primitives[0].dimensions_m[0], upper_r, 0.005);
  EXPECT_NEAR(top->primitives[0].dimensions_m[1], upper_h, 0.015);
  ScanParams without;
  without.segment.level_cut = false;
  Result<ScanResult> by_outline = scan_frame(frame, without);
  ASSERT_TRUE(by_outline.ok()) << by_outline.error().format();
  EXPECT_EQ(by_outline->scene.objects.size(), 2u);
  without.touching_width_step = false;
  Result<ScanResult> merged = scan_frame(frame, without);
  ASSERT_TRUE(merged.ok()) << merged.error().format();
  EXPECT_EQ(merged->scene.objects.size(), 1u);
}

// OSD learning scenes: the scan with default parameters against the labels.
std::optional<OsdSceneScore> score_scene(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(ANNEX_SHARED_DIR) / "data/osd-learn";
  if (!std::filesystem::exists(dir / (name + "_depth.png"))) return std::nullopt;
  Result<OsdScene> scene = read_osd_scene(dir, name);
  EXPECT_TRUE(scene.ok()) << scene.error().format();
  if (!scene) return std::nullopt;
  Result<OsdExpectations> expect =
      read_osd_expectations_file(std::filesystem::path(ANNEX_SOURCE_DIR) / "bench/osd_expectations.txt");
  EXPECT_TRUE(expect.ok()) << expect.error().format();
  if (!expect) return std::nullopt;
  Result<ScanResult> scan = scan_frame(scene->frame);
  EXPECT_TRUE(scan.ok()) << scan.error().format();
  if (!scan) return std::nullopt;
  return score_osd_scene(*scene, *scan, *expect);
}

void expect_all_whole(const std::string& name, int objects) {
  const auto s = score_scene(name);
  if (!s) GTEST_SKIP() << "../shared/data/osd-learn is absent: OSD test skipped";
  EXPECT_EQ(s->labelled, objects) << name;
  EXPECT_EQ(s->found, objects) << name;
  EXPECT_EQ(s->merges, 0) << name;
  for (const OsdObjectScore& o : s->objects)
    if (o.expected != "frustum") EXPECT_TRUE(o.shape_ok) << name << " object " << o.id << " " << o.reported;
}

TEST(ClutterOsd, BoxStandingOnABoxIsTwoBoxes) { expect_all_whole("learn20", 2); }
TEST(ClutterOsd, ThreeStackedBoxesAreThreeBoxes) { expect_all_whole("learn22", 3); }
TEST(ClutterOsd, BoxLeaningOnABoxIsTwoBoxes) { expect_all_whole("learn25", 2); }
TEST(ClutterOsd, JarOnATinIsTwoCylinders) { expect_all_whole("learn42", 2); }
TEST(ClutterOsd, CanLyingOnTheTableIsACylinder) { expect_all_whole("learn43", 3); }
// The free-space test (a solid cannot be seen through) on real bodies that first broke it:
// the table under a box overhanging the box it stands on (learn18, learn21), a pot's inner
// floor and the table behind a dome's rounded top (learn37, learn38, learn40).
TEST(ClutterOsd, BoxOverhangingTheBoxUnderItIsStillABox) {
  expect_all_whole("learn18", 2);
  expect_all_whole("learn21", 3);
}
TEST(ClutterOsd, PotsBowlsAndDomesKeepTheirShapes) {
  expect_all_whole("learn37", 3);
  expect_all_whole("learn38", 4);
  expect_all_whole("learn40", 3);
}
// The box behind a standing can shows either side of it: one box, not two pieces.
TEST(ClutterOsd, BoxSeenEitherSideOfACanIsOneBox) {
  expect_all_whole("learn31", 2);
  const auto s = score_scene("learn31");
  if (s) EXPECT_EQ(s->fragments, 0);
}
// learn28's box behind a standing box: its two pieces' front faces lie on one line 18 cm
// long, which the side normals alone set about 2 degrees off (the joint box's azimuth
// fuses the faces' lines with the normals by their noise): one box, not two pieces.
TEST(ClutterOsd, BoxSeenEitherSideOfABoxIsOneBox) {
  expect_all_whole("learn28", 2);
  const auto s = score_scene("learn28");
  if (s) {
    EXPECT_EQ(s->fragments, 0);
    EXPECT_EQ(s->reported, 2);
  }
}
// The can lying behind a box shows either side of it: one cylinder, not two pieces
// (the pixels of its hidden middle's edges that no cluster kept do not part them).
TEST(ClutterOsd, CanLyingBehindABoxIsOneCylinder) {
  for (const char* name : {"learn30", "learn32"}) {
    const auto s = score_scene(name);
    if (!s) GTEST_SKIP() << "../shared/data/osd-learn is absent: OSD test skipped";
    EXPECT_EQ(s->found, 2) << name;
    EXPECT_EQ(s->fragments, 0) << name;
    EXPECT_EQ(s->reported, 2) << name;
    for (const OsdObjectScore& o : s->objects)
      EXPECT_TRUE(o.shape_ok) << name << " object " << o.id << " " << o.reported;
  }
}

// The upper box of learn20 and the jar of learn42 stand on the lower object's top: their
// primitives start there, not at the table.
void expect_one_on_top(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(ANNEX_SHARED_DIR) / "data/osd-learn";
  if (!std::filesystem::exists(dir / (name + "_depth.png")))
    GTEST_SKIP() << "../shared/data/osd-learn is absent: OSD test skipped";
  Result<OsdScene> scene = read_osd_scene(dir, name);
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  Result<ScanResult> scan = scan_frame(scene->frame);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  ASSERT_EQ(scan->scene.objects.size(), 2u);
  std::vector<double> bottoms, tops;
  for (const PhysicalObject& o : scan->scene.objects) {
    ASSERT_FALSE(o.primitives.empty());
    const PhysicalPrimitive& p = o.primitives[0];
    const double h = p.dimensions_m.back();
    const double mid = dot(scan->plane.normal, p.center) + scan->plane.d;
    bottoms.push_back(mid - h / 2);
    tops.push_back(mid + h / 2);
  }
  const size_t upper = bottoms[0] > bottoms[1] ? 0 : 1, lower = 1 - upper;
  EXPECT_LT(bottoms[lower], 0.01) << name;  // on the table
  EXPECT_NEAR(bottoms[upper], tops[lower], 0.015) << name;  // on the lower object's top
  // Both report the table as their support; the upper one names the object it stands on.
  const std::vector<PhysicalObject>& objs = scan->scene.objects;
  EXPECT_EQ(objs[upper].on_object, objs[lower].id) << name;
  EXPECT_EQ(scan->clusters[upper].on_object, static_cast<int>(lower)) << name;
  EXPECT_TRUE(objs[lower].on_object.empty()) << name;
  EXPECT_EQ(objs[upper].support_id, objs[lower].support_id) << name;
}

// Three boxes, each on the one below (learn22): the stack is a chain of on_object links
// down to one box on the table.
TEST(ClutterOsd, StackOfThreeNamesEachLowerBox) {
  const std::filesystem::path dir = std::filesystem::path(ANNEX_SHARED_DIR) / "data/osd-learn";
  if (!std::filesystem::exists(dir / "learn22_depth.png"))
    GTEST_SKIP() << "../shared/data/osd-learn is absent: OSD test skipped";
  Result<OsdScene> scene = read_osd_scene(dir, "learn22");
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  Result<ScanResult> scan = scan_frame(scene->frame);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  ASSERT_EQ(scan->scene.objects.size(), 3u);
  int on_table = 0, stacked = 0;
  std::map<std::string, double> base;
  for (const PhysicalObject& o : scan->scene.objects) {
    const PhysicalPrimitive& p = o.primitives.at(0);
    base[o.id] = dot(scan->plane.normal, p.center) + scan->plane.d - p.dimensions_m.back() / 2;
  }
  for (const PhysicalObject& o : scan->scene.objects) {
    if (o.on_object.empty()) {
      ++on_table;
      continue;
    }
    ++stacked;
    ASSERT_TRUE(base.count(o.on_object)) << o.on_object;
    EXPECT_GT(base[o.id], base[o.on_object] + 0.03) << o.id << " on " << o.on_object;
  }
  EXPECT_EQ(on_table, 1);
  EXPECT_EQ(stacked, 2);
}

// learn34, 37, 38: a cookie tin on its edge, lid to the camera, among bowls and a pot.
TEST(ClutterOsd, TinsOnTheirEdgeAreCylinders) {
  for (const char* name : {"learn34", "learn37", "learn38"}) {
    const auto s = score_scene(name);
    if (!s) GTEST_SKIP() << "../shared/data/osd-learn is absent: OSD test skipped";
    EXPECT_EQ(s->merges, 0) << name;
    for (const OsdObjectScore& o : s->objects)
      if (o.expected == "cylinder") EXPECT_TRUE(o.shape_ok) << name << " object " << o.id << " " << o.reported;
  }
}
// learn33-35: the bowl of each scene is a cone (a frustum), not a sphere; the other
// open containers are cones or cylinders.
TEST(ClutterOsd, BowlsAreFrustums) {
  for (const char* name : {"learn33", "learn34", "learn35"}) {
    const auto s = score_scene(name);
    if (!s) GTEST_SKIP() << "../shared/data/osd-learn is absent: OSD test skipped";
    int cones = 0;
    for (const OsdObjectScore& o : s->objects) {
      if (o.expected != "frustum") continue;
      EXPECT_TRUE(o.reported == "cone" || o.reported == "cylinder") << name << " object " << o.id << " " << o.reported;
      cones += o.reported == "cone";
    }
    EXPECT_GE(cones, 1) << name;
  }
}

// learn36-38: the pot with handles is a cylinder (or a cone) of its body, not unknown;
// its body is about 17 cm across.
TEST(ClutterOsd, PotWithHandlesIsItsBody) {
  for (const char* name : {"learn36", "learn37", "learn38"}) {
    const auto s = score_scene(name);
    if (!s) GTEST_SKIP() << "../shared/data/osd-learn is absent: OSD test skipped";
    int pots = 0;
    for (const OsdObjectScore& o : s->objects) {
      if (o.expected != "frustum" || o.reported == "cone") continue;
      EXPECT_EQ(o.reported, "cylinder") << name << " object " << o.id;
      ++pots;
    }
    EXPECT_EQ(pots, 1) << name;
  }
}

TEST(ClutterOsd, UpperBoxStandsOnTheLowerBoxTop) { expect_one_on_top("learn20"); }
TEST(ClutterOsd, JarStandsOnTheTinTop) { expect_one_on_top("learn42"); }

// learn17's case drawn by hand: the lower box is a ring round the upper one, and the
// labels give the upper box the crease pixels along its lower edge, which the reported
// ring holds. Its points' mean lies on the upper box and its own pixel nearest that mean
// on those crease pixels; its most interior pixel lies on the lower box.
TEST(OsdEvaluator, CentreOfARingLiesInsideTheRingNotOnItsInnerEdge) {
  const CameraIntrinsics k;
  OsdScene scene;
  scene.name = "ring";
  scene.frame.width = k.width;
  scene.frame.height = k.height;
  scene.object_of_pixel.assign(static_cast<size_t>(k.width) * k.height, 0);
  ScanCluster ring;
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      PointXYZRGB p;
      p.z = 1.0f;
      p.x = static_cast<float>((u - k.cx) / k.fx);
      p.y = static_cast<float>((v - k.cy) / k.fy);
      scene.frame.points.push_back(p);
      const int i = v * k.width + u;
      const bool upper = u >= 300 && u < 340 && v >= 200 && v < 240;
      const bool lower = u >= 280 && u < 360 && v >= 180 && v < 265 && !upper;
      if (upper) scene.object_of_pixel[i] = 3;
      if (lower) scene.object_of_pixel[i] = 2;
      if (lower || (upper && v == 239)) ring.pixels.push_back(i);
      if (upper || lower) ++scene.labelled_points[scene.object_of_pixel[i]];
    }
  ScanResult scan;
  scan.clusters.push_back(ring);
  const OsdExpectations expect;
  const OsdSceneScore score = score_osd_scene(scene, scan, expect);
  ASSERT_EQ(score.objects.size(), 2u);
  EXPECT_TRUE(score.objects[0].found) << score.notes[0];   // object 2, the ring
  EXPECT_FALSE(score.objects[1].found) << score.notes[0];  // object 3, not reported
  EXPECT_EQ(score.whole, 1);
  EXPECT_EQ(score.fragments, 0);
}

TEST(OsdExpectations, ErrorsNameLineAndColumn) {
  auto bad = parse_osd_expectations("learn1 2 box\nlearn1 x box\n", "e.txt");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().location.line, 2);
  EXPECT_EQ(bad.error().location.column, 8);
  bad = parse_osd_expectations("learn1 2 sphere\n", "e.txt");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().location.column, 10);
  bad = parse_osd_expectations("learn1 2 box\nlearn1 2 box # again\n", "e.txt");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().location.line, 2);
  const auto good = parse_osd_expectations("# c\nlearn1 2 box\n\nlearn1 3 cylinder", "e.txt");
  ASSERT_TRUE(good.ok());
  EXPECT_EQ(good->class_of("learn1", 3), "cylinder");
  EXPECT_EQ(good->class_of("learn1", 4), "any");
}

// Grown objects are fitted again beside the label's rebuild and the pieces that joining
// occluded pieces reads (scanner.cpp: one pass of independent items): learn28's and
// learn31's boxes, joined from two pieces (the scene differs with the join off), scan
// the same on one, two and three threads, bit for bit.
TEST(ClutterOsd, JoinedPiecesScanTheSameOnOneTwoAndThreeThreads) {
  const std::filesystem::path dir = std::filesystem::path(ANNEX_SHARED_DIR) / "data/osd-learn";
  if (!std::filesystem::exists(dir / "learn28_depth.png"))
    GTEST_SKIP() << "../shared/data/osd-learn is absent: OSD test skipped";
  for (const std::string name : {"learn28", "learn31"}) {
    Result<OsdScene> scene = read_osd_scene(dir, name);
    ASSERT_TRUE(scene.ok()) << scene.error().format();
    ScanParams one;
    one.threads = 1;
    const Result<ScanResult> base = scan_frame(scene->frame, one);
    ASSERT_TRUE(base.ok()) << name << ": " << base.error().format();
    ScanParams apart = one;
    apart.join_occluded = false;
    const Result<ScanResult> pieces = scan_frame(scene->frame, apart);
    ASSERT_TRUE(pieces.ok()) << name << ": " << pieces.error().format();
    EXPECT_LT(base->scene.objects.size(), pieces->scene.objects.size()) << name;
    for (int threads : {2, 3}) {
      ScanParams p = one;
      p.threads = threads;
      const Result<ScanResult> r = scan_frame(scene->frame, p);
      ASSERT_TRUE(r.ok()) << name << ": " << r.error().format();
      EXPECT_TRUE(r->scene == base->scene) << name << ", threads " << threads;
      ASSERT_EQ(r->clusters.size(), base->clusters.size()) << name << ", threads " << threads;
      for (size_t c = 0; c < r->clusters.size(); ++c) {
        EXPECT_EQ(r->clusters[c].pixels, base->clusters[c].pixels) << name << ", object " << c;
        const auto& a = r->clusters[c].points;
        const auto& b = base->clusters[c].points;
        EXPECT_TRUE(a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0))
            << name << ", threads " << threads << ", object " << c;
      }
    }
  }
}

}  // namespace
}  // namespace annex
