// Scanning one seeded room of room_scene_params whole, and finding its truth objects
// (the room tests that follow one object of a measured room).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "annex/runtime/scanner.h"
#include "annex/runtime/synthetic_scene.h"
#include "label_owner.h"

namespace annex {

// A room of room_scene_params scanned: each truth object's scanned object (the largest
// of those most of whose pixels show it) and how many show it.
struct RoomScan {
  SyntheticScene scene;
  PhysicalScene truth;
  std::vector<SupportSurface> supports;  // the scan's
  std::vector<std::optional<PhysicalObject>> of;
  std::vector<int> pieces;
};

inline RoomScan scan_room(std::uint64_t seed, const ScanParams& params) {
  RoomScan r;
  const Result<SyntheticScene> s = generate_scene(room_scene_params(seed));
  EXPECT_TRUE(s.ok()) << seed;
  if (!s) return r;
  r.scene = *s;
  const SyntheticFrame f = render_scene(*s);
  r.truth = f.truth;
  const Result<ScanResult> scan = scan_frame(f.frame, params);
  EXPECT_TRUE(scan.ok()) << seed;
  if (!scan) return r;
  r.supports = scan->scene.supports;
  r.of.resize(s->objects.size());
  r.pieces.resize(s->objects.size(), 0);
  std::vector<std::size_t> size(s->objects.size(), 0);
  for (std::size_t k = 0; k < scan->clusters.size(); ++k) {
    const int owner = majority_label(f, scan->clusters[k]);
    if (owner < 0 || owner >= static_cast<int>(s->objects.size())) continue;
    const auto t = static_cast<std::size_t>(owner);
    ++r.pieces[t];
    if (scan->clusters[k].pixels.size() > size[t]) {
      size[t] = scan->clusters[k].pixels.size();
      r.of[t] = scan->scene.objects[k];
    }
  }
  return r;
}

// The first object of the room for which `is` holds, -1 none.
template <typename Is>
int find_object(const SyntheticScene& s, Is is) {
  for (std::size_t t = 0; t < s.objects.size(); ++t)
    if (is(s.objects[t])) return static_cast<int>(t);
  return -1;
}

}  // namespace annex
