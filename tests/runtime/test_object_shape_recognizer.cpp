// ObjectShapeRecognizer on analytic point sets: the visible half of each primitive
// resting on a plane, seen from a camera at the origin, with seeded depth noise.
#include "annex/runtime/object_shape_recognizer.h"

#include "annex/reference/object_shape_recognizer_cgal.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>

namespace annex {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The table is the plane y = 0.4 (camera frame, y down), up = -y: a point's height
// above it is 0.4 - y. Objects stand about 1 m in front of the camera.
const Plane kTable{{0, -1, 0}, 0.4};
const Vec3 kUp{0, -1, 0};

struct Surface {
  Vec3 p, n;
};

// Keeps the points of a convex solid that face the camera, adds depth noise.
struct Cloud {
  std::vector<Vec3> points, normals;
};

Cloud visible(const std::vector<Surface>& surface, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, sigma);
  Cloud c;
  for (const Surface& s : surface) {
    if (dot(s.n, s.p) >= 0) continue;  // faces away from the camera at the origin
    if (s.p.y > 0.4 - 1e-4 && s.n.y > 0.5) continue;
    const Vec3 ray = normalized(s.p);
    c.points.push_back(s.p + ray * noise(rng));
    c.normals.push_back(s.n);
  }
  return c;
}

// Base centre on the table at (x, 0.4, z); shapes built around +up.
Vec3 on_table(double x, double z, double h) { return {x, 0.4 - h, z}; }

std::vector<Surface> cylinder(Vec3 base, double r, double h, int n = 120) {
  std::vector<Surface> out;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= n / 2; ++j) {
      const double t = 2 * kPi * i / n, z = h * j / (n / 2);
      const Vec3 radial{std::cos(t), 0, std::sin(t)};
      out.push_back({base + radial * r + kUp * z, radial});
    }
  for (int i = 0; i < n; ++i)
    for (int j = 1; j < n / 4; ++j) {
      const double t = 2 * kPi * i / n, rr = r * j / (n / 4);
      out.push_back({base + Vec3{std::cos(t) * rr, 0, std::sin(t) * rr} + kUp * h, kUp});
    }
  return out;
}

std::vector<Surface> cone(Vec3 base, double r, double h, double top_r = 0, int n = 120) {
  std::vector<Surface> out;
  const double slope = (r - top_r) / h;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= n / 2; ++j) {
      const double t = 2 * kPi * i / n, z = h * j / (n / 2);
      const Vec3 radial{std::cos(t), 0, std::sin(t)};
      const double rr = r - slope * z;
      out.push_back({base + radial * rr + kUp * z, normalized(radial + kUp * slope)});
    }
  return out;
}

std::vector<Surface> sphere(Vec3 center, double r, int n = 120) {
  std::vector<Surface> out;
  for (int i = 0; i < n; ++i)
    for (int j = 1; j < n / 2; ++j) {
      const double t = 2 * kPi * i / n, f = kPi * j / (n / 2);
      const Vec3 d{std::sin(f) * std::cos(t), std::cos(f), std::sin(f) * std::sin(t)};
      out.push_back({center + d * r, d});
    }
  return out;
}

std::vector<Surface> torus(Vec3 center, double major, double minor, int n = 160) {
  std::vector<Surface> out;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n / 3; ++j) {
      const double t = 2 * kPi * i / n, f = 2 * kPi * j / (n / 3);
      const Vec3 radial{std::cos(t), 0, std::sin(t)};
      const Vec3 d = radial * std::cos(f) + kUp * std::sin(f);
      out.push_back({center + radial * major + d * minor, d});
    }
  return out;
}

// Box with sides along rotated x/z by `yaw`.
std::vector<Surface> box(Vec3 base, double sx, double sz, double h, double yaw, int n = 60) {
  std::vector<Surface> out;
  const Vec3 ex{std::cos(yaw), 0, std::sin(yaw)}, ez{-std::sin(yaw), 0, std::cos(yaw)};
  auto face = [&](Vec3 origin, Vec3 a, Vec3 b, Vec3 normal) {
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j)
        out.push_back({origin + a * (double(i) / n) + b * (double(j) / n), normal});
  };
  const Vec3 c0 = base - ex * (sx / 2) - ez * (sz / 2);
  face(c0 + kUp * h, ex * sx, ez * sz, kUp);
  face(c0, ex * sx, kUp * h, ez * -1.0);
  face(c0 + ez * sz, ex * sx, kUp * h, ez);
  face(c0, ez * sz, kUp * h, ex * -1.0);
  face(c0 + ex * sx, ez * sz, kUp * h, ex);
  return out;
}

