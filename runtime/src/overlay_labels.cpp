// Run's overlay labels: project each overlay's points into each eye, then the scan
// picture's label layout and text (scan_overlay.h).
#include "annex/runtime/overlay_labels.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "annex/runtime/pose_tracker.h"
#include "annex/runtime/scan_overlay.h"

namespace annex {

std::string overlay_label_text(const AnnexedObject& object) {
  char vote[32];
  std::snprintf(vote, sizeof vote, "%.2f", object.vote);
  std::string text = object.virtual_name + " on " + object.physical_id + " " + vote;
  if (object.fit.clamped) text += " clamped";
  return text + " " + std::string(tracking_state_name(object.track.state));
}

void draw_overlay_labels(RgbaImage& image, std::span<const Eye> eyes,
                         const std::vector<OverlayLabel>& labels) {
  if (image.rgba.size() != static_cast<std::size_t>(image.width) * image.height * 4) return;
  int x0 = 0;
  for (const Eye& eye : eyes) {
    const CameraIntrinsics& k = eye.intrinsics;
    std::vector<ImageLabel> placed;
    for (const OverlayLabel& l : labels) {
      double top = k.height, bottom = -1, left = k.width, right = -1;
      for (const Vec3& world : l.points) {
        const Vec3 p = eye.eye_from_sensor.apply(world);
        if (!(p.z > eye.near_m) || !std::isfinite(p.x) || !std::isfinite(p.y)) continue;
        const double u = k.fx * p.x / p.z + k.cx, v = k.fy * p.y / p.z + k.cy;
        if (u < 0 || v < 0 || u >= k.width || v >= k.height) continue;
        top = std::min(top, v), bottom = std::max(bottom, v);
        left = std::min(left, u), right = std::max(right, u);
      }
      if (bottom < 0) continue;  // not in this eye's view
      ImageLabel il;
      il.text = l.text;
      il.colour = l.dim ? std::array<std::uint8_t, 3>{160, 160, 160}
                        : std::array<std::uint8_t, 3>{255, 255, 255};
      il.top = static_cast<int>(top);
      il.bottom = static_cast<int>(bottom);
      il.left = static_cast<int>(left);
      il.right = static_cast<int>(right);
      placed.push_back(std::move(il));
    }
    draw_labels(image.rgba.data(), image.width, image.height, 4, placed, x0, k.width);
    x0 += k.width;
  }
}

std::vector<Vec3> label_points(const MeshData& mesh, std::size_t max_points) {
  const std::size_t n = mesh.vertex_count();
  std::vector<Vec3> out;
  if (n == 0 || max_points == 0) return out;
  const std::size_t step = std::max<std::size_t>(1, n / max_points);
  for (std::size_t i = 0; i < n; i += step) out.push_back(mesh.vertex(i));
  return out;
}

}  // namespace annex
