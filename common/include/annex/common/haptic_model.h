#pragma once
// The developer's haptic model (paper, "Developer Experience"): per virtual object,
// primitives placed on its visual mesh, three levels of priority and per-dimension
// scaling limits. This is what the editor saves and the runtime reads.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/shape.h"

namespace annex {

// One dimension of a primitive: its size on the virtual model, its priority w_h
// and the scale factors the developer allows when the model is fitted to a prop.
struct Dimension {
  double value_m = 0.1;
  double weight = 1.0;     // w_h in [0, 1]
  double min_scale = 0.5;  // 0 < min_scale <= max_scale
  double max_scale = 2.0;
  bool operator==(const Dimension&) const = default;
};

struct Primitive {
  std::string name;
  ShapeKind kind = ShapeKind::cylinder;
  Pose pose;                           // relative to the virtual object's origin
  double weight = 1.0;                 // w_s in [0, 1]
  std::vector<Dimension> dimensions;   // dimension_count(kind) entries, in dimension_names order
  bool operator==(const Primitive&) const = default;
};

struct VirtualObject {
  std::string name;
  std::string mesh;          // path of the visual mesh, relative to the spec file
  bool annexable = true;     // false: always virtual-only, never matched
  double priority = 1.0;     // w_o in [0, 1]
  std::vector<Primitive> primitives;  // as authored; the Voter ranks them by w_s
  double min_vote = 0.0;  // a prop voting less is never matched (docs/voting.md)
  // Metres per mesh unit: the visual mesh is drawn scaled by it (a model authored in
  // centimetres has 0.01, a duck modelled 1.6 m tall but 12 cm in the scene 0.075).
  // Primitive positions and sizes are in metres of the scaled model.
  double model_scale = 1.0;
  bool operator==(const VirtualObject&) const = default;
};

// One size range of an exclude rule, inclusive, in metres: a dimension of the rule's
// shape (`radius`, `size_x`...) or kPropHeight, the prop's height above its support.
inline constexpr std::string_view kPropHeight = "prop_height";
struct SizeRange {
  std::string dimension;
  std::optional<double> min_m;  // none: no lower bound
  std::optional<double> max_m;  // none: no upper bound
  bool operator==(const SizeRange&) const = default;
};

// Props the developer forbids (the paper's future work, for safety: nothing taller
// than 40 cm, no sphere larger than a football). A physical object is excluded when
// one of its primitives has `shape` (any shape when unset) and every range holds.
struct ExcludeRule {
  std::string name;
  std::optional<ShapeKind> shape;
  std::vector<SizeRange> ranges;
  bool operator==(const ExcludeRule&) const = default;
};

// A whole .haptic file: the virtual objects of one AR scene and the props never to annex.
struct HapticSpec {
  std::vector<VirtualObject> objects;
  std::vector<ExcludeRule> exclude = {};  // (a default, so {objects} initialisers stay warning-free)
  bool operator==(const HapticSpec&) const = default;
};

// A primitive of `kind` with default dimensions (10 cm), weights 1 and limits [0.5, 2].
Primitive make_primitive(ShapeKind kind, std::string name);

}  // namespace annex