ObjectShape recognize(const Cloud& c) { return recognize_object_shape(c.points, c.normals, kTable); }

TEST(ObjectShapeRecognizer, UprightCylinderRadiusFromVisibleArcAndHeightFromPlane) {
  const Cloud c = visible(cylinder(on_table(0.1, 1.0, 0), 0.045, 0.18), 0.002, 1);
  const ObjectShape s = recognize(c);
  ASSERT_FALSE(s.primitives.empty());
  const PhysicalPrimitive& p = s.primitives[0].primitive;
  EXPECT_EQ(p.kind, ShapeKind::cylinder);
  EXPECT_NEAR(p.dimensions_m[0], 0.045, 0.003);
  EXPECT_NEAR(p.dimensions_m[1], 0.18, 0.006);
  EXPECT_NEAR(dot(normalized(p.axis), kUp), 1.0, 1e-6);
  EXPECT_NEAR(p.center.x, 0.1, 0.004);
  EXPECT_NEAR(p.center.y, 0.4 - 0.09, 0.006);
  EXPECT_GT(s.fit, 0.8);
}

TEST(ObjectShapeRecognizer, ConeHeightReachesTheApex) {
  const Cloud c = visible(cone(on_table(-0.1, 1.1, 0), 0.06, 0.15), 0.0015, 2);
  const ObjectShape s = recognize(c);
  ASSERT_FALSE(s.primitives.empty());
  const PhysicalPrimitive& p = s.primitives[0].primitive;
  EXPECT_EQ(p.kind, ShapeKind::cone);
  EXPECT_NEAR(p.dimensions_m[0], 0.06, 0.004);
  EXPECT_NEAR(p.dimensions_m[1], 0.15, 0.01);
}

TEST(ObjectShapeRecognizer, CupLikeFrustumIsAConeWithItsNarrowRadius) {
  // A cup-like frustum, 5 cm at the base to 3.5 cm at the top: reported as itself, a cone
  // with its wide radius, its height and its narrow end's radius, pointing up.
  const Cloud c = visible(cone(on_table(0, 1.0, 0), 0.05, 0.15, 0.035), 0.0015, 12);
  const ObjectShape s = recognize(c);
  ASSERT_FALSE(s.primitives.empty());
  const PhysicalPrimitive& p = s.primitives[0].primitive;
  EXPECT_EQ(p.kind, ShapeKind::cone);
  EXPECT_NEAR(p.dimensions_m[0], 0.05, 0.004);
  EXPECT_NEAR(p.dimensions_m[1], 0.15, 0.01);
  EXPECT_NEAR(p.narrow_radius_m, 0.035, 0.004);
  EXPECT_GT(dot(normalized(p.axis), kUp), 0.999);
  EXPECT_GT(s.fit, 0.8);
}

TEST(ObjectShapeRecognizer, WithinShapeGrowsTheSolidByTheMargin) {
  ShapeFit fit;
  fit.primitive.kind = ShapeKind::box;
  fit.primitive.dimensions_m = {0.2, 0.1, 0.3};
  fit.primitive.center = {0, 0, 1};
  fit.primitive.axis = {0, -1, 0};
  fit.x_axis = {1, 0, 0};
  EXPECT_TRUE(within_shape(fit, {0.09, -0.14, 1.04}, 0.0));
  EXPECT_FALSE(within_shape(fit, {0.11, 0, 1}, 0.0));
  EXPECT_TRUE(within_shape(fit, {0.11, 0, 1}, 0.015));
  EXPECT_FALSE(within_shape(fit, {0, 0, 1.07}, 0.015));
  fit.primitive.kind = ShapeKind::cylinder;
  fit.primitive.dimensions_m = {0.05, 0.2};
  EXPECT_TRUE(within_shape(fit, {0.03, 0.09, 1.03}, 0.0));
  EXPECT_FALSE(within_shape(fit, {0.045, 0, 1.045}, 0.0));  // outside the circle
  EXPECT_TRUE(within_shape(fit, {0.045, 0, 1.045}, 0.02));
  EXPECT_FALSE(within_shape(fit, {0, 0.13, 1}, 0.02));  // above the top
}

