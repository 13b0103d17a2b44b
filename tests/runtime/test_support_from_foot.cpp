// An object stands where its foot is (ScanParams::support_from_foot): a cluster whose
// lowest point lies on a higher support's plane, within that support's reach, is that
// support's, not the floor's whose hull holds the rest of its pixels. Rooms 9569's ball
// and unseen rooms 7001's ring, each across the table's edge, were given to the floor.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <optional>

#include "annex/runtime/scanner.h"
#include "room_scan.h"

namespace annex {
namespace {

// The overhanging object of the room: its scanned object's support's height above the
// table's plane and the floor's (in metres, along the truth's normal), and its shape.
struct Footing {
  double off_table = 1e9, off_floor = 1e9;
  std::optional<ShapeKind> kind;
};

Footing overhanging(std::uint64_t seed, bool from_foot) {
  ScanParams p;
  p.support_from_foot = from_foot;
  const RoomScan r = scan_room(seed, p);
  const int t = find_object(r.scene, [](const SyntheticObject& o) { return o.overhang; });
  EXPECT_GE(t, 0) << seed << ": the generator no longer puts an object across the edge";
  if (t < 0 || r.of.empty() || !r.of[static_cast<std::size_t>(t)]) return {};
  const PhysicalObject& got = *r.of[static_cast<std::size_t>(t)];
  Footing out;
  if (!got.primitives.empty()) out.kind = got.primitives[0].kind;
  for (const SupportSurface& sp : r.supports)
    if (sp.id == got.support_id) {
      // The truth's supports: "table", then "floor".
      out.off_table = std::abs(sp.plane.d - r.truth.supports.at(0).plane.d);
      out.off_floor = std::abs(sp.plane.d - r.truth.supports.at(1).plane.d);
    }
  return out;
}

constexpr std::uint64_t kRooms[] = {9569, 7001};

TEST(SupportFromFoot, AnObjectAcrossTheTableEdgeIsOnTheTable) {
  for (std::uint64_t seed : kRooms) {
    const Footing f = overhanging(seed, true);
    EXPECT_LT(f.off_table, 0.03) << seed;
    EXPECT_EQ(f.kind, seed == 9569 ? ShapeKind::sphere : ShapeKind::torus) << seed;
  }
}

TEST(SupportFromFoot, WithoutItTheObjectAcrossTheEdgeIsGivenToTheFloor) {
  for (std::uint64_t seed : kRooms) {
    const Footing f = overhanging(seed, false);
    EXPECT_LT(f.off_floor, 0.05) << seed;
  }
}

}  // namespace
}  // namespace annex
