#pragma once
/// \file
/// PNG output shared by the scan overlay, the Renderer and the editor's screenshots.

#include <cstdint>
#include <filesystem>
#include <string>

#include "annex/common/result.h"

namespace annex {

/// Encodes 8-bit pixels (1 to 4 channels, rows top to bottom, tightly packed) as PNG.
/// Returns an empty string for an empty image or a bad channel count.
std::string encode_png(int width, int height, int channels, const std::uint8_t* pixels);

/// Encodes and writes atomically (write_file_atomically); errors name the path.
Status write_png_file(const std::filesystem::path& path, int width, int height, int channels,
                      const std::uint8_t* pixels);

}  // namespace annex
