#include "annex/authoring/fit.h"

#include <cmath>

#include <gtest/gtest.h>

namespace annex::authoring {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Surface samples of a cylinder about `axis` (+Y or +Z), centred at c.
std::vector<Vec3> cylinder_points(double r, double h, Vec3 c, bool along_y) {
  std::vector<Vec3> pts;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j < 36; ++j) {
      const double t = 2 * kPi * j / 36, a = -h / 2 + h * i / 20;
      const Vec3 local = along_y ? Vec3{r * std::cos(t), a, r * std::sin(t)}
                                 : Vec3{r * std::cos(t), r * std::sin(t), a};
      pts.push_back(c + local);
    }
  return pts;
}

TEST(FitPrimitive, CylinderAlongY) {
  const auto pts = cylinder_points(0.04, 0.2, {0.1, 0.1, 0}, true);
  auto fit = fit_primitive(pts, ShapeKind::cylinder);
  ASSERT_TRUE(fit);
  const Vec3 axis = fit->pose.axis();
  EXPECT_NEAR(std::abs(axis.y), 1.0, 1e-6);
  EXPECT_NEAR(fit->dimensions[0], 0.04, 1e-3);
  EXPECT_NEAR(fit->dimensions[1], 0.2, 1e-6);
  EXPECT_NEAR(fit->pose.position.x, 0.1, 1e-6);
  EXPECT_NEAR(fit->pose.position.y, 0.1, 1e-6);
}

TEST(FitPrimitive, FlatDiscTakesItsThicknessAsAxis) {
  // A paddle blade: radius 7.5 cm, 1 cm thick along Z.
  const auto pts = cylinder_points(0.075, 0.01, {0, 0.17, 0}, false);
  auto fit = fit_primitive(pts, ShapeKind::cylinder);
  ASSERT_TRUE(fit);
  EXPECT_NEAR(std::abs(fit->pose.axis().z), 1.0, 1e-6);
  EXPECT_NEAR(fit->dimensions[0], 0.075, 1e-3);
  EXPECT_NEAR(fit->dimensions[1], 0.01, 1e-6);
}

TEST(FitPrimitive, ConePointsFromBaseToApex) {
  // Base radius 5 cm at y = 0, apex at y = 0.1.
  std::vector<Vec3> pts;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j < 36; ++j) {
      const double y = 0.1 * i / 20, r = 0.05 * (1 - y / 0.1), t = 2 * kPi * j / 36;
      pts.push_back({r * std::cos(t), y, r * std::sin(t)});
    }
  auto fit = fit_primitive(pts, ShapeKind::cone);
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->pose.axis().y, 1.0, 1e-6);
  EXPECT_NEAR(fit->dimensions[0], 0.05, 1e-3);
  EXPECT_NEAR(fit->dimensions[1], 0.1, 1e-6);
  // Upside down: the axis follows.
  for (Vec3& p : pts) p.y = -p.y;
  auto flipped = fit_primitive(pts, ShapeKind::cone);
  ASSERT_TRUE(flipped);
  EXPECT_NEAR(flipped->pose.axis().y, -1.0, 1e-6);
}

TEST(FitPrimitive, SphereAndBox) {
  std::vector<Vec3> sphere;
  for (int i = 1; i < 18; ++i)
    for (int j = 0; j < 36; ++j) {
      const double th = kPi * i / 18, ph = 2 * kPi * j / 36;
      sphere.push_back({0.09 * std::sin(th) * std::cos(ph), 0.1 + 0.09 * std::cos(th),
                        0.09 * std::sin(th) * std::sin(ph)});
    }
  sphere.push_back({0, 0.19, 0});
  sphere.push_back({0, 0.01, 0});
  auto s = fit_primitive(sphere, ShapeKind::sphere);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->dimensions[0], 0.09, 1e-3);
  EXPECT_NEAR(s->pose.position.y, 0.1, 1e-3);

  // Box 0.3 x 0.2 x 0.1 rotated 30 degrees about Z.
  std::vector<Vec3> box;
  const double c = std::cos(kPi / 6), sn = std::sin(kPi / 6);
  for (int i = 0; i < 8; ++i) {
    const Vec3 p{(i & 1) ? 0.15 : -0.15, (i & 2) ? 0.1 : -0.1, (i & 4) ? 0.05 : -0.05};
    box.push_back({c * p.x - sn * p.y, sn * p.x + c * p.y, p.z});
  }
  auto b = fit_primitive(box, ShapeKind::box);
  ASSERT_TRUE(b);
  EXPECT_NEAR(b->dimensions[0], 0.3, 1e-6);
  EXPECT_NEAR(b->dimensions[1], 0.2, 1e-6);
  EXPECT_NEAR(b->dimensions[2], 0.1, 1e-6);
  const Vec3 x_axis = rotate(b->pose.rotation, {1, 0, 0});
  EXPECT_NEAR(std::abs(x_axis.x), c, 1e-6);
}

TEST(FitPrimitive, TorusLyingFlat) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 48; ++i)
    for (int j = 0; j < 16; ++j) {
      const double u = 2 * kPi * i / 48, v = 2 * kPi * j / 16;
      const double rr = 0.03 + 0.008 * std::cos(v);
      pts.push_back({rr * std::cos(u), 0.008 * std::sin(v), rr * std::sin(u)});
    }
  auto fit = fit_primitive(pts, ShapeKind::torus);
  ASSERT_TRUE(fit);
  EXPECT_NEAR(std::abs(fit->pose.axis().y), 1.0, 1e-6);
  EXPECT_NEAR(fit->dimensions[0], 0.03, 1e-3);
  EXPECT_NEAR(fit->dimensions[1], 0.008, 1e-4);
}

