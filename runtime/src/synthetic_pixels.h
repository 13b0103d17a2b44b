// The per-pixel render loop of the generators (synthetic_scene.cpp, synthetic_motion.cpp):
// one (jittered) ray per pixel cast against the scene by the caller, then the Kinect
// model (dropout, edge dropout, axial noise) and the shaded colour per pixel. The scenes
// differ only in what a ray hits and in their colours; internal to the runtime library.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "annex/runtime/frame.h"
#include "annex/runtime/synthetic_scene.h"

namespace annex::synthetic_pixels {

// The surface a pixel's ray hits: camera depth, |cos| of the incidence, label.
struct SurfaceHit {
  double depth = std::numeric_limits<double>::infinity();
  double cos_incidence = 1;
  int label = kLabelNothing;
};

struct PixelHit {
  SurfaceHit surface;
  double ray_x = 0, ray_y = 0;  // normalized image coordinates of the (jittered) ray
};

// The frame's random draws, in the order both generators have always made them (a
// normal distribution keeps a second value between calls, so it is shared too).
struct Draws {
  std::mt19937_64 rng;
  std::normal_distribution<double> gauss{0.0, 1.0};
  std::uniform_real_distribution<double> unit{0.0, 1.0};
};

// Pass 1: `cast(u, v, ray_x, ray_y)` gives the surface the ray through the (jittered)
// image point (ray_x, ray_y, 1) hits, for every pixel in row order.
template <class Cast>
std::vector<PixelHit> cast_pixels(const CameraIntrinsics& cam, double jitter_px, Draws& draws,
                                  Cast&& cast) {
  std::vector<PixelHit> hits(static_cast<std::size_t>(cam.width) * cam.height);
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      const double uj = u + (jitter_px > 0 ? jitter_px * draws.gauss(draws.rng) : 0.0);
      const double vj = v + (jitter_px > 0 ? jitter_px * draws.gauss(draws.rng) : 0.0);
      PixelHit& px = hits[static_cast<std::size_t>(v) * cam.width + u];
      px.ray_x = (uj - cam.cx) / cam.fx;
      px.ray_y = (vj - cam.cy) / cam.fy;
      px.surface = cast(u, v, px.ray_x, px.ray_y);
    }
  }
  return hits;
}

using Rgb = std::array<std::uint8_t, 3>;

// Pass 2: the organized frame (points, shaded colours from `colour(label)`) and the
// labels of `hits`, the sensor model applied when `noise.enabled`. `return_keep`, when
// set, scales the chance a surface returns depth (a dark surface's weak infrared
// return); it draws nothing, so the random stream is the same with or without it.
void sense_pixels(const std::vector<PixelHit>& hits, const CameraIntrinsics& cam,
                  const SensorNoiseParams& noise, Draws& draws,
                  const std::function<Rgb(int label)>& colour, Frame& frame,
                  std::vector<int>& labels,
                  const std::function<double(const SurfaceHit&)>& return_keep = {});

}  // namespace annex::synthetic_pixels
