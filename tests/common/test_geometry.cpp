#include "annex/common/geometry.h"

#include <gtest/gtest.h>

namespace annex {
namespace {

void expect_near(Vec3 a, Vec3 b) {
  EXPECT_NEAR(a.x, b.x, 1e-12);
  EXPECT_NEAR(a.y, b.y, 1e-12);
  EXPECT_NEAR(a.z, b.z, 1e-12);
}

TEST(Geometry, RotationFromZTakesZOntoAxis) {
  for (Vec3 axis : {Vec3{1, 0, 0}, Vec3{0, -1, 0}, Vec3{0, 0, 1}, Vec3{0, 0, -1}, Vec3{1, 2, 3}}) {
    expect_near(rotate(rotation_from_z(axis), {0, 0, 1}), normalized(axis));
  }
}

TEST(Geometry, QuaternionProductComposesRotations) {
  const Quat a = rotation_from_z({1, 0, 0});
  const Quat b = rotation_from_z({0, 1, 0});
  const Vec3 v{0.3, -0.2, 0.9};
  expect_near(rotate(a * b, v), rotate(a, rotate(b, v)));
}

TEST(Geometry, PoseAxis) {
  Pose p;
  expect_near(p.axis(), {0, 0, 1});
  p.rotation = rotation_from_z({0, -1, 0});
  expect_near(p.axis(), {0, -1, 0});
}

}  // namespace
}  // namespace annex
