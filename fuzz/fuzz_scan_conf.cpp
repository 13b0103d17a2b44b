// libFuzzer target for scan.conf (docs/perception.md): any input must parse or fail
// with a located error.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "annex/runtime/scanner.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto params = annex::parse_scan_config(text, "fuzz.conf");
  if (!params.ok() && (params.error().location.origin != "fuzz.conf" ||
                       params.error().message.empty()))
    std::abort();
  return 0;
}
