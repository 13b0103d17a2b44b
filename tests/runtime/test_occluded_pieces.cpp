// Pieces of one object stand on one support (occlusion_join.h). Fresh rooms 9929: a box on
// the table 1 m from the camera, in front of a shelf 60 cm behind it, was joined with a
// piece of the shelf's side standing on the shelf's lower board, both read as boxes and
// the image between them covered: one box of 74 by 66 cm, partial, on the board.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "annex/runtime/scanner.h"
#include "room_scan.h"

namespace annex {
namespace {

TEST(OccludedPieces, PiecesOnTwoSupportsAreTwoObjects) {
  ScanParams apart;
  apart.join_occluded = false;
  for (const ScanParams& params : {ScanParams{}, apart}) {
    const RoomScan r = scan_room(9929u, params);
    const int t = find_object(r.scene, [](const SyntheticObject& o) {
      return o.kind == ShapeKind::box && o.support == 0 && o.dimensions_m.at(2) > 0.2;
    });
    ASSERT_GE(t, 0) << "the generator no longer puts the tall box on 9929's table";
    const auto& got = r.of[static_cast<std::size_t>(t)];
    ASSERT_TRUE(got.has_value()) << params.join_occluded;
    ASSERT_FALSE(got->primitives.empty());
    EXPECT_EQ(got->primitives[0].kind, ShapeKind::box);
    std::vector<double> truth = r.scene.objects[static_cast<std::size_t>(t)].dimensions_m;
    std::vector<double> seen = got->primitives[0].dimensions_m;
    std::sort(truth.begin(), truth.end());
    std::sort(seen.begin(), seen.end());
    ASSERT_EQ(seen.size(), truth.size());
    for (std::size_t k = 0; k < truth.size(); ++k) EXPECT_NEAR(seen[k], truth[k], 0.01) << k;
    EXPECT_FALSE(got->partial);
    // On the table: the truth's first support.
    const auto on =
        std::find_if(r.supports.begin(), r.supports.end(),
                     [&](const SupportSurface& sp) { return sp.id == got->support_id; });
    ASSERT_NE(on, r.supports.end());
    EXPECT_LT(std::abs(on->plane.d - r.truth.supports.at(0).plane.d), 0.02);
  }
}

}  // namespace
}  // namespace annex
