#pragma once
// The scan's picture for people: the camera's colour image, dimmed, each object's
// points coloured, its fitted primitives drawn as wireframes projected with the
// intrinsics, and a label "p2 cylinder" (docs/perception.md).

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

// PNG bytes of an image (stb_image_write), and an atomic file write of them.
std::string encode_png(const RgbImage& image);
Status write_png(const std::filesystem::path& path, const RgbImage& image);

}  // namespace annex
