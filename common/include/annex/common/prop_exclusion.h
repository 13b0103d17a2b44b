#pragma once
// The spec's exclude rules applied to scanned props: which rule, if any, forbids a
// physical object (docs/haptic-format.md, "Props never to annex").

#include <optional>
#include <string>

#include "annex/common/haptic_model.h"
#include "annex/common/physical_scene.h"

namespace annex {

// Height of an object's top above its support (the plane's signed distance of the
// highest point of its primitives' bounds); without a support, its extent along the
// salient primitive's axis. Bounds are exact for spheres and for axes along the
// normal, conservative for tilted shapes (a box's side directions are not recorded).
double prop_height_m(const PhysicalObject& object, const std::optional<Plane>& support);

// Index into spec.exclude of the first rule that forbids this object, or none.
std::optional<int> excluding_rule(const HapticSpec& spec, const PhysicalObject& object,
                                  const std::optional<Plane>& support);

// The rule as one line for reports and the editor: "shape sphere, radius min 0.11".
std::string describe_exclude_rule(const ExcludeRule& rule);

}  // namespace annex