TEST(ObjectShapeRecognizer, SphereRestingOnThePlane) {
  const Cloud c = visible(sphere(on_table(0, 0.9, 0.05), 0.05), 0.0015, 3);
  const ObjectShape s = recognize(c);
  ASSERT_FALSE(s.primitives.empty());
  EXPECT_EQ(s.primitives[0].primitive.kind, ShapeKind::sphere);
  EXPECT_NEAR(s.primitives[0].primitive.dimensions_m[0], 0.05, 0.003);
}

// A dark surface far away (the generator's dark objects): depth returns only where it
// faces the camera (cos of incidence above `lit`), `keep` of those pixels survive, and
// the smoother leaves the sparse points raw, with no normal.
Cloud dark(const std::vector<Surface>& surface, double lit, double keep, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pick(0, 1);
  Cloud c;
  for (const Surface& s : surface) {
    const Vec3 ray = normalized(s.p);
    if (-dot(s.n, ray) < lit || pick(rng) > keep) continue;
    std::normal_distribution<double> noise(0, DepthNoise{}.sigma_z(s.p.z));
    c.points.push_back(s.p + ray * noise(rng));
    c.normals.push_back({0, 0, 0});
  }
  return c;
}

// A dark ball 2.2 m away shows the cap that faces the camera: its free fit's radius and
// centre are ill-determined, its top is the ball's (shape_sphere_cap_depth_share).
TEST(ObjectShapeRecognizer, DarkBallsCapIsASphereFittedFromItsTop) {
  int spheres = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const Cloud c = dark(sphere(on_table(0.1, 2.2, 0.04), 0.04, 240), 0.75, 0.05, seed);
    ASSERT_GE(c.points.size(), 40u);
    const ObjectShape s = recognize(c);
    if (!s.primitives.empty() && s.primitives[0].primitive.kind == ShapeKind::sphere) {
      ++spheres;
      EXPECT_NEAR(s.primitives[0].primitive.dimensions_m[0], 0.04, 0.008);
    }
  }
  EXPECT_GE(spheres, 5);
}

// A dark box's lit faces, 2 to 2.3 m away, curve along the view only, at their edge
// (rooms 7059's box was a sphere): not a sphere (shape_sphere_min_curvature_share).
TEST(ObjectShapeRecognizer, DarkBoxsLitFacesAreNoSphere) {
  for (double z : {2.0, 2.3})
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      const Cloud c = dark(box(on_table(0.1, z, 0), 0.05, 0.1, 0.076, 0.6, 120), 0.7, 0.05, seed);
      const ObjectShape s = recognize(c);
      ASSERT_FALSE(s.primitives.empty());
      EXPECT_NE(s.primitives[0].primitive.kind, ShapeKind::sphere) << z << " m, seed " << seed;
    }
}

TEST(ObjectShapeRecognizer, TorusLyingFlat) {
  const Cloud c = visible(torus(on_table(0.05, 0.9, 0.02), 0.06, 0.02), 0.0015, 4);
  const ObjectShape s = recognize(c);
  ASSERT_FALSE(s.primitives.empty());
  const PhysicalPrimitive& p = s.primitives[0].primitive;
  EXPECT_EQ(p.kind, ShapeKind::torus);
  EXPECT_NEAR(p.dimensions_m[0], 0.06, 0.004);
  EXPECT_NEAR(p.dimensions_m[1], 0.02, 0.003);
}

// The strip of a ball's edge that a straight cut gives the ring beside it (fresh rooms
// 9514): the ball's surface nearer the ring than `depth` past its own side, rising far
// above the ring's tube.
std::vector<Surface> ball_edge(Vec3 center, double r, double depth) {
  std::vector<Surface> edge;
  for (const Surface& q : sphere(center, r))
    if (q.p.x < center.x - r + depth) edge.push_back(q);
  return edge;
}

