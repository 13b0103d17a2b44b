#pragma once
// The scan's picture for people: the camera's colour image, dimmed, each object's
// points coloured, its fitted primitives drawn as wireframes projected with the
// intrinsics, and a label "p2 cylinder" (docs/perception.md).

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "annex/common/result.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/scanner.h"

namespace annex {

struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // row-major, 3 bytes per pixel
};

// `intrinsics` are scaled to the frame's size when it differs from theirs.
// Unorganized frames draw on a black 640x480 canvas (the scanner's re-organized grid).
RgbImage draw_scan_overlay(const Frame& frame, const ScanResult& scan,
                           const CameraIntrinsics& intrinsics = {});

// Where the overlay's labels go. Each asks for a box of its text's size next to its
// object's pixel bounds; the boxes lie inside the image and, when there is room, over
// no other label: above the object, else below it, beside it, or stacked further away.
struct LabelRequest {
  int width = 0, height = 0;             // the label's box, pixels
  int top = 0, bottom = 0, left = 0, right = 0;  // the object's pixel bounds
};
struct LabelBox {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) x [y0, y1)
  bool overlaps(const LabelBox& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};
std::vector<LabelBox> layout_labels(const std::vector<LabelRequest>& labels, int image_width,
                                    int image_height);

// A label's text and colour, and the pixel bounds of what it names.
struct ImageLabel {
  std::string text;
  std::array<std::uint8_t, 3> colour{255, 255, 255};
  int top = 0, bottom = 0, left = 0, right = 0;
};
// Draws the labels, white-on-black boxes of stb_easy_font text laid out by
// layout_labels, on RGB (channels 3) or RGBA (4, drawn opaque) pixels, row-major. The
// labels' bounds and their layout are in the region [region_x0, region_x0 +
// region_width) of the image (one eye of a side-by-side render; -1: to the right edge).
void draw_labels(std::uint8_t* pixels, int image_width, int image_height, int channels,
                 const std::vector<ImageLabel>& labels, int region_x0 = 0, int region_width = -1);

// PNG bytes of an image (stb_image_write), and an atomic file write of them.
std::string encode_png(const RgbImage& image);
Status write_png(const std::filesystem::path& path, const RgbImage& image);

}  // namespace annex
