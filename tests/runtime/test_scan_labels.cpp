// The scan picture (scan_overlay.h): its labels, none cut at the image's edges, none over
// another while there is room; its background, the scene even without colour.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "annex/runtime/scan_overlay.h"
#include "annex/runtime/scanner.h"

namespace annex {
namespace {

TEST(ScanLabels, StayInsideTheImage) {
  // Objects touching each edge: a label centred on them would stick out.
  const std::vector<LabelRequest> labels = {{120, 18, 0, 40, 0, 30},
                                            {120, 18, 200, 479, 600, 639},
                                            {200, 18, 100, 140, 630, 639}};
  const auto boxes = layout_labels(labels, 640, 480);
  ASSERT_EQ(boxes.size(), labels.size());
  for (const LabelBox& b : boxes) {
    EXPECT_GE(b.x0, 0);
    EXPECT_GE(b.y0, 0);
    EXPECT_LE(b.x1, 640);
    EXPECT_LE(b.y1, 480);
  }
}

TEST(ScanLabels, BusyScenesStackLabelsWithoutOverlap) {
  // Eight objects side by side in a row, each narrower than its label.
  std::vector<LabelRequest> labels;
  for (int k = 0; k < 8; ++k) labels.push_back({140, 18, 200, 260, 250 + 12 * k, 260 + 12 * k});
  const auto boxes = layout_labels(labels, 640, 480);
  for (size_t i = 0; i < boxes.size(); ++i)
    for (size_t j = i + 1; j < boxes.size(); ++j)
      EXPECT_FALSE(boxes[i].overlaps(boxes[j])) << i << " and " << j;
  // The first goes where a reader looks: just above its object.
  EXPECT_EQ(boxes[0].y1, 200 - 4);
}

TEST(ScanLabels, WithNoRoomLeftTheyStillStayInside) {
  std::vector<LabelRequest> labels(40, LabelRequest{300, 40, 100, 140, 100, 140});
  const auto boxes = layout_labels(labels, 320, 240);
  for (const LabelBox& b : boxes) {
    EXPECT_GE(b.x0, 0);
    EXPECT_LE(b.y1, 240);
  }
}

// A cloud without colour (a model such as milk.pcd, 13,704 bare x y z points) is drawn by
// depth where its points project, nearer lighter, and black where no point is.
TEST(ScanOverlay, ColourlessCloudIsShadedByDepth) {
  const CameraIntrinsics k;
  Frame cloud;
  for (int v = 200; v < 280; ++v)
    for (int u = 280; u < 360; ++u) {
      const float z = u < 320 ? 0.8f : 1.2f;  // a near patch left, a far one right
      PointXYZRGB p;
      p.z = z;
      p.x = static_cast<float>((u - k.cx) * z / k.fx);
      p.y = static_cast<float>((v - k.cy) * z / k.fy);
      cloud.points.push_back(p);
    }
  cloud.width = static_cast<int>(cloud.points.size());
  cloud.height = 1;
  const RgbImage img = draw_scan_overlay(cloud, ScanResult{});
  ASSERT_EQ(img.width, 640);
  auto at = [&](int u, int v) { return img.rgb[(static_cast<size_t>(v) * img.width + u) * 3]; };
  EXPECT_EQ(at(100, 100), 0);
  EXPECT_GT(at(300, 240), at(340, 240));
  EXPECT_GT(at(340, 240), 0);
}

}  // namespace
}  // namespace annex
