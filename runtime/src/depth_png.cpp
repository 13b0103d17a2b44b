#include "annex/runtime/depth_png.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>

// stb_image's PNG decoder, with internal linkage so tests may compile their own copy.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_NO_STDIO
#include <stb/stb_image.h>

#include "annex/formats/file_io.h"

namespace annex {
namespace {

Error file_error(std::string_view origin, const std::string& message) {
  return Error{message, Location{std::string(origin)}};
}

std::string printable(std::string_view s) {
  std::string out;
  for (char c : s) out += (c >= 32 && c < 127) ? c : '?';
  return out;
}

struct PngHeader {
  int width = 0, height = 0, channels = 0;
  bool sixteen_bit = false;
};

std::uint32_t be32(std::string_view b, std::size_t at) {
  return (std::uint32_t{static_cast<unsigned char>(b[at])} << 24) |
         (std::uint32_t{static_cast<unsigned char>(b[at + 1])} << 16) |
         (std::uint32_t{static_cast<unsigned char>(b[at + 2])} << 8) |
         std::uint32_t{static_cast<unsigned char>(b[at + 3])};
}

// Header checks before any pixel is decoded, read from the IHDR chunk that the PNG
// specification puts first: memory follows the image's real size, and the error
// says what the header claims.
Result<PngHeader> read_header(std::string_view path, std::string_view bytes,
                              const DepthPngParams& params) {
  static constexpr char kSignature[] = "\x89PNG\r\n\x1a\n";
  if (bytes.size() < 29 || bytes.compare(0, 8, kSignature, 8) != 0 ||
      bytes.compare(12, 4, "IHDR") != 0)
    return file_error(path, "not a PNG image");
  PngHeader h;
  const std::uint32_t w = be32(bytes, 16), ht = be32(bytes, 20);
  const int bit_depth = static_cast<unsigned char>(bytes[24]);
  const int colour_type = static_cast<unsigned char>(bytes[25]);
  if (w == 0 || ht == 0 || w > static_cast<std::uint32_t>(params.max_side_px) ||
      ht > static_cast<std::uint32_t>(params.max_side_px))
    return file_error(path, "PNG header claims " + std::to_string(w) + "x" + std::to_string(ht) +
                                " pixels; at most " + std::to_string(params.max_side_px) +
                                " per side are read");
  h.width = static_cast<int>(w);
  h.height = static_cast<int>(ht);
  // Colour types 0 grey, 2 RGB, 3 palette, 4 grey+alpha, 6 RGBA.
  h.channels = colour_type == 0 ? 1 : colour_type == 4 ? 2 : colour_type == 6 ? 4 : 3;
  h.sixteen_bit = bit_depth == 16;
  return h;
}

// The PNG's chunks, each checked to lie within the file, with empty IDAT chunks
// left out (legal, but stb_image copies from a null buffer for them: found by
// fuzz_depth_png). What stb_image decodes.
Result<std::string> checked_chunks(std::string_view path, std::string_view bytes) {
  std::string out(bytes.substr(0, 8));
  std::size_t at = 8;
  while (at < bytes.size()) {
    if (bytes.size() - at < 12)
      return file_error(path, "truncated PNG: " + std::to_string(bytes.size() - at) +
                                  " bytes after the last chunk");
    const std::uint32_t length = be32(bytes, at);
    const std::string_view type = bytes.substr(at + 4, 4);
    if (length > bytes.size() - at - 12)
      return file_error(path, "truncated PNG: chunk '" + printable(type) + "' claims " +
                                  std::to_string(length) + " bytes, " +
                                  std::to_string(bytes.size() - at - 12) + " remain");
    if (!(type == "IDAT" && length == 0)) out.append(bytes.substr(at, 12 + length));
    at += 12 + length;
    if (type == "IEND") break;
  }
  return out;
}

Result<std::string> read_bytes(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return file_error(path.string(), "no such file");
  // 64 MiB holds an uncompressed 4096x4096 16-bit image.
  return read_text_file(path, std::size_t{64} << 20);
}

}  // namespace

Result<DepthImage> read_depth_png(const std::filesystem::path& path,
                                  const DepthPngParams& params) {
  if (!(params.depth_scale > 0) || !std::isfinite(params.depth_scale))
    return file_error(path.string(), "depth scale must be a positive number");
  Result<std::string> bytes = read_bytes(path);
  if (!bytes) return bytes.error();
  return decode_depth_png(*bytes, path.string(), params);
}

Result<DepthImage> decode_depth_png(std::string_view bytes, std::string_view path,
                                    const DepthPngParams& params) {
  if (!(params.depth_scale > 0) || !std::isfinite(params.depth_scale))
    return file_error(path, "depth scale must be a positive number");
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    return file_error(path, "PNG file too large");
  Result<PngHeader> h = read_header(path, bytes, params);
  if (!h) return h.error();
  Result<std::string> chunks = checked_chunks(path, bytes);
  if (!chunks) return chunks.error();
  if (!h->sixteen_bit)
    return file_error(path, "8-bit image: depth must be a 16-bit PNG (an 8-bit one is a "
                            "visualisation, not a measurement)");
  if (h->channels != 1)
    return file_error(path, "depth PNG has " + std::to_string(h->channels) +
                                " channels; a depth image has one");
  int w = 0, hgt = 0, n = 0;
  std::unique_ptr<stbi_us, void (*)(void*)> pixels(
      stbi_load_16_from_memory(reinterpret_cast<const stbi_uc*>(chunks->data()),
                               static_cast<int>(chunks->size()), &w, &hgt, &n, 1),
      stbi_image_free);
  if (!pixels) return file_error(path, "corrupt PNG (" + std::string(stbi_failure_reason()) + ")");

  DepthImage depth;
  depth.width = w;
  depth.height = hgt;
  depth.depth_mm.resize(static_cast<std::size_t>(w) * hgt);
  const double to_mm = 1000.0 / params.depth_scale;
  for (std::size_t i = 0; i < depth.depth_mm.size(); ++i) {
    const double mm = std::round(pixels.get()[i] * to_mm);
    // Beyond what millimetres in 16 bits hold (65 m): no sensor measures it.
    depth.depth_mm[i] = mm <= 65535.0 ? static_cast<std::uint16_t>(mm) : 0;
  }
  return depth;
}

Result<ColorImage> read_color_png(const std::filesystem::path& path,
                                  const DepthPngParams& params) {
  Result<std::string> bytes = read_bytes(path);
  if (!bytes) return bytes.error();
  return decode_color_png(*bytes, path.string(), params);
}

Result<ColorImage> decode_color_png(std::string_view bytes, std::string_view path,
                                    const DepthPngParams& params) {
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    return file_error(path, "PNG file too large");
  Result<PngHeader> h = read_header(path, bytes, params);
  if (!h) return h.error();
  Result<std::string> chunks = checked_chunks(path, bytes);
  if (!chunks) return chunks.error();
  int w = 0, hgt = 0, n = 0;
  std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
      stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(chunks->data()),
                            static_cast<int>(chunks->size()), &w, &hgt, &n, 3),
      stbi_image_free);
  if (!pixels) return file_error(path, "corrupt PNG (" + std::string(stbi_failure_reason()) + ")");
  ColorImage color;
  color.width = w;
  color.height = hgt;
  color.rgb.assign(pixels.get(), pixels.get() + static_cast<std::size_t>(w) * hgt * 3);
  return color;
}