TEST(ObjectShapeRecognizer, TorusLyingFlatKeepsItsTubeUnderANeighboursStrip) {
  // A ring (6 and 2 cm radii) and a strip 2 cm deep of a ball's edge touching it, up to
  // 12 cm above the table: the torus is fitted to the points under 1.5 times the height
  // most of them lie under (shape_torus_own_points). Fitted to every point, the strip
  // pulls the tube up round it, or keeps the torus from being tried.
  const Vec3 ring = on_table(0.05, 0.9, 0.02);
  const double ball_r = 0.07;
  std::vector<Surface> both = torus(ring, 0.06, 0.02);
  const std::vector<Surface> strip =
      ball_edge(on_table(0.05 + 0.08 + ball_r, 0.9, ball_r), ball_r, 0.02);
  both.insert(both.end(), strip.begin(), strip.end());
  const Cloud c = visible(both, 0.0015, 4);
  const ObjectShape s = recognize(c);
  ASSERT_FALSE(s.primitives.empty());
  const PhysicalPrimitive& p = s.primitives[0].primitive;
  EXPECT_EQ(p.kind, ShapeKind::torus);
  EXPECT_NEAR(p.dimensions_m[0], 0.06, 0.006);
  EXPECT_NEAR(p.dimensions_m[1], 0.02, 0.004);
  ShapeRecognizerParams every_point;
  every_point.torus_own_points = false;
  const ObjectShape before = recognize_object_shape(c.points, c.normals, kTable, every_point);
  const bool tube = !before.primitives.empty() &&
                    before.primitives[0].primitive.kind == ShapeKind::torus &&
                    std::abs(before.primitives[0].primitive.dimensions_m[1] - 0.02) < 0.004;
  EXPECT_FALSE(tube);
}

// A cylinder lying on the table along azimuth `yaw`, its axis level at its radius.
std::vector<Surface> lying_cylinder(Vec3 middle, double r, double length, double yaw, int n = 120) {
  std::vector<Surface> out;
  const Vec3 along{std::cos(yaw), 0, std::sin(yaw)}, across{-std::sin(yaw), 0, std::cos(yaw)};
  const Vec3 axis = middle + kUp * r;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= n / 2; ++j) {
      const double t = 2 * kPi * i / n, a = length * (double(j) / (n / 2) - 0.5);
      const Vec3 radial = across * std::cos(t) + kUp * std::sin(t);
      out.push_back({axis + along * a + radial * r, radial});
    }
  for (const double end : {-1.0, 1.0})
    for (int i = 0; i < n; ++i)
      for (int j = 1; j < n / 4; ++j) {
        const double t = 2 * kPi * i / n, rr = r * j / (n / 4);
        const Vec3 radial = across * std::cos(t) + kUp * std::sin(t);
        out.push_back({axis + along * (end * length / 2) + radial * rr, along * end});
      }
  return out;
}

TEST(ObjectShapeRecognizer, ATinOnItsSideShorterThanWideIsALevelCylinder) {
  // Rooms 13085 (session 43): a tin 9 cm long of 4.6 cm radius on its side, its footprint
  // shorter along its axis than across: the lying cylinder is tried along either side of
  // the footprint, its circle on the side's points (a lid's lie inside it and shrank it).
  for (const double yaw : {0.3, 1.2}) {
    const Cloud c = visible(lying_cylinder(on_table(0.05, 1.1, 0), 0.046, 0.09, yaw), 0.0015, 5);
    const ObjectShape s = recognize(c);
    ASSERT_FALSE(s.primitives.empty());
    const PhysicalPrimitive& p = s.primitives[0].primitive;
    EXPECT_EQ(p.kind, ShapeKind::cylinder) << "yaw " << yaw;
    EXPECT_LT(std::abs(dot(normalized(p.axis), kUp)), 0.05) << "yaw " << yaw;
    EXPECT_NEAR(p.dimensions_m[0], 0.046, 0.003) << "yaw " << yaw;
    EXPECT_NEAR(p.dimensions_m[1], 0.09, 0.008) << "yaw " << yaw;
  }
}

