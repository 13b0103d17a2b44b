// Run's overlay labels (overlay_labels.h): the text says what is annexed onto what, and
// each label lies inside its eye's part of the image, beside its overlay, over no other.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "annex/runtime/overlay_labels.h"

namespace annex {
namespace {

RgbaImage grey(int width, int height) {
  RgbaImage img;
  img.width = width;
  img.height = height;
  img.rgba.assign(static_cast<std::size_t>(width) * height * 4, 100);
  return img;
}

// Bounds of the pixels that differ from the grey background, in [x_lo, x_hi).
struct Changed {
  int count = 0, x0 = 1 << 20, y0 = 1 << 20, x1 = -1, y1 = -1;
};
Changed changed(const RgbaImage& img, int x_lo = 0, int x_hi = -1) {
  if (x_hi < 0) x_hi = img.width;
  Changed c;
  for (int y = 0; y < img.height; ++y)
    for (int x = x_lo; x < x_hi; ++x) {
      const std::uint8_t* p = &img.rgba[(static_cast<std::size_t>(y) * img.width + x) * 4];
      if (p[0] == 100 && p[1] == 100 && p[2] == 100) continue;
      ++c.count;
      c.x0 = std::min(c.x0, x), c.y0 = std::min(c.y0, y);
      c.x1 = std::max(c.x1, x), c.y1 = std::max(c.y1, y);
    }
  return c;
}

// The sensor's own view, Kinect intrinsics (identity eye_from_sensor).
Eye kinect_eye() {
  Eye e;
  e.intrinsics = CameraIntrinsics{};
  return e;
}

// A 10 cm cube of points 1 m in front of the sensor, `dx` metres to the right.
std::vector<Vec3> cube(double dx) {
  std::vector<Vec3> pts;
  for (double x : {-0.05, 0.05})
    for (double y : {-0.05, 0.05})
      for (double z : {-0.05, 0.05}) pts.push_back({dx + x, y, 1.0 + z});
  return pts;
}

TEST(OverlayLabels, TextNamesObjectPropVoteAndState) {
  AnnexedObject o;
  o.virtual_name = "champagne_bottle";
  o.physical_id = "p1";
  o.vote = 84.046;
  EXPECT_EQ(overlay_label_text(o), "champagne_bottle on p1 84.05 tracking");
  o.fit.clamped = true;
  o.track.state = TrackingState::held;
  EXPECT_EQ(overlay_label_text(o), "champagne_bottle on p1 84.05 clamped held");
}

TEST(OverlayLabels, AboveTheOverlayAndInsideTheImage) {
  RgbaImage img = grey(640, 480);
  const Eye eye = kinect_eye();
  draw_overlay_labels(img, std::span<const Eye>(&eye, 1), {{"mug on p3 9.23 tracking", cube(0), false}});
  const Changed c = changed(img);
  ASSERT_GT(c.count, 100);
  // The cube's nearest face spans rows 212..267 (525 * 0.05 / 0.95 around 239.5): the
  // label ends just above it, horizontally centred on it.
  EXPECT_LT(c.y1, 212);
  EXPECT_GT(c.y1, 212 - 12);
  EXPECT_LT(c.x0, 320);
  EXPECT_GT(c.x1, 320);
}

TEST(OverlayLabels, TwoOverlaysInOnePlaceGetTwoLabelsAndEdgesCutNone) {
  RgbaImage img = grey(640, 480);
  const Eye eye = kinect_eye();
  // Two at the image's right edge; a long label would stick out if centred on them.
  const std::vector<OverlayLabel> labels = {
      {"champagne_bottle on p1 84.05 tracking", cube(0.55), false},
      {"lamp on p4 32.14 clamped tracking", cube(0.55), true}};
  draw_overlay_labels(img, std::span<const Eye>(&eye, 1), labels);
  const Changed c = changed(img);
  ASSERT_GT(c.count, 200);
  EXPECT_GE(c.x0, 0);
  EXPECT_LE(c.x1, 639);
  // Two text bands, one above the other: the changed rows are more than one label high.
  EXPECT_GT(c.y1 - c.y0, 2 * 14);
  // One label alone covers fewer rows.
  RgbaImage one = grey(640, 480);
  draw_overlay_labels(one, std::span<const Eye>(&eye, 1), {labels[0]});
  const Changed c1 = changed(one);
  EXPECT_LT(c1.y1 - c1.y0, 20);
}

TEST(OverlayLabels, EachEyeLabelsItsOwnHalfAndUnseenObjectsGetNone) {
  RgbaImage img = grey(1280, 480);
  const std::array<Eye, 2> eyes = {kinect_eye(), kinect_eye()};
  draw_overlay_labels(img, eyes, {{"lamp on p4 32.14 tracking", cube(0), false}});
  const Changed left = changed(img, 0, 640), right = changed(img, 640, 1280);
  ASSERT_GT(left.count, 100);
  ASSERT_GT(right.count, 100);
  EXPECT_EQ(left.count, right.count);
  EXPECT_EQ(right.x0 - 640, left.x0);
  // Behind the camera, or beside its view: no label.
  RgbaImage none = grey(640, 480);
  std::vector<Vec3> behind = cube(0);
  for (Vec3& p : behind) p.z = -p.z;
  draw_overlay_labels(none, std::span<const Eye>(eyes.data(), 1),
                      {{"a", behind, false}, {"b", cube(3.0), false}});
  EXPECT_EQ(changed(none).count, 0);
}

}  // namespace
}  // namespace annex
