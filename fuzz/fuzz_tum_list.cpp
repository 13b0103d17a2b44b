// libFuzzer target for TUM RGB-D list files (rgb.txt, depth.txt): any input must
// parse or fail with a located error; parsed entries have a finite non-negative
// timestamp, a file name without blanks and increasing line numbers.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "annex/runtime/frame_grabber_depth_png.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto list = annex::parse_tum_list(text, "fuzz.txt");
  if (!list.ok()) {
    const auto& loc = list.error().location;
    if (loc.origin != "fuzz.txt" || loc.line < 1 || loc.column < 1) std::abort();
    return 0;
  }
  int last_line = 0;
  for (const annex::TumListEntry& e : *list) {
    if (!std::isfinite(e.timestamp_s) || e.timestamp_s < 0 || e.file.empty() ||
        e.file.find_first_of(" \t\n") != std::string::npos || e.line <= last_line)
      std::abort();
    last_line = e.line;
  }
  return 0;
}