TEST(ObjectShapeRecognizer, BoxFootprintAndHeight) {
  const Cloud c = visible(box(on_table(0, 1.0, 0), 0.16, 0.09, 0.12, 0.5), 0.0015, 5);
  const ObjectShape s = recognize(c);
  ASSERT_FALSE(s.primitives.empty());
  const PhysicalPrimitive& p = s.primitives[0].primitive;
  EXPECT_EQ(p.kind, ShapeKind::box);
  EXPECT_NEAR(p.dimensions_m[0], 0.16, 0.005);  // the longer side is size_x
  EXPECT_NEAR(p.dimensions_m[1], 0.09, 0.005);
  EXPECT_NEAR(p.dimensions_m[2], 0.12, 0.005);
  // The box's x axis follows its longer side.
  const Vec3 ex{std::cos(0.5), 0, std::sin(0.5)};
  EXPECT_GT(std::abs(dot(s.primitives[0].x_axis, ex)), 0.99);
}

TEST(ObjectShapeRecognizer, BottleGetsBodyCylinderAndNeckCone) {
  std::vector<Surface> bottle = cylinder(on_table(0, 1.0, 0), 0.04, 0.16);
  // Drop the body's cap and put a shoulder cone (r 4 -> 0.6 cm over 8 cm) on it. (A
  // shoulder ending much wider, near a third of its base, is a frustum that reads as a
  // cylinder as well as a cone: GentleFrustumReadsAsCylinderOfMeanRadius.)
  std::erase_if(bottle, [](const Surface& s) { return s.n.y < -0.9; });
  for (const Surface& s : cone(on_table(0, 1.0, 0.16), 0.04, 0.08, 0.006)) bottle.push_back(s);
  const ObjectShape s = recognize(visible(bottle, 0.0015, 6));
  ASSERT_EQ(s.primitives.size(), 2u);
  EXPECT_EQ(s.primitives[0].primitive.kind, ShapeKind::cylinder);
  EXPECT_NEAR(s.primitives[0].primitive.dimensions_m[0], 0.04, 0.003);
  EXPECT_EQ(s.primitives[1].primitive.kind, ShapeKind::cone);
  // The neck sits above the body: heights 0.16 to 0.24 m, i.e. y from 0.24 to 0.16.
  EXPECT_LT(s.primitives[1].primitive.center.y, 0.4 - 0.16);
  EXPECT_GT(s.primitives[1].primitive.center.y, 0.4 - 0.24);
}

TEST(ObjectShapeRecognizer, ScatteredPointsAreUnknown) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.08, 0.08), h(0, 0.15);
  Cloud c;
  for (int i = 0; i < 1500; ++i) c.points.push_back({u(rng), 0.4 - h(rng), 1.0 + u(rng)});
  const ObjectShape s = recognize_object_shape(c.points, {}, kTable);
  EXPECT_TRUE(s.primitives.empty());
  EXPECT_EQ(s.fit, 0.0);
}

TEST(ObjectShapeRecognizer, TooFewPointsAreUnknown) {
  const std::vector<Vec3> pts{{0, 0.3, 1}, {0.01, 0.3, 1}, {0, 0.29, 1}};
  EXPECT_TRUE(recognize_object_shape(pts, {}, kTable).primitives.empty());
}

TEST(ObjectShapeRecognizer, DeterministicForASeed) {
  const Cloud c = visible(cylinder(on_table(0, 1.0, 0), 0.05, 0.1), 0.003, 8);
  const ObjectShape a = recognize(c), b = recognize(c);
  ASSERT_EQ(a.primitives.size(), b.primitives.size());
  for (size_t i = 0; i < a.primitives.size(); ++i)
    EXPECT_EQ(a.primitives[i].primitive, b.primitives[i].primitive);
}

TEST(ObjectShapeRecognizer, WorksWithoutNormals) {
  const Cloud c = visible(cylinder(on_table(0, 1.0, 0), 0.05, 0.2), 0.0015, 9);
  const ObjectShape s = recognize_object_shape(c.points, {}, kTable);
  ASSERT_FALSE(s.primitives.empty());
  EXPECT_EQ(s.primitives[0].primitive.kind, ShapeKind::cylinder);
  EXPECT_NEAR(s.primitives[0].primitive.dimensions_m[0], 0.05, 0.004);
}

