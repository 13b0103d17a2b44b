#pragma once
// `--color RGB.png --intrinsics fx,fy,cx,cy --depth-scale S`, shared by scan, match
// (a depth PNG as the frame) and run (depth PNG sources).

#include <charconv>
#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>

#include "annex/runtime/depth_png.h"
#include "annex/runtime/frame_grabber.h"
#include "annex/runtime/frame_grabber_depth_png.h"
#include "annex/runtime/pcd_io.h"
#include "cli.h"

namespace annex::cli {

// Reads --depth-scale and --intrinsics into `params`; false after printing the error.
inline bool read_depth_options(std::string_view command, const ParsedArgs& args,
                               FrameSourceParams& params) {
  if (auto v = args.get("depth-scale")) {
    double s = 0;
    const auto [end, ec] = std::from_chars(v->data(), v->data() + v->size(), s);
    if (ec != std::errc() || end != v->data() + v->size() || !std::isfinite(s) || !(s > 0)) {
      fail(command, "--depth-scale expects a positive number (1000: millimetres, TUM 5000), got '" +
                        *v + "'",
           kExitBadInput);
      return false;
    }
    params.depth_scale = s;
  }
  if (auto v = args.get("intrinsics")) {
    Result<CameraIntrinsics> k = parse_intrinsics(*v, 0, 0, "--intrinsics");
    if (!k) {
      std::cerr << k.error().format() << "\n";
      return false;
    }
    params.intrinsics = *k;
  }
  return true;
}

inline bool is_png_path(std::string_view path) {
  std::string ext(path.size() >= 4 ? path.substr(path.size() - 4) : std::string_view());
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".png";
}

// One frame from a .pcd, or a depth .png through `params` (read_depth_options) and
// --color; the depth image options apply to PNGs only.
inline Result<Frame> read_frame_file(const std::string& path, const ParsedArgs& args,
                                     const FrameSourceParams& params) {
  if (!is_png_path(path)) {
    for (const char* option : {"color", "intrinsics", "depth-scale"})
      if (args.has(option))
        return Error{std::string("--") + option + " applies to a depth .png, not to this file",
                     Location{path}};
    return read_pcd(path);
  }
  std::optional<std::filesystem::path> color;
  if (auto c = args.get("color")) color = *c;
  return read_depth_png_frame(path, color, params);
}

}  // namespace annex::cli
