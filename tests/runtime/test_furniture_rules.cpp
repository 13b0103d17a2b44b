// The furniture rules (runtime/src/furniture_rules.h, docs/perception.md "Every support
// surface") on seeded generated rooms: each case is a false prop the scanner reported
// before the rule, checked with the rule on (gone, and no true object lost) and off
// (back), so the test fails without the rule.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>
#include <set>
#include <string>

#include "annex/runtime/scanner.h"
#include "annex/runtime/synthetic_scene.h"
#include "label_owner.h"

namespace annex {
namespace {

// The defaults with the rules that flag partial (a top hidden by anything nearer, one
// upright face) off: several rules catch some of these cases, and each test shows what
// its own rule does on its own.
ScanParams alone() {
  ScanParams p;
  p.partial_when_top_hidden = false;
  p.panel_noise_factor = 0;
  // Nor cut in two as touching bodies (touching_split.h): with the rules off, a wall's
  // strip one primitive explains poorly is cut into two flat boxes.
  p.touching_max_coverage = 0;
  return p;
}

struct Seen {
  int whole = 0;  // objects reported whole (not partial) that are mostly `label`'s pixels
  int found = 0;  // truth objects, not cut by the border, that some scanned object shows
};

// `rooms`: room_scene_params (the held-out rooms) without the objects on the shelf's
// boards, as the rooms were when these cases were found; else world_scene_params. With
// those objects, the wall's slice in rooms 5073 and 7014 is no longer what the cut-top
// rule takes, and only the partial rules catch it (the bench's rooms figures count it).
Seen scan_seeds(const std::vector<std::uint64_t>& seeds, bool rooms, int label,
                const ScanParams& params) {
  Seen seen;
  for (std::uint64_t seed : seeds) {
    SyntheticSceneParams scene_params = rooms ? room_scene_params(seed) : world_scene_params(seed);
    if (rooms) scene_params.shelf_objects = 0;
    const Result<SyntheticScene> scene = generate_scene(scene_params);
    EXPECT_TRUE(scene.ok()) << "seed " << seed;
    if (!scene) continue;
    const SyntheticFrame f = render_scene(*scene);
    const Result<ScanResult> scan = scan_frame(f.frame, params);
    EXPECT_TRUE(scan.ok()) << "seed " << seed << ": " << (scan ? "" : scan.error().format());
    if (!scan) continue;
    std::set<int> shown;
    for (size_t k = 0; k < scan->clusters.size(); ++k) {
      const int owner = majority_label(f, scan->clusters[k]);
      if (owner == label && !scan->scene.objects[k].partial) ++seen.whole;
      if (owner >= 0 && !f.truth.objects[static_cast<size_t>(owner)].partial) shown.insert(owner);
    }
    seen.found += static_cast<int>(shown.size());
  }
  return seen;
}

// The rule that `with` has and `without` lacks takes every `label` object reported whole
// on `seeds` (at least `at_least` of them without it), and no true object with them.
void expect_rule_takes(const std::vector<std::uint64_t>& seeds, bool rooms, int label,
                       const ScanParams& with, const ScanParams& without, int at_least) {
  const Seen on = scan_seeds(seeds, rooms, label, with);
  const Seen off = scan_seeds(seeds, rooms, label, without);
  EXPECT_EQ(on.whole, 0) << "seed " << seeds.front() << ", label " << label;
  EXPECT_GE(off.whole, at_least) << "seed " << seeds.front() << ", label " << label;
  EXPECT_EQ(on.found, off.found) << "seed " << seeds.front() << ", label " << label;
}

TEST(FurnitureRules, AWardrobeCutByTheHeightBandIsNoProp) {
  // Held-out seeds 5005, 5009 and 5077 (a wardrobe 1.65 to 1.97 m tall beside the table,
  // 2.5 to 2.9 m away) and 3004 (unseen): the band cuts the wardrobe's front at 60 cm
  // and the slice came out as a box of 0.59 m. Its front runs on above the band in most
  // columns, but its rows, spaced 2 to 5 cm by the steep view and the noise, joined
  // their neighbours above fewer times than continues_above asks of a cluster that big
  // (a fiftieth of its pixels: the joins lie along its top edge only).
  const std::vector<std::uint64_t> seeds{5005u, 5009u, 5077u, 3004u};
  const ScanParams with = alone();
  ScanParams without = alone();
  without.cut_top_share = 0;
  expect_rule_takes(seeds, false, kLabelFurniture, with, without, 4);
}

TEST(FurnitureRules, AWallCutByTheHeightBandIsNoProp) {
  // Held-out rooms 5073 and unseen 7014: the wall behind a low table, its lower 60 cm in
  // the floor's band, came out as a box of 0.57 to 0.59 m.
  const std::vector<std::uint64_t> seeds{5073u, 7014u};
  const ScanParams with = alone();
  ScanParams without = alone();
  without.cut_top_share = 0;
  const Seen on = scan_seeds(seeds, true, kLabelWall, with);
  const Seen off = scan_seeds(seeds, true, kLabelWall, without);
  EXPECT_LT(on.whole, off.whole);
  EXPECT_EQ(on.found, off.found);
}

TEST(FurnitureRules, WhatANearTableTopHidesIsNoProp) {
  // Held-out seeds 5111 (a level camera 25 cm above a table 1 m away) and 5066 (the
  // same, 1.2 m away): a leg and the wall seen under the table, their tops hidden by
  // the table's top. Its front edge, 3 cm thick and 60 cm to 1 m from the camera, spans
  // eight to ten grid rows, more than the six the look-up for the top spanned: the leg
  // was a box of 0.27 m, the wall a strip 1.7 m wide reported whole.
  const ScanParams with = alone();
  ScanParams without = alone();
  without.support_edge_m = 0;
  expect_rule_takes({5111u}, false, kLabelLeg, with, without, 1);
  expect_rule_takes({5066u}, false, kLabelWall, with, without, 1);
}

TEST(FurnitureRules, WhatSomethingNearerHidesTheTopOfIsPartial) {
  // Held-out rooms 5073, 5100 and 5109: the wall seen under a shelf's lower board or
  // between a chair's seat and the table, its top against the nearer board or seat, came
  // out as boxes and lying cylinders 0.1 to 0.65 m long. Tuned seed 2033 and held-out
  // 5010: a cabinet's front under its top's nearer edge, whose top region is no support.
  // None of them shows where it ends.
  ScanParams with = alone();
  with.partial_when_top_hidden = true;
  const ScanParams without = alone();
  expect_rule_takes({5073u, 5100u, 5109u}, true, kLabelWall, with, without, 3);
  expect_rule_takes({2033u, 5010u}, false, kLabelFurniture, with, without, 2);
}

TEST(FurnitureRules, AChairsBackRisingBehindTheTableIsPartial) {
  // Held-out rooms 5037 and 5119, unseen 7021: a chair's back behind the table, seen
  // above the table's far edge, one flat face 0.2 to 0.46 m wide whose foot the table
  // hides, came out as a box 5 to 9 mm deep. A face whose foot is seen stays whole (the
  // laptop's lid, PlaneCandidates.APlanePrimitiveMatchesARealFlatSurface; the bins seen
  // face-on in nyu_basement).
  ScanParams with = alone();
  with.panel_noise_factor = ScanParams{}.panel_noise_factor;
  const ScanParams without = alone();
  expect_rule_takes({5037u, 5119u, 7021u}, true, kLabelChair, with, without, 3);
}

}  // namespace
}  // namespace annex
