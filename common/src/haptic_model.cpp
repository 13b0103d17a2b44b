#include "annex/common/haptic_model.h"

#include <utility>

namespace annex {

Primitive make_primitive(ShapeKind kind, std::string name) {
  Primitive p;
  p.name = std::move(name);
  p.kind = kind;
  p.dimensions.assign(static_cast<size_t>(dimension_count(kind)), Dimension{});
  return p;
}

}  // namespace annex
