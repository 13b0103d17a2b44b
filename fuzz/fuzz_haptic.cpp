// libFuzzer target for the .haptic reader: any input must parse or fail cleanly, and
// whatever parses must pass validate_haptic and survive write -> parse unchanged.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "annex/formats/haptic_format.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto spec = annex::parse_haptic(text, "fuzz.haptic");
  if (!spec.ok()) {
    // Every error must be located.
    if (spec.error().location.line < 1 || spec.error().location.column < 1) std::abort();
    return 0;
  }
  if (auto st = annex::validate_haptic(*spec); !st.ok()) {
    std::fprintf(stderr, "parsed spec fails validation: %s\n", st.error().format().c_str());
    std::abort();
  }
  const std::string written = annex::write_haptic(*spec);
  auto again = annex::parse_haptic(written, "written.haptic");
  if (!again.ok()) {
    std::fprintf(stderr, "written text does not parse: %s\n%s", again.error().format().c_str(),
                 written.c_str());
    std::abort();
  }
  if (!(*again == *spec) || annex::write_haptic(*again) != written) {
    std::fprintf(stderr, "round trip changed the spec:\n%s", written.c_str());
    std::abort();
  }
  return 0;
}
