// The depth cameras' noise presets (depth_noise.h).
#include "annex/runtime/depth_noise.h"

namespace annex {

std::optional<DepthNoise> depth_noise_named(std::string_view name) {
  if (name == "kinect") return DepthNoise{};
  // RMS = z^2 subpixel / (f baseline) = z^2 0.08 / (430 px x 0.050 m).
  if (name == "stereo") return DepthNoise{0.0, 0.0037, 0.0};
  // 1.5 - 0.5 z + 0.3 z^2 mm = 1.29 + 0.3 (z - 0.83)^2 mm.
  if (name == "tof") return DepthNoise{0.00129, 0.0003, 0.83};
  return std::nullopt;
}

}  // namespace annex
