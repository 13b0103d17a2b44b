// libFuzzer target for the PCD reader (header and ascii, binary and LZF
// binary_compressed bodies): any input must decode or fail cleanly; a decoded frame
// has width x height points, each all finite or all NaN, and survives our writer
// and the decoder again unchanged.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>

#include "annex/runtime/pcd_io.h"

namespace {

bool same(const annex::Frame& a, const annex::Frame& b) {
  if (a.width != b.width || a.height != b.height || a.points.size() != b.points.size())
    return false;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const annex::PointXYZRGB &p = a.points[i], &q = b.points[i];
    const bool nan = std::isnan(p.x);
    if (nan != std::isnan(q.x)) return false;
    if (!nan && std::memcmp(&p.x, &q.x, 12) != 0) return false;
    if (p.r != q.r || p.g != q.g || p.b != q.b) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const auto frame = annex::decode_pcd(bytes, "fuzz.pcd");
  if (!frame.ok()) {
    if (frame.error().location.origin != "fuzz.pcd" || frame.error().message.empty()) std::abort();
    return 0;
  }
  const annex::Frame& f = *frame;
  if (f.width < 1 || f.height < 1 ||
      f.points.size() != static_cast<std::size_t>(f.width) * f.height)
    std::abort();
  for (const annex::PointXYZRGB& p : f.points) {
    const int finite = std::isfinite(p.x) + std::isfinite(p.y) + std::isfinite(p.z);
    const int nan = std::isnan(p.x) + std::isnan(p.y) + std::isnan(p.z);
    if (finite != 3 && nan != 3) std::abort();
  }
  const auto again = annex::decode_pcd(annex::pcd_bytes(f), "written.pcd");
  if (!again.ok() || !same(*again, f)) {
    std::fprintf(stderr, "write -> decode changed the frame\n");
    std::abort();
  }
  return 0;
}
