// libFuzzer target for hmd.conf (docs/renderer.md): any input must parse or fail
// with a located error; a parsed config gives two eyes with finite projections.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <vector>

#include "annex/runtime/renderer.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::vector<annex::Diagnostic> warnings;
  const auto hmd = annex::parse_hmd_config(text, "fuzz.conf", &warnings);
  if (!hmd.ok()) {
    if (hmd.error().location.origin != "fuzz.conf" || hmd.error().message.empty()) std::abort();
    return 0;
  }
  (void)annex::hmd_eyes(*hmd);
  return 0;
}
