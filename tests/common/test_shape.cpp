#include "annex/common/shape.h"

#include <gtest/gtest.h>

#include <vector>

#include "annex/common/haptic_model.h"

namespace annex {
namespace {

TEST(Shape, NamesRoundTrip) {
  for (ShapeKind k : kAllShapes) EXPECT_EQ(shape_from_name(shape_name(k)), k);
  EXPECT_FALSE(shape_from_name("cube").has_value());
  EXPECT_FALSE(shape_from_name("").has_value());
}

TEST(Shape, DimensionNames) {
  EXPECT_EQ(dimension_count(ShapeKind::sphere), 1);
  EXPECT_EQ(dimension_count(ShapeKind::cylinder), 2);
  EXPECT_EQ(dimension_count(ShapeKind::cone), 2);
  EXPECT_EQ(dimension_count(ShapeKind::torus), 2);
  EXPECT_EQ(dimension_count(ShapeKind::box), 3);
  EXPECT_EQ(dimension_index(ShapeKind::torus, "minor_radius"), 1);
  EXPECT_EQ(dimension_index(ShapeKind::box, "size_z"), 2);
  EXPECT_EQ(dimension_index(ShapeKind::sphere, "height"), -1);
}

TEST(Shape, FootprintRadiusIsTheCircleTheShapeCoversOnItsSupport) {
  const std::vector<double> box{0.3, 0.4, 0.1};  // a 3-4-5 triangle: diagonal 0.5
  EXPECT_DOUBLE_EQ(footprint_radius(ShapeKind::box, box), 0.25);
  EXPECT_DOUBLE_EQ(footprint_radius(ShapeKind::plane, std::vector<double>{0.6, 0.8}), 0.5);
  EXPECT_DOUBLE_EQ(footprint_radius(ShapeKind::torus, std::vector<double>{0.05, 0.02}), 0.07);
  EXPECT_DOUBLE_EQ(footprint_radius(ShapeKind::cone, std::vector<double>{0.08, 0.2}), 0.08);
  EXPECT_DOUBLE_EQ(footprint_radius(ShapeKind::sphere, std::vector<double>{0.04}), 0.04);
  // Too few dimensions: no footprint, no read past the end.
  EXPECT_EQ(footprint_radius(ShapeKind::box, std::vector<double>{0.3}), 0);
}

TEST(HapticModel, MakePrimitiveHasOneDimensionPerName) {
  for (ShapeKind k : kAllShapes) {
    const Primitive p = make_primitive(k, "x");
    EXPECT_EQ(static_cast<int>(p.dimensions.size()), dimension_count(k));
    EXPECT_EQ(p.kind, k);
  }
}

}  // namespace
}  // namespace annex
