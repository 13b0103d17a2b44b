#pragma once
// The set-up of the AnnexSession tests (tests/runtime test_faults, test_session_exclude,
// test_session_background, test_tracking_session) and bench/bench_session: generated
// scenes of a few props and the spec that has one virtual object per prop. No gtest, so
// the benchmark can use it too: a scene that cannot be drawn throws, and a test fails
// with the message.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "annex/common/haptic_model.h"
#include "annex/runtime/synthetic_scene.h"

namespace annex::test {

// generate_scene with this seed, these kinds (drawn in turn) and this many objects.
inline SyntheticScene make_scene(std::uint64_t seed,
                                 std::vector<ShapeKind> kinds = {ShapeKind::cylinder,
                                                                 ShapeKind::sphere, ShapeKind::box},
                                 int objects = 3) {
  SyntheticSceneParams p;
  p.seed = seed;
  p.object_count = objects;
  p.kinds = std::move(kinds);
  Result<SyntheticScene> s = generate_scene(p);
  if (!s)
    throw std::runtime_error("no scene from seed " + std::to_string(seed) + ": " +
                             s.error().format());
  return std::move(s).value();
}

// Three props of three different shapes (the first seed from `seed` on that draws
// them), so that no tracker can mistake one prop for another of its shape.
inline SyntheticScene three_props(std::uint64_t seed) {
  SyntheticSceneParams p;
  p.object_count = 3;
  p.kinds = {ShapeKind::cylinder, ShapeKind::sphere, ShapeKind::box};
  for (p.seed = seed; p.seed < seed + 200; ++p.seed) {
    Result<SyntheticScene> s = generate_scene(p);
    if (!s) continue;
    const auto& o = s->objects;
    if (o.size() == 3 && o[0].kind != o[1].kind && o[1].kind != o[2].kind && o[0].kind != o[2].kind)
      return std::move(s).value();
  }
  throw std::runtime_error("no scene of three different shapes from seed " + std::to_string(seed));
}

// One virtual object per synthetic object, of its shape and size ("v0", "v1", ...).
inline HapticSpec spec_for(const SyntheticScene& scene) {
  HapticSpec spec;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    VirtualObject v;
    v.name = "v" + std::to_string(i);
    Primitive p = make_primitive(scene.objects[i].kind, "body");
    for (size_t d = 0; d < p.dimensions.size(); ++d)
      p.dimensions[d].value_m = scene.objects[i].dimensions_m[d];
    v.primitives.push_back(p);
    spec.objects.push_back(v);
  }
  return spec;
}

}  // namespace annex::test
