#include "annex/authoring/recent_files.h"

#include <gtest/gtest.h>

#include "test_util.h"

namespace annex::authoring {
namespace {

TEST(RecentFiles, MostRecentFirstWithoutDuplicates) {
  RecentFiles r;
  r = add_recent(r, "/a/one.haptic");
  r = add_recent(r, "/a/two.haptic");
  r = add_recent(r, "/a/one.haptic");
  ASSERT_EQ(r.paths.size(), 2u);
  EXPECT_EQ(r.paths[0], "/a/one.haptic");
  EXPECT_EQ(r.paths[1], "/a/two.haptic");
}

TEST(RecentFiles, KeepsAtMostTen) {
  RecentFiles r;
  for (int i = 0; i < 15; ++i) r = add_recent(r, "/f" + std::to_string(i) + ".haptic");
  ASSERT_EQ(r.paths.size(), kMaxRecent);
  EXPECT_EQ(r.paths.front(), "/f14.haptic");
  EXPECT_EQ(r.paths.back(), "/f5.haptic");
}

TEST(RecentFiles, WriteReadRoundTripAndMissingFileIsEmpty) {
  const auto dir = testing::fresh_dir("recent");
  EXPECT_TRUE(read_recent(dir / "none.txt").paths.empty());
  RecentFiles r;
  r = add_recent(r, "/x/b.haptic");
  r = add_recent(r, "/x/a.haptic");
  ASSERT_TRUE(write_recent(dir / "sub" / "recent.txt", r));
  EXPECT_EQ(read_recent(dir / "sub" / "recent.txt").paths, r.paths);
}

}  // namespace
}  // namespace annex::authoring
