// The generators' sensor pass: Kinect dropout and axial noise per pixel, shaded colours.
#include "synthetic_pixels.h"

#include <cmath>
#include <utility>

namespace annex::synthetic_pixels {
namespace {

Rgb shade(Rgb c, double cos_incidence) {
  const double f = 0.35 + 0.65 * cos_incidence;
  return {static_cast<std::uint8_t>(c[0] * f), static_cast<std::uint8_t>(c[1] * f),
          static_cast<std::uint8_t>(c[2] * f)};
}

}  // namespace

void sense_pixels(const std::vector<PixelHit>& hits, const CameraIntrinsics& cam,
                  const SensorNoiseParams& noise, Draws& draws,
                  const std::function<Rgb(int label)>& colour, Frame& frame,
                  std::vector<int>& labels,
                  const std::function<double(const SurfaceHit&)>& return_keep) {
  const int w = cam.width, h = cam.height;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  frame.width = w;
  frame.height = h;
  frame.intrinsics = cam;
  frame.points.resize(n);
  labels.resize(n);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto depth_at = [&](int u, int v) {
    return u < 0 || v < 0 || u >= w || v >= h ? inf
                                              : hits[static_cast<std::size_t>(v) * w + u].surface.depth;
  };
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      const PixelHit& px = hits[i];
      PointXYZRGB& p = frame.points[i];
      labels[i] = px.surface.label;
      p.x = p.y = p.z = nan;
      if (px.surface.label == kLabelNothing) continue;
      const Rgb c = shade(colour(px.surface.label), px.surface.cos_incidence);
      p.r = c[0], p.g = c[1], p.b = c[2];
      const double z = px.surface.depth;
      if (z < noise.min_range_m || z > noise.max_range_m) continue;
      double depth = z;
      if (noise.enabled) {
        double keep = 1 - noise.dropout;
        if (px.surface.cos_incidence < noise.grazing_cos)
          keep *= px.surface.cos_incidence / noise.grazing_cos;
        bool edge = false;
        double other = z;  // the neighbour's depth farthest from z (finite), for a mix
        for (const auto& [du, dv] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
          const double n = depth_at(u + du, v + dv);
          if (std::abs(n - z) <= noise.edge_jump_m) continue;
          edge = true;
          if (std::isfinite(n) && std::abs(n - z) > std::abs(other - z)) other = n;
        }
        if (edge) keep *= 1 - noise.edge_dropout;
        if (return_keep) keep *= return_keep(px.surface);
        const double draw = draws.unit(draws.rng);
        const double e = draws.gauss(draws.rng);
        if (draw >= keep) continue;
        // A flying pixel draws twice more (only then: the stream is as before without).
        if (edge && noise.flying_share > 0 && draws.unit(draws.rng) < noise.flying_share)
          depth = z + draws.unit(draws.rng) * (other - z);
        depth += noise.axial.sigma_z(depth) * e;
      }
      p.x = static_cast<float>(px.ray_x * depth);
      p.y = static_cast<float>(px.ray_y * depth);
      p.z = static_cast<float>(depth);
    }
  }
}

}  // namespace annex::synthetic_pixels