// A real object as the scanner hands it over (tests/runtime/data/milk_detergent_bottle.txt):
// the points, their normals and the support's plane.
struct RealCluster {
  Cloud cloud;
  Plane support;
};

RealCluster read_real_cluster(const std::filesystem::path& path) {
  RealCluster out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    if (line.rfind("support", 0) == 0) {
      std::string word;
      fields >> word >> out.support.normal.x >> out.support.normal.y >> out.support.normal.z >>
          out.support.d;
      continue;
    }
    Vec3 p, n;
    if (fields >> p.x >> p.y >> p.z >> n.x >> n.y >> n.z)
      out.cloud.points.push_back(p), out.cloud.normals.push_back(n);
  }
  return out;
}

// `plane` turned by `deg` about the horizontal axis at `azimuth` radians from the camera's
// x axis, through the foot of `at` on it.
Plane tilted(const Plane& plane, double deg, double azimuth, Vec3 at) {
  const Vec3 ax = normalized(cross(plane.normal, Vec3{0, 0, 1})), az = cross(ax, plane.normal);
  const Vec3 about = ax * std::cos(azimuth) + az * std::sin(azimuth);
  const double a = deg * kPi / 180;
  const Vec3 n = plane.normal * std::cos(a) + cross(about, plane.normal) * std::sin(a);
  const Vec3 foot = at - plane.normal * (dot(plane.normal, at) + plane.d);
  return {n, -dot(n, foot)};
}

// The real detergent bottle (a handle on its side) is a cylinder covering 65 % of its
// points. With its floor turned by a tenth of a degree a tighter cylinder of 52 % ranked
// above that one and the bottle was `unknown`: only a candidate covering min_coverage is
// chosen when one does. (Turned about one other axis, and by 0.15 to 0.3 degree about
// three, the 65 % cylinder is not fitted at all and the bottle is still `unknown`:
// docs/BENCHMARKS.md, "Session 21".)
TEST(ObjectShapeRecognizer, ACandidateCoveringTooLittleDoesNotHideOneThatCovers) {
  const std::filesystem::path path =
      std::filesystem::path(ANNEX_SOURCE_DIR) / "tests/runtime/data/milk_detergent_bottle.txt";
  ASSERT_TRUE(std::filesystem::is_regular_file(path)) << path;
  const RealCluster bottle = read_real_cluster(path);
  ASSERT_EQ(bottle.cloud.points.size(), 793u);
  Vec3 mean{0, 0, 0};
  for (const Vec3& q : bottle.cloud.points) mean = mean + q;
  mean = mean * (1.0 / static_cast<double>(bottle.cloud.points.size()));
  const ShapeRecognizerParams params;
  for (double azimuth : {0.0, kPi / 4, -kPi / 4}) {
    const ObjectShape shape = recognize_object_shape(bottle.cloud.points, bottle.cloud.normals,
                                                     tilted(bottle.support, 0.1, azimuth, mean));
    ASSERT_FALSE(shape.primitives.empty()) << "turned about azimuth " << azimuth;
    EXPECT_EQ(shape.primitives[0].primitive.kind, ShapeKind::cylinder);
    EXPECT_GE(shape.fit, params.min_coverage);
    // The tighter cylinder is among the candidates, and covers too little.
    EXPECT_TRUE(
        std::any_of(shape.candidates.begin(), shape.candidates.end(), [&](const ShapeFit& c) {
          return c.primitive.kind == ShapeKind::cylinder && c.coverage < params.min_coverage;
        }));
  }
}

TEST(ObjectShapeRecognizerCgal, FindsTheCylinderOfAClearCylinder) {
  const Cloud c = visible(cylinder(on_table(0, 1.0, 0), 0.05, 0.2), 0.001, 10);
  const ObjectShape s = recognize_object_shape_cgal(c.points, c.normals);
  ASSERT_FALSE(s.primitives.empty());
  // Efficient RANSAC reports what it detects; on a clean cylinder the side wins.
  EXPECT_EQ(s.primitives[0].primitive.kind, ShapeKind::cylinder);
  EXPECT_NEAR(s.primitives[0].primitive.dimensions_m[0], 0.05, 0.005);
}

}  // namespace
}  // namespace annex
