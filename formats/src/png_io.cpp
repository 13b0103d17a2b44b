#include "annex/formats/png_io.h"

#include <zlib.h>

#include <cstdlib>

// stb's own deflate takes about 40 ms for a 640x480 overlay; zlib at its fastest level
// takes about 13 ms and writes smaller files, which matters at one PNG per frame.
static unsigned char* annex_zlib_compress(unsigned char* data, int size, int* out_size, int) {
  uLongf bound = compressBound(static_cast<uLong>(size));
  auto* out = static_cast<unsigned char*>(std::malloc(bound));
  if (out == nullptr || compress2(out, &bound, data, static_cast<uLong>(size), Z_BEST_SPEED) != Z_OK) {
    std::free(out);
    *out_size = 0;
    return nullptr;
  }
  *out_size = static_cast<int>(bound);
  return out;
}

// The one translation unit that compiles stb_image_write.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#define STBIW_ZLIB_COMPRESS annex_zlib_compress
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
