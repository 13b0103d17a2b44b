// The scan picture's labels (scan_overlay.h): none cut at the image's edges, none over
// another while there is room.
#include <gtest/gtest.h>

#include <vector>

#include "annex/runtime/scan_overlay.h"

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

}  // namespace
}  // namespace annex