Result<Frame> read_depth_frame(const std::filesystem::path& depth_path,
                               const std::optional<std::filesystem::path>& color_path,
                               const CameraIntrinsics& intrinsics,
                               const DepthPngParams& params) {
  Result<DepthImage> depth = read_depth_png(depth_path, params);
  if (!depth) return depth.error();
  std::optional<ColorImage> color;
  if (color_path) {
    Result<ColorImage> c = read_color_png(*color_path, params);
    if (!c) return c.error();
    if (c->width * depth->height != c->height * depth->width)
      return file_error(color_path->string(), "colour image is " + std::to_string(c->width) + "x" +
                                         std::to_string(c->height) + " but the depth image " +
                                         depth_path.filename().string() + " is " +
                                         std::to_string(depth->width) + "x" +
                                         std::to_string(depth->height));
    color = std::move(*c);
  }
  Result<Frame> frame = depth_to_frame(*depth, color ? &*color : nullptr, intrinsics);
  if (!frame) return file_error(depth_path.string(), frame.error().message);
  return frame;
}

Result<CameraIntrinsics> parse_intrinsics(std::string_view text, int width, int height,
                                          std::string_view origin) {
  double v[4];
  std::size_t pos = 0;
  for (int i = 0; i < 4; ++i) {
    const std::size_t end = i < 3 ? text.find(',', pos) : text.size();
    if (end == std::string_view::npos || end == pos)
      return Error{"want fx,fy,cx,cy (four numbers), got '" + std::string(text) + "'",
                   Location{std::string(origin)}};
    const std::string token(text.substr(pos, end - pos));
    char* stop = nullptr;
    v[i] = std::strtod(token.c_str(), &stop);
    if (stop != token.c_str() + token.size() || !std::isfinite(v[i]))
      return Error{"'" + token + "' is not a number in fx,fy,cx,cy",
                   Location{std::string(origin)}};
    pos = end + 1;
  }
  if (!(v[0] > 0) || !(v[1] > 0))
    return Error{"focal lengths fx and fy must be positive", Location{std::string(origin)}};
  CameraIntrinsics k;
  k.width = width;
  k.height = height;
  k.fx = v[0];
  k.fy = v[1];
  k.cx = v[2];
  k.cy = v[3];
  return k;
}

}  // namespace annex
