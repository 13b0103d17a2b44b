#pragma once
// A depth camera's axial noise: the standard deviation of one pixel's depth at depth z,
// sigma_z(z) = base + quadratic (z - centre)^2 metres. Nguyen, Izadi & Lovell (2012) fit
// this form to the Kinect; it also holds for active stereo (RMS = z^2 subpixel /
// (focal baseline), Intel's tuning guide for the RealSense D400) and, fitted, for time
// of flight (Fankhauser et al. 2015, the Kinect v2). The scanner's tolerances (support
// bands, creases, shape fits, the touching cut) are multiples of it, so a camera
// noisier or quieter than the Kinect gets tolerances of its own.

#include <cmath>
#include <optional>
#include <string_view>

namespace annex {

struct DepthNoise {
  double base_m = 0.0012;           // the Kinect's (Nguyen et al. 2012)
  double quadratic_per_m = 0.0019;  // metres per square metre
  double centre_m = 0.4;
  double sigma_z(double z) const {
    return base_m + quadratic_per_m * (z - centre_m) * (z - centre_m);
  }
  // Whether sigma_z is finite and above 0 at every depth > 0: the tolerances divide by it.
  bool positive() const {
    return std::isfinite(base_m) && std::isfinite(quadratic_per_m) && std::isfinite(centre_m) &&
           base_m >= 0 && quadratic_per_m >= 0 &&
           (base_m > 0 || (quadratic_per_m > 0 && centre_m <= 0));
  }
  bool operator==(const DepthNoise&) const = default;
};

// The presets by name, nullopt for any other:
//   kinect  structured light, the Kinect v1 / Xtion / Structure (the default);
//   stereo  active stereo, a RealSense D435 at 848 x 480 (f 430 px, baseline 50 mm,
//           subpixel RMS 0.08): 0.0037 z^2;
//   tof     time of flight, the Kinect v2 / Azure Kinect (Fankhauser et al. 2015 at
//           normal incidence: 1.5 - 0.5 z + 0.3 z^2 mm).
std::optional<DepthNoise> depth_noise_named(std::string_view name);

// What DepthNoise::positive() asks, for messages.
inline constexpr std::string_view kDepthNoiseMustBePositive =
    "depth noise must be above 0 at every depth: depth_noise_base_m > 0, or "
    "depth_noise_quadratic > 0 with depth_noise_centre_m <= 0";

// "kinect, stereo, tof": for messages and --help.
inline constexpr std::string_view kDepthNoiseNames = "kinect, stereo, tof";

}  // namespace annex
