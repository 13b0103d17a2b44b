#include "annex/formats/png_io.h"

// The one translation unit that compiles stb_image_write.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

#include "annex/formats/file_io.h"

namespace annex {

std::string encode_png(int width, int height, int channels, const std::uint8_t* pixels) {
  std::string out;
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 || pixels == nullptr) return out;
  stbi_write_png_to_func(
      [](void* ctx, void* data, int size) {
        static_cast<std::string*>(ctx)->append(static_cast<const char*>(data),
                                               static_cast<std::size_t>(size));
      },
      &out, width, height, channels, pixels, width * channels);
  return out;
}

Status write_png_file(const std::filesystem::path& path, int width, int height, int channels,
                      const std::uint8_t* pixels) {
  const std::string bytes = encode_png(width, height, channels, pixels);
  if (bytes.empty())
    return Error{"cannot encode a " + std::to_string(width) + "x" + std::to_string(height) +
                     " image as PNG",
                 Location{path.string(), 0, 0}};
  return write_file_atomically(path, bytes);
}

}  // namespace annex
