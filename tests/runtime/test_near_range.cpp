// An object running into the sensor's near blind zone, which returns no depth, is cut
// as one across the image's border: the generator's truth says so and the scanner flags
// it partial (sensor_min_range_m, scanner.cpp cut_or_hidden). Fresh rooms 8078 and 8118:
// bowls 0.45 m away whose near rim lies nearer than the Kinect's 0.4 m showed their far
// half alone and were reported whole, as boxes.
#include <gtest/gtest.h>

#include <optional>

#include "annex/runtime/scanner.h"
#include "annex/runtime/synthetic_scene.h"
#include "scan_one.h"

namespace annex {
namespace {

// A bowl: a cone apex down (wide end up) of rim radius 8 cm, 3.2 cm tall, its foot half
// the rim (fresh room 8118's).
SyntheticObject bowl() {
  SyntheticObject o = resting_object(ShapeKind::cone, {0.08, 0.032}, 0, 0);
  o.apex_down = true;
  o.narrow_radius_m = 0.04;
  return o;
}

TEST(NearRange, ABowlRunningIntoTheBlindZoneIsCut) {
  // 0.44 m away along a view 50 degrees down, its near rim lies nearer than 0.4 m.
  const std::optional<OneScan> near = scan_one_seen(bowl(), 0.44, 50);
  ASSERT_TRUE(near && near->scanned);
  EXPECT_TRUE(near->truth.partial);
  EXPECT_TRUE(near->scanned->partial);
  // The rule, not another, flags it: off, the bowl is reported whole.
  ScanParams off;
  off.sensor_min_range_m = 0;
  const std::optional<OneScan> unflagged = scan_one_seen(bowl(), 0.44, 50, 11, off);
  ASSERT_TRUE(unflagged && unflagged->scanned);
  EXPECT_FALSE(unflagged->scanned->partial);
}

TEST(NearRange, TheSameBowlWhollyInRangeIsWhole) {
  const std::optional<OneScan> seen = scan_one_seen(bowl(), 0.6, 50);
  ASSERT_TRUE(seen && seen->scanned);
  EXPECT_FALSE(seen->truth.partial);
  EXPECT_FALSE(seen->scanned->partial);
}

}  // namespace
}  // namespace annex
