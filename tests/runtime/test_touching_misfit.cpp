// Two touching bodies that differ in size under one primitive: the two means of their
// footprint halve the larger, and neither half is explained; the cut along what the one
// primitive leaves out parts them (touching_split.h, ScanParams::touching_misfit_cut).
// One object's misfit refitted apart gives two solids round one axis, which no two
// bodies side by side are. Which clusters are tried (ScanParams::touching_max_coverage)
// and how well each part must be explained (touching_part_coverage) are two questions.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <utility>

#include "annex/runtime/pcd_io.h"
#include "annex/runtime/scanner.h"
#include "room_scan.h"
#include "touching_split.h"

namespace annex {
namespace {

const std::filesystem::path kRealDir = std::filesystem::path(ANNEX_SHARED_DIR) / "data" / "real";

// The room's object for which `is` holds and the one it touches (the object it was
// placed touching, or the one placed touching it); -1 for either when the generator no
// longer makes them.
template <typename Is>
std::pair<int, int> touching_pair(std::uint64_t seed, const SyntheticScene& scene, Is is) {
  const int t = find_object(scene, is);
  EXPECT_GE(t, 0) << "the generator no longer puts the object in " << seed;
  if (t < 0) return {-1, -1};
  int other = scene.objects[static_cast<std::size_t>(t)].touching;
  if (other < 0)
    other = find_object(scene, [&](const SyntheticObject& o) { return o.touching == t; });
  EXPECT_GE(other, 0) << seed << ": the object no longer touches another";
  return {t, other};
}

// Whether the scanned object of truth object k is one of its own kind.
bool found_as_itself(const RoomScan& r, int k) {
  const auto& got = r.of[static_cast<std::size_t>(k)];
  return got && !got->primitives.empty() &&
         got->primitives[0].kind == r.scene.objects[static_cast<std::size_t>(k)].kind;
}

// Whether the room's touching pair holding an object for which `is` holds is found as two
// objects, each of its own kind; when `misfit_needed`, not with the means' cut alone.
template <typename Is>
void expect_pair_apart(std::uint64_t seed, Is is, bool misfit_needed = true) {
  ScanParams means_only;
  means_only.touching_misfit_cut = false;
  const RoomScan r = scan_room(seed, ScanParams{});
  const auto [t, other] = touching_pair(seed, r.scene, is);
  ASSERT_GE(t, 0);
  ASSERT_GE(other, 0);
  for (const int k : {t, other}) EXPECT_TRUE(found_as_itself(r, k)) << seed << " object " << k;
  if (!misfit_needed) return;
  // With the means' cut alone, one of the two is no object's own.
  const RoomScan merged = scan_room(seed, means_only);
  EXPECT_TRUE(!merged.of[static_cast<std::size_t>(t)] ||
              !merged.of[static_cast<std::size_t>(other)])
      << seed;
}

// The room's touching pair holding an object for which `is` holds, scanned with
// `params`: whether both are found, each as an object of its own kind.
template <typename Is>
bool pair_found_apart(std::uint64_t seed, const ScanParams& params, Is is) {
  const RoomScan r = scan_room(seed, params);
  const auto [t, other] = touching_pair(seed, r.scene, is);
  return t >= 0 && other >= 0 && found_as_itself(r, t) && found_as_itself(r, other);
}

TEST(TouchingMisfit, AFlatBowlAgainstABoxIsTwoObjects) {
  // Fresh rooms 9571 (session 33): a flat bowl 1.35 m away against a box of twice its
  // pixels; the box alone explains 70 % of the cluster.
  expect_pair_apart(9571u, [](const SyntheticObject& o) {
    return o.kind == ShapeKind::cone && o.dimensions_m.at(0) > 2 * o.dimensions_m.at(1);
  });
}

TEST(TouchingMisfit, ABallAgainstARingIsTwoObjects) {
  // Fresh rooms 9514: a ball 1.76 m away against a ring lying flat; one cylinder over
  // both explained 68 %, and the cut along its misfit parted them. Since session 44 a
  // cylinder lying across both explains 78 %, its misfit all on the ring's side, and the
  // means' cut parts them; the ring's part holds a strip of the ball's edge, 10 cm above
  // the ring's top, which the ring's torus leaves out (kTorusOwnHeight).
  expect_pair_apart(
      9514u,
      [](const SyntheticObject& o) {
        return o.kind == ShapeKind::sphere && o.dimensions_m.at(0) > 0.07;
      },
      false);
}

TEST(TouchingMisfit, OneBowlPoorlyFittedStaysOneObject) {
  // Rooms 5026: a flat bowl 0.98 m away, its cone explaining 64 %. Cut along its misfit,
  // its two parts were a cone and a cylinder round one axis, 0.5 cm apart: one object.
  const RoomScan r = scan_room(5026u, ScanParams{});
  const int t = find_object(r.scene, [](const SyntheticObject& o) {
    return o.kind == ShapeKind::cone && o.dimensions_m.at(0) > 0.1;
  });
  ASSERT_GE(t, 0) << "the generator no longer puts the flat bowl in 5026";
  EXPECT_EQ(r.pieces[static_cast<std::size_t>(t)], 1);
  const auto& got = r.of[static_cast<std::size_t>(t)];
  ASSERT_TRUE(got.has_value());
  ASSERT_FALSE(got->primitives.empty());
  EXPECT_EQ(got->primitives[0].kind, ShapeKind::cone);
}

// The gate asking no cluster for two feet (ScanParams::touching_two_feet_coverage): every
// cluster under 0.85 is tried, as a user may set at the cost of the refits.
ScanParams wider_gate() {
  ScanParams p;
  p.touching_two_feet_coverage = 1;
  return p;
}

// The gate before session 37: clusters under 0.8 tried, all of them.
ScanParams old_gate() {
  ScanParams p;
  p.touching_max_coverage = 0.8;
  p.touching_two_feet_coverage = 1;
  return p;
}

// The first object of a room placed touching another.
bool placed_touching(const SyntheticObject& o) {
  return o.touching >= 0;
}

TEST(TouchingGate, TwoBodiesUnderTheWiderGateStandOnTwoFeet) {
  // Touching pairs 2.2 to 2.6 m away that one primitive explains at 0.80 to 0.85 (rooms
  // 5061, fresh rooms 9748, 10092; 10010 is the fourth over the sets, its room's first
  // pair another one). The gate of 0.8 never tried them; under 0.85 a cluster explained
  // that well is tried when it stands on two feet, and each pair is two objects of their
  // own kinds. Fresh rooms 8084's pair, 2.95 m away, recedes between its means by 0.7
  // sigma only (its foot seen in two pieces: AFootSeenInTwoPiecesStandsOnTwoFeet).
  // 9748's pair (a ball against a tin 2.4 m away) with its circle as fitted then: at its
  // points' own scatter (session 42) the tin's circle is its own, one cylinder explains
  // the pair at 0.81 with the ball left out, and the information criterion prefers one
  // body, narrowly (20.4 against two bodies' 20.9): one object.
  ScanParams circle_then;
  circle_then.shape.circle_own_scatter = false;
  for (const std::uint64_t seed : {5061u, 9748u, 10092u}) {
    const ScanParams base = seed == 9748u ? circle_then : ScanParams{};
    ScanParams old = old_gate();
    old.shape.circle_own_scatter = base.shape.circle_own_scatter;
    EXPECT_TRUE(pair_found_apart(seed, base, placed_touching)) << seed;
    EXPECT_FALSE(pair_found_apart(seed, old, placed_touching)) << seed;
  }
}

TEST(TouchingGate, AFootSeenInTwoPiecesStandsOnTwoFeet) {
  // Fresh rooms 8084: a ball against a tin 2.95 m away, one sphere over both explaining
  // 0.83. Its front recedes between the means by 0.7 sigma only, but no point of its
  // foot lies in the middle six of the sixteen bins between them, where its sampling
  // (twelve points a bin) leaves one empty by chance at e^-12: two feet, and two objects.
  // Without the gap's evidence it is not tried and stays one.
  const auto ball = [](const SyntheticObject& o) { return o.kind == ShapeKind::sphere; };
  EXPECT_TRUE(pair_found_apart(8084u, ScanParams{}, ball));
  ScanParams notch_alone;
  notch_alone.touching_gap_evidence = 0;
  EXPECT_FALSE(pair_found_apart(8084u, notch_alone, ball));
}

TEST(TouchingGate, ABottleWithAHandleStandsOnOneFoot) {
  // The real milk frame's detergent bottle: one cylinder explains 0.85 of it (its handle
  // and the veil at its edges are the rest). Its foot, seen as a ring's front arc, narrows
  // between the means, but its front is one arc: it is not tried, and its refits would
  // double the scan's shapes stage.
  const Result<Frame> frame = read_pcd(kRealDir / "milk_cartoon_all_small_clorox.pcd");
  if (!frame) GTEST_SKIP() << "../shared/data/real is absent: real-frame test skipped";
  const Result<ScanResult> scan = scan_frame(*frame);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  const ScanCluster* bottle = nullptr;
  for (const ScanCluster& c : scan->clusters)
    if (!c.shape.primitives.empty() && c.shape.primitives[0].coverage >= 0.8 &&
        (!bottle || c.pixels.size() > bottle->pixels.size()))
      bottle = &c;
  ASSERT_NE(bottle, nullptr);
  ASSERT_GT(bottle->pixels.size(), 10000u) << "the bottle is no longer the frame's largest cluster";
  EXPECT_LT(bottle->shape.primitives[0].coverage, 0.85);
  EXPECT_FALSE(stands_on_two_feet(*frame, *bottle));
  // It is the notch that tells: the bottle's foot narrows between the means, and its
  // front's wobble (0.7 sigma) passes a notch of a quarter sigma.
  TouchingSplitParams fine;
  fine.notch_sigmas = 0.25;
  EXPECT_TRUE(stands_on_two_feet(*frame, *bottle, fine));
}

TEST(TouchingGate, ARingAgainstAFlatBowlShowingNoFootIsTried) {
  // Fresh rooms 9507 (session 35): a ring lying flat against a flat bowl 1.1 m away, no
  // crease between them; one box over both explains 84 %, which the gate of 0.8 never
  // tries to cut. Seen from above, neither shows a point in the lowest quarter of the
  // cluster's height (the bowl narrows under its rim, the ring bulges over its foot):
  // with no foot seen nothing tells one body from two, and since session 38 the cluster
  // is tried and parted, as a gate asking no cluster for two feet parts it.
  const auto ring = [](const SyntheticObject& o) { return o.kind == ShapeKind::torus; };
  EXPECT_TRUE(pair_found_apart(9507u, wider_gate(), ring));
  EXPECT_TRUE(pair_found_apart(9507u, ScanParams{}, ring));
  EXPECT_FALSE(pair_found_apart(9507u, old_gate(), ring));
}

TEST(TouchingGate, APartIsJudgedByItsOwnThresholdNotTheGates) {
  // Unseen rooms 7036: a dark cup against a flat bowl 1.3 m away, cut in two; the cup's
  // own cone explains 84 % of its part. With the wider gate also asked of the parts, the
  // cut is refused and the two are one object of no shape.
  const auto cup = [](const SyntheticObject& o) {
    return o.kind == ShapeKind::cone && o.dimensions_m.at(1) > 0.15;
  };
  EXPECT_TRUE(pair_found_apart(7036u, wider_gate(), cup));
  ScanParams gate_for_parts = wider_gate();
  gate_for_parts.touching_part_coverage = gate_for_parts.touching_max_coverage;
  EXPECT_FALSE(pair_found_apart(7036u, gate_for_parts, cup));
}

}  // namespace
}  // namespace annex
