#pragma once
// Depth and colour images as PNG files, the form most recorders and datasets use
// (TUM RGB-D, OSD, NYU): 16-bit single-channel depth whose value / depth_scale is
// metres, 0 where the sensor saw nothing, and an 8-bit colour image registered to it.

#include <filesystem>
#include <optional>
#include <string_view>

#include "annex/common/result.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/frame_grabber.h"

namespace annex {

struct DepthPngParams {
  // Stored value / depth_scale = metres: 1000 for millimetres (Kinect, OSD), 5000
  // for TUM RGB-D.
  double depth_scale = 1000.0;
  // Images wider or taller than this are refused before decoding: no depth sensor
  // delivers them, and a lying header must not make us allocate for its promise.
  int max_side_px = 4096;
};

// Reads a 16-bit grey PNG into millimetres. Errors name the file: missing, not a
// PNG, 8-bit (a visualisation, not depth), more than one channel, too large, or a
// scale that is not positive.
Result<DepthImage> read_depth_png(const std::filesystem::path& path,
                                  const DepthPngParams& params = {});

// The same from a whole file held in memory; pure, for tests and the fuzz target.
// Errors are located at `origin`.
Result<DepthImage> decode_depth_png(std::string_view bytes, std::string_view origin,
                                    const DepthPngParams& params = {});

// Reads an 8-bit PNG (grey, grey+alpha, RGB or RGBA) as RGB.
Result<ColorImage> read_color_png(const std::filesystem::path& path,
                                  const DepthPngParams& params = {});

Result<ColorImage> decode_color_png(std::string_view bytes, std::string_view origin,
                                    const DepthPngParams& params = {});

// A depth PNG (and optional colour PNG) back-projected through the intrinsics into
// an organized frame. The depth image's size must match the intrinsics'.
Result<Frame> read_depth_frame(const std::filesystem::path& depth_path,
                               const std::optional<std::filesystem::path>& color_path,
                               const CameraIntrinsics& intrinsics,
                               const DepthPngParams& params = {});

// Intrinsics from "fx,fy,cx,cy" for a width x height image; errors for a malformed
// list or non-positive focal lengths, located at `origin` (an option name).
Result<CameraIntrinsics> parse_intrinsics(std::string_view text, int width, int height,
                                          std::string_view origin);

}  // namespace annex