// A mug handle: 160 degrees of a ring standing upright beside the body. The bounding
// box's centre is 2 cm off the ring's; the circle fit finds the true centre.
TEST(FitPrimitive, TorusFromACShapedHandle) {
  const Vec3 c{0.044, 0.05, 0};
  std::vector<Vec3> pts;
  for (int i = 0; i <= 24; ++i)
    for (int j = 0; j < 16; ++j) {
      const double u = (-80 + 160.0 * i / 24) * kPi / 180, v = 2 * kPi * j / 16;
      const Vec3 dir{std::cos(u), std::sin(u), 0};
      pts.push_back(c + dir * (0.028 + 0.0065 * std::cos(v)) + Vec3{0, 0, 0.0065 * std::sin(v)});
    }
  auto fit = fit_primitive(pts, ShapeKind::torus);
  ASSERT_TRUE(fit);
  EXPECT_NEAR(std::abs(fit->pose.axis().z), 1.0, 1e-6);
  EXPECT_NEAR(fit->pose.position.x, 0.044, 5e-4);
  EXPECT_NEAR(fit->pose.position.y, 0.05, 5e-4);
  EXPECT_NEAR(fit->pose.position.z, 0.0, 1e-6);
  EXPECT_NEAR(fit->dimensions[0], 0.028, 5e-4);
  EXPECT_NEAR(fit->dimensions[1], 0.0065, 3e-4);
  // Local +X points from the ring's centre into the arc (the grip), here +X.
  EXPECT_GT(rotate(fit->pose.rotation, Vec3{1, 0, 0}).x, 0.99);
}

// The visible half of a curved neck (radius 3 to 5 cm along a wavy profile) about an
// axis tilted 20 degrees: the points' spread and the normals' covariance both lean, the
// normal lines all meet the axis. Fitted with its normals, the cone stands on that axis.
TEST(FitPrimitive, CurvedNeckSeenFromOneSideFindsItsAxisFromItsNormals) {
  const double tilt = 20 * kPi / 180;
  const Vec3 axis{std::sin(tilt), std::cos(tilt), 0};
  const Vec3 e0 = normalized(cross(axis, Vec3{0, 0, 1})), e1 = cross(axis, e0);
  std::vector<Vec3> pts, normals;
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 30; ++j) {
      const double h = 0.1 * i / 40, t = kPi * j / 30;  // half the round
      const double r = 0.05 - 0.02 * h / 0.1 + 0.004 * std::sin(60 * h), dr = -0.2 + 0.24 * std::cos(60 * h);
      const Vec3 radial = e0 * std::cos(t) + e1 * std::sin(t);
      pts.push_back(Vec3{0.01, 0.2, 0} + axis * h + radial * r);
      normals.push_back(normalized(radial - axis * dr));
    }
  FitOptions options;
  options.normals = normals;
  auto fit = fit_primitive(pts, ShapeKind::cone, options);
  ASSERT_TRUE(fit);
  EXPECT_GT(dot(fit->pose.axis(), axis), std::cos(1.0 * kPi / 180));  // base below, apex up
  EXPECT_NEAR(fit->dimensions[1], 0.1, 0.01);
  // Without normals the half-shell's spread alone cannot tell.
  auto blind = fit_primitive(pts, ShapeKind::cone);
  ASSERT_TRUE(blind);
  EXPECT_LT(std::abs(dot(blind->pose.axis(), axis)), std::cos(1.0 * kPi / 180));
}

TEST(FitPrimitive, TooFewPointsIsAnError) {
  const std::vector<Vec3> pts{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  auto fit = fit_primitive(pts, ShapeKind::sphere);
  ASSERT_FALSE(fit);
  EXPECT_NE(fit.error().message.find("at least 4"), std::string::npos);
}

TEST(FitPrimitive, WithFitKeepsWeightsAndRoundsNoise) {
  Primitive p = make_primitive(ShapeKind::cylinder, "body");
  p.weight = 0.4;
  p.dimensions[0].weight = 0.8;
  FitResult f;
  f.pose.position = {1e-20, 0.123456789, -3e-19};
  f.dimensions = {0.0456031345, 0.2};
  const Primitive q = with_fit(p, f);
  EXPECT_EQ(q.name, "body");
  EXPECT_EQ(q.weight, 0.4);
  EXPECT_EQ(q.dimensions[0].weight, 0.8);
  EXPECT_EQ(q.pose.position.x, 0.0);
  EXPECT_FALSE(std::signbit(q.pose.position.z));
  EXPECT_NEAR(q.pose.position.y, 0.12346, 1e-12);
  EXPECT_NEAR(q.dimensions[0].value_m, 0.0456, 1e-12);
}

TEST(SymmetricEigen, DiagonalAndRotatedFrame) {
  const double m[3][3] = {{1, 0, 0}, {0, 3, 0}, {0, 0, 2}};
  const Eigen3 e = symmetric_eigen(m);
  EXPECT_NEAR(e.values[0], 3, 1e-12);
  EXPECT_NEAR(e.values[1], 2, 1e-12);
  EXPECT_NEAR(e.values[2], 1, 1e-12);
  EXPECT_NEAR(std::abs(e.vectors[0].y), 1, 1e-12);
  const Quat q = quat_from_frame({0, 1, 0}, {-1, 0, 0}, {0, 0, 1});  // 90 degrees about Z
  const Vec3 x = rotate(q, {1, 0, 0});
  EXPECT_NEAR(x.y, 1, 1e-12);
  EXPECT_NEAR(x.x, 0, 1e-12);
}

}  // namespace
}  // namespace annex::authoring
