// A cone flatter than 26 degrees (a wide lid, a flat lampshade) faces up as much as a
// top does: its side is then what lies below the top's height (shape_flat_cone_sides,
// object_shape_recognizer.cpp fit_cone). Fresh rooms 8014 and 8099: dark flat cones apex
// up, 10 to 11 cm in radius and 4.7 to 7.7 cm tall, 1.1 to 1.2 m away, had no cone
// candidate and came out unknown (8099 since session 17: its cone ran off, see below).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "annex/runtime/scanner.h"
#include "annex/runtime/synthetic_scene.h"
#include "label_owner.h"
#include "room_scan.h"
#include "scan_one.h"

namespace annex {
namespace {

struct View {
  SyntheticObject object;
  double distance_m = 0, tilt_deg = 0;
};

// How many of the views, each seen in scenes 1..n, read as `kind`.
int read_as(ShapeKind kind, const std::vector<View>& views, int n, bool flat_cone_sides) {
  ScanParams params;
  params.shape.flat_cone_sides = flat_cone_sides;
  int right = 0;
  for (const View& v : views)
    for (int seed = 1; seed <= n; ++seed) {
      const std::optional<PhysicalObject> o =
          scan_one(v.object, v.distance_m, v.tilt_deg, static_cast<std::uint64_t>(seed), params);
      right += o && !o->primitives.empty() && o->primitives[0].kind == kind;
    }
  return right;
}

SyntheticObject shape(ShapeKind kind, std::vector<double> dimensions_m) {
  return resting_object(kind, std::move(dimensions_m), 0, 0);
}

TEST(ShapeFlatCone, AConeFlatterThanTheSideTestIsACone) {
  // Sides rising 17 and 18 degrees, 0.8 m away, seen from 25 and 45 degrees above: its
  // normals lie 72 degrees and more from the side's test.
  constexpr int kScenes = 3;
  const std::vector<View> views{{shape(ShapeKind::cone, {0.12, 0.04}), 0.8, 25},
                                {shape(ShapeKind::cone, {0.12, 0.04}), 0.8, 45},
                                {shape(ShapeKind::cone, {0.10, 0.03}), 0.8, 45}};
  EXPECT_GE(read_as(ShapeKind::cone, views, kScenes, true), 3 * kScenes - 1);
  EXPECT_LE(read_as(ShapeKind::cone, views, kScenes, false), 1);
}

// What a fresh room's dark flat cone (apex up, 10 cm or more in radius, flatter than it is
// wide) reads as, with flat cone sides on or off: its shape's name, "unknown" when no
// shape fits it, "missed" when no scanned object shows it; `got` receives the object.
std::string dark_flat_cone(std::uint64_t seed, bool flat_cone_sides,
                           PhysicalObject* got = nullptr) {
  const Result<SyntheticScene> s = generate_scene(room_scene_params(seed));
  EXPECT_TRUE(s.ok());
  if (!s) return "missed";
  const SyntheticFrame f = render_scene(*s);
  ScanParams params;
  params.shape.flat_cone_sides = flat_cone_sides;
  // The supports as they were found then, one plane for all of a height's regions: 8014's
  // table fitted on its own pixels (support_fit_sigmas, session 18) makes it a cone
  // without flat cone sides too.
  params.support_fit_sigmas = 0;
  const Result<ScanResult> scan = scan_frame(f.frame, params);
  EXPECT_TRUE(scan.ok());
  if (!scan) return "missed";
  for (std::size_t k = 0; k < scan->clusters.size(); ++k) {
    const int t = majority_label(f, scan->clusters[k]);
    if (t < 0) continue;
    const SyntheticObject& truth = s->objects[static_cast<std::size_t>(t)];
    if (truth.kind != ShapeKind::cone || truth.apex_down || truth.dimensions_m[0] < 0.1 ||
        truth.dimensions_m[1] > 2 * truth.dimensions_m[0])
      continue;
    const PhysicalObject& o = scan->scene.objects[k];
    if (got) *got = o;
    return o.primitives.empty() ? "unknown" : std::string(shape_name(o.primitives[0].kind));
  }
  return "missed";
}

TEST(ShapeFlatCone, ADarkFlatConeWithoutASideForTheCylinderIsACone) {
  // Fresh room 8014 (apex up, r 10.3 cm, 4.7 cm tall, 1.08 m away): its dark side returns
  // in patches and faces up; the upright cylinder, the cone's start, found no side and a
  // circle 2.3 m wide, so no cone was tried and it came out unknown. The footprint's
  // outline gives the axis.
  EXPECT_EQ(dark_flat_cone(8014, true), "cone");
  EXPECT_EQ(dark_flat_cone(8014, false), "unknown");
}

TEST(ShapeFlatCone, AFlatConeWhoseFitRunsOffStartsAgainFromItsFootprint) {
  // Fresh room 8099 (session 17; apex up, r 11.0 cm, 7.7 cm tall, 1.19 m away, dark):
  // the upright cylinder read its side as one of r 16.6 cm, and the cone started from it
  // ran off to a radius of 5.5 m whose arc follows the side, past any prop: no cone, and
  // the object came out unknown. Such a run-off starts again from the footprint's circle.
  PhysicalObject got;
  EXPECT_EQ(dark_flat_cone(8099, true, &got), "cone");
  ASSERT_FALSE(got.primitives.empty());
  EXPECT_NEAR(got.primitives[0].dimensions_m[0], 0.110, 0.005);
  EXPECT_NEAR(got.primitives[0].dimensions_m[1], 0.077, 0.005);
}

TEST(ShapeFlatCone, AFlatTinAndAFlatBoxStayWhatTheyAre) {
  // As wide and as tall: their sides stand upright, their tops alone face up.
  constexpr int kScenes = 3;
  const std::vector<View> tins{{shape(ShapeKind::cylinder, {0.12, 0.04}), 0.8, 25},
                               {shape(ShapeKind::cylinder, {0.10, 0.03}), 0.8, 45}};
  const std::vector<View> boxes{{shape(ShapeKind::box, {0.24, 0.24, 0.04}), 0.8, 25},
                                {shape(ShapeKind::box, {0.2, 0.2, 0.03}), 0.8, 45}};
  EXPECT_EQ(read_as(ShapeKind::cylinder, tins, kScenes, true), 2 * kScenes);
  EXPECT_EQ(read_as(ShapeKind::box, boxes, kScenes, true), 2 * kScenes);
}

// Truth cones widening upward (bowls, frustums apex down) 1.5 to 2.5 m deep in each
// seed's scene (rooms or world_scene_params), and how many of them read as cones.
struct Bowls {
  int seen = 0, cones = 0;
};
Bowls bowls_read_as_cones(const std::vector<std::pair<std::uint64_t, bool>>& seeds,
                          const ScanParams& params) {
  Bowls b;
  for (const auto& [seed, rooms] : seeds) {
    const Result<SyntheticScene> s =
        generate_scene(rooms ? room_scene_params(seed) : world_scene_params(seed));
    EXPECT_TRUE(s.ok()) << seed;
    if (!s) continue;
    const SyntheticFrame f = render_scene(*s);
    const Result<ScanResult> scan = scan_frame(f.frame, params);
    EXPECT_TRUE(scan.ok()) << seed;
    if (!scan) continue;
    for (std::size_t k = 0; k < scan->clusters.size(); ++k) {
      const int t = majority_label(f, scan->clusters[k]);
      if (t < 0 || scan->scene.objects[k].partial) continue;
      const SyntheticObject& truth = s->objects[static_cast<std::size_t>(t)];
      const double z = table_to_camera_point(*s, truth.center).z;
      if (truth.kind != ShapeKind::cone || !truth.apex_down || z < 1.5 || z > 2.5) continue;
      ++b.seen;
      const PhysicalObject& o = scan->scene.objects[k];
      b.cones += !o.primitives.empty() && o.primitives[0].kind == ShapeKind::cone;
    }
  }
  return b;
}

TEST(ShapeLid, ABowlsTopIsItsLidNotItsNoisiestPoints) {
  // Held-out 5045, unseen 3026, fresh rooms 8029 and 9564 (session 34): bowls and
  // frustums widening up, 1.5 to 2.4 m away, read as cylinders. The cylinder's top was
  // its side's 98 % height, which the noise lifts above the rim, and the cone's its
  // points' 99 %: on a flat bowl those tops miss the lid by a centimetre. The lid's
  // median height, the cap flat to the noise, sets both (shape_lid_spread_sigmas).
  const std::vector<std::pair<std::uint64_t, bool>> seeds{
      {5045u, false}, {3026u, false}, {8029u, true}, {9564u, true}};
  ScanParams off;
  off.shape.lid_spread_sigmas = 0;
  const Bowls on_b = bowls_read_as_cones(seeds, ScanParams{});
  const Bowls off_b = bowls_read_as_cones(seeds, off);
  EXPECT_EQ(on_b.seen, off_b.seen);
  EXPECT_GE(on_b.seen, 3);  // 9564's bowl lies at 1.5 m range, nearer along the axis
  EXPECT_EQ(on_b.cones, on_b.seen);
  EXPECT_EQ(off_b.cones, 0);
}

TEST(ShapeLid, AFlatTinsHeightIsItsLids) {
  // A tin 10 cm in radius and 4 cm tall, 2.4 m away seen from 30 degrees above: its
  // height within 3 mm, where the side's 98 % height overshoots by about twice the noise.
  constexpr int kScenes = 5;
  ScanParams off;
  off.shape.lid_spread_sigmas = 0;
  double on_error = 0, off_error = 0;
  for (int seed = 1; seed <= kScenes; ++seed) {
    const SyntheticObject tin = shape(ShapeKind::cylinder, {0.10, 0.04});
    const std::optional<PhysicalObject> on =
        scan_one(tin, 2.4, 30, static_cast<std::uint64_t>(seed), ScanParams{});
    const std::optional<PhysicalObject> without =
        scan_one(tin, 2.4, 30, static_cast<std::uint64_t>(seed), off);
    ASSERT_TRUE(on && !on->primitives.empty() && without && !without->primitives.empty());
    ASSERT_EQ(on->primitives[0].kind, ShapeKind::cylinder) << seed;
    on_error += std::abs(on->primitives[0].dimensions_m[1] - 0.04) / kScenes;
    off_error += std::abs(without->primitives[0].dimensions_m[1] - 0.04) / kScenes;
  }
  EXPECT_LT(on_error, 0.003);
  EXPECT_LT(on_error, off_error);
}

TEST(ShapeLid, ABowlTheConeExplainsWholeIsNoBodyWithANeck) {
  // Fresh rooms 9882 (session 34): a bowl 21 cm wide at its rim, 2.4 m away. Its cone
  // explains every point (rms 3.1 mm); the cylinder (86 %, rms 8 mm) with its rim fitted
  // as a bottle's neck (23 %) summed 109 % and won as a pair. A pair covers at most all
  // of the points.
  const RoomScan r = scan_room(9882u, ScanParams{});
  const int t = find_object(r.scene, [](const SyntheticObject& o) {
    return o.kind == ShapeKind::cone && o.apex_down && std::abs(o.dimensions_m[0] - 0.107) < 0.001;
  });
  ASSERT_GE(t, 0);
  const std::optional<PhysicalObject>& o = r.of[static_cast<std::size_t>(t)];
  ASSERT_TRUE(o && !o->primitives.empty());
  EXPECT_EQ(o->primitives[0].kind, ShapeKind::cone);
  EXPECT_EQ(o->primitives.size(), 1u);
}

}  // namespace
}  // namespace annex
