// libFuzzer target for the .scene reader: any input must parse or fail cleanly, and
// whatever parses must pass validate_scene and survive write -> parse unchanged.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "annex/formats/scene_format.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto scene = annex::parse_scene(text, "fuzz.scene");
  if (!scene.ok()) {
    if (scene.error().location.line < 1 || scene.error().location.column < 1) std::abort();
    return 0;
  }
  if (auto st = annex::validate_scene(*scene); !st.ok()) {
    std::fprintf(stderr, "parsed scene fails validation: %s\n", st.error().format().c_str());
    std::abort();
  }
  const std::string written = annex::write_scene(*scene);
  auto again = annex::parse_scene(written, "written.scene");
  if (!again.ok()) {
    std::fprintf(stderr, "written text does not parse: %s\n%s", again.error().format().c_str(),
                 written.c_str());
    std::abort();
  }
  if (!(*again == *scene) || annex::write_scene(*again) != written) {
    std::fprintf(stderr, "round trip changed the scene:\n%s", written.c_str());
    std::abort();
  }
  return 0;
}
