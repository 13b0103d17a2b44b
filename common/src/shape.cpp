#include "annex/common/shape.h"

#include <array>
#include <cmath>

namespace annex {
namespace {
constexpr std::array<std::string_view, 1> kSphereDims{"radius"};
constexpr std::array<std::string_view, 2> kCylinderDims{"radius", "height"};
constexpr std::array<std::string_view, 2> kConeDims{"radius", "height"};
constexpr std::array<std::string_view, 2> kTorusDims{"major_radius", "minor_radius"};
constexpr std::array<std::string_view, 3> kBoxDims{"size_x", "size_y", "size_z"};
constexpr std::array<std::string_view, 2> kPlaneDims{"size_x", "size_y"};
}  // namespace

std::string_view shape_name(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::sphere: return "sphere";
    case ShapeKind::cylinder: return "cylinder";
    case ShapeKind::cone: return "cone";
    case ShapeKind::torus: return "torus";
    case ShapeKind::box: return "box";
    case ShapeKind::plane: return "plane";
  }
  return "unknown";
}

std::optional<ShapeKind> shape_from_name(std::string_view name) {
  for (ShapeKind k : kAllShapes)
    if (shape_name(k) == name) return k;
  return std::nullopt;
}

std::span<const std::string_view> dimension_names(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::sphere: return kSphereDims;
    case ShapeKind::cylinder: return kCylinderDims;
    case ShapeKind::cone: return kConeDims;
    case ShapeKind::torus: return kTorusDims;
    case ShapeKind::box: return kBoxDims;
    case ShapeKind::plane: return kPlaneDims;
  }
  return {};
}

int dimension_index(ShapeKind kind, std::string_view name) {
  const auto names = dimension_names(kind);
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  return -1;
}

double footprint_radius(ShapeKind kind, std::span<const double> d) {
  if (d.size() < static_cast<size_t>(dimension_count(kind))) return 0;
  switch (kind) {
    case ShapeKind::sphere:
    case ShapeKind::cylinder:
    case ShapeKind::cone:
      return d[0];
    case ShapeKind::torus:
      return d[0] + d[1];
    case ShapeKind::box:
    case ShapeKind::plane:
      return 0.5 * std::hypot(d[0], d[1]);
  }
  return 0;
}

}  // namespace annex
