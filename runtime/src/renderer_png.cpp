// PNG output of rendered frames, through the shared writer (formats/png_io.h).
#include <string>

#include "annex/formats/png_io.h"
#include "annex/runtime/renderer.h"

namespace annex {
namespace {

bool well_formed(const RgbaImage& image) {
  return image.width > 0 && image.height > 0 &&
         image.rgba.size() == static_cast<std::size_t>(image.width) * image.height * 4;
}

}  // namespace

std::string encode_rgba_png(const RgbaImage& image) {
  if (!well_formed(image)) return {};
  return encode_png(image.width, image.height, 4, image.rgba.data());
}

Status write_rgba_png(const std::filesystem::path& path, const RgbaImage& image) {
  if (!well_formed(image))
    return Error{"cannot encode a " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + " image as PNG",
                 Location{path.string(), 0, 0}};
  return write_png_file(path, image.width, image.height, 4, image.rgba.data());
}

}  // namespace annex
