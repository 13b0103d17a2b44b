// A build with ANNEX_WITH_OPENNI2=OFF compiles frame_grabber_no_openni2.cpp in place of
// the OpenNI2 sources. This test compiles that translation unit in every build (so it
// cannot rot while the default build has OpenNI2) and checks what a user of such a
// build is told. The whole OFF build is docs/reliability.md's.
#include <gtest/gtest.h>

#include "annex/runtime/frame_grabber.h"

namespace annex {
namespace {

TEST(NoOpenNI2, DeviceAndRecordingSayTheBuildHasNone) {
  auto device = open_openni2_device("#1");
  ASSERT_FALSE(device);
  EXPECT_NE(device.error().format().find("cannot open OpenNI2 device '#1'"), std::string::npos)
      << device.error().format();
  EXPECT_NE(device.error().format().find("ANNEX_WITH_OPENNI2=OFF"), std::string::npos);

  auto file = open_oni_file("take.oni", FrameSourceParams{});
  ASSERT_FALSE(file);
  EXPECT_EQ(file.error().location.origin, "take.oni");
  EXPECT_NE(file.error().format().find("built without OpenNI2"), std::string::npos)
      << file.error().format();
}

}  // namespace
}  // namespace annex
