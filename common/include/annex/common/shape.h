#pragma once
// The primitive shapes a haptic model is built from and a scan recognises.
// The paper's four (sphere, cylinder, cone, torus) plus box and plane from its future
// work: a plane is a flat rectangle (a virtual panel, screen or keyboard) matched to a
// real flat surface (a table's free region, a box's face), not to a solid object.

#include <optional>
#include <span>
#include <string_view>

namespace annex {

enum class ShapeKind { sphere, cylinder, cone, torus, box, plane };

inline constexpr ShapeKind kAllShapes[] = {ShapeKind::sphere, ShapeKind::cylinder,
                                           ShapeKind::cone,   ShapeKind::torus,
                                           ShapeKind::box,    ShapeKind::plane};
// The solid shapes: what the recognizer fits to an object and synthetic scenes are made of.
inline constexpr ShapeKind kSolidShapes[] = {ShapeKind::sphere, ShapeKind::cylinder,
                                             ShapeKind::cone, ShapeKind::torus, ShapeKind::box};

std::string_view shape_name(ShapeKind kind);
std::optional<ShapeKind> shape_from_name(std::string_view name);

// Named dimensions in metres, in the order files list them and votes compare them.
// sphere: radius; cylinder: radius, height; cone: radius (of the base), height;
// torus: major_radius, minor_radius; box: size_x, size_y, size_z;
// plane: size_x, size_y (a rectangle in its local x-y plane, its normal the local z axis).
std::span<const std::string_view> dimension_names(ShapeKind kind);
inline int dimension_count(ShapeKind kind) {
  return static_cast<int>(dimension_names(kind).size());
}
// Index of a dimension name for this shape, or -1.
int dimension_index(ShapeKind kind, std::string_view name);

// Radius of the circle the shape covers on its support, whatever its yaw: a round
// shape's radius (a cone's base, its widest), a torus's outer radius, a box's or plane's
// half diagonal. 0 when `dimensions` holds fewer than dimension_count(kind).
double footprint_radius(ShapeKind kind, std::span<const double> dimensions);

}  // namespace annex
