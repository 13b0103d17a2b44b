// libFuzzer target for the depth and colour PNG readers: any input must decode or
// fail cleanly; a decoded image has width x height pixels within the size limit.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "annex/runtime/depth_png.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  // Small limits keep each run fast; the header check is the same at any limit.
  const annex::DepthPngParams params{.depth_scale = 5000, .max_side_px = 64};
  const auto depth = annex::decode_depth_png(bytes, "fuzz.png", params);
  if (depth.ok()) {
    if (depth->width < 1 || depth->height < 1 || depth->width > 64 || depth->height > 64 ||
        depth->depth_mm.size() != static_cast<std::size_t>(depth->width) * depth->height)
      std::abort();
  } else if (depth.error().location.origin != "fuzz.png") {
    std::abort();
  }
  const auto color = annex::decode_color_png(bytes, "fuzz.png", params);
  if (color.ok()) {
    if (color->width < 1 || color->height < 1 || color->width > 64 || color->height > 64 ||
        color->rgb.size() != static_cast<std::size_t>(color->width) * color->height * 3)
      std::abort();
  } else if (color.error().location.origin != "fuzz.png") {
    std::abort();
  }
  return 0;
}
