// Scanning one generated object alone (the shape tests of test_runtime_rooms).
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>

#include <gtest/gtest.h>

#include "annex/runtime/scanner.h"
#include "annex/runtime/synthetic_scene.h"

namespace annex {

// Object 0 of a one-object scene seen from `distance_m` at `tilt_deg` (scene seed
// `seed`), the object standing on the aim point: its truth, and the scanned object most
// of whose pixels show it (none when no scanned object does).
struct OneScan {
  PhysicalObject truth;
  std::optional<PhysicalObject> scanned;
};

inline std::optional<OneScan> scan_one_seen(SyntheticObject object, double distance_m,
                                            double tilt_deg, std::uint64_t seed = 11,
                                            const ScanParams& params = {}) {
  SyntheticSceneParams p;
  p.seed = seed;
  p.object_count = 0;
  p.camera_distance_min_m = p.camera_distance_max_m = distance_m;
  p.camera_tilt_min_deg = p.camera_tilt_max_deg = tilt_deg;
  Result<SyntheticScene> s = generate_scene(p);
  EXPECT_TRUE(s.ok());
  if (!s) return std::nullopt;
  const double t = s->camera_tilt_deg * 3.14159265358979323846 / 180;
  const Vec3 aim = s->camera_position +
                   Vec3{0, std::cos(t), -std::sin(t)} * (s->camera_position.z / std::sin(t));
  object.center.x = aim.x;
  object.center.y = aim.y;
  s->objects = {object};
  const SyntheticFrame f = render_scene(*s);
  const Result<ScanResult> scan = scan_frame(f.frame, params);
  EXPECT_TRUE(scan.ok());
  if (!scan) return std::nullopt;
  OneScan seen{f.truth.objects.at(0), std::nullopt};
  for (std::size_t k = 0; k < scan->clusters.size(); ++k) {
    int mine = 0;
    for (int i : scan->clusters[k].pixels) mine += f.labels[static_cast<std::size_t>(i)] == 0;
    if (2 * mine > static_cast<int>(scan->clusters[k].pixels.size())) {
      seen.scanned = scan->scene.objects[k];
      break;
    }
  }
  return seen;
}

// The scanned object of scan_one_seen alone.
inline std::optional<PhysicalObject> scan_one(SyntheticObject object, double distance_m,
                                              double tilt_deg, std::uint64_t seed = 11,
                                              const ScanParams& params = {}) {
  const std::optional<OneScan> seen =
      scan_one_seen(std::move(object), distance_m, tilt_deg, seed, params);
  return seen ? seen->scanned : std::nullopt;
}

}  // namespace annex
