// The synthetic scene generator: determinism, the Kinect noise statistics, and
// ground truth checked against the rendered points with independent distance formulas.
#include "annex/runtime/synthetic_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace annex {
namespace {

constexpr double kPi = 3.14159265358979323846;

double sigma(double z) { return 0.0012 + 0.0019 * (z - 0.4) * (z - 0.4); }

double point_norm(const PointXYZRGB& p) { return std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z); }

// Distance from (a, b) to the segment (a0, b0)-(a1, b1) in a 2D half-plane section.
double segment_distance(double a, double b, double a0, double b0, double a1, double b1) {
  const double da = a1 - a0, db = b1 - b0;
  const double t = std::clamp(((a - a0) * da + (b - b0) * db) / (da * da + db * db), 0.0, 1.0);
  return std::hypot(a - (a0 + t * da), b - (b0 + t * db));
}

// Unsigned distance from a camera-frame point to the surface of object i, from the
// ground truth (centre, axis, dimensions) alone, except a box's yaw, taken from the scene.
double surface_distance(const SyntheticScene& scene, const PhysicalScene& truth, std::size_t i,
                        Vec3 p) {
  const PhysicalPrimitive& prim = truth.objects[i].primitives[0];
  const Vec3 rel = p - prim.center;
  const double h = dot(rel, prim.axis);
  const double rho = norm(rel - prim.axis * h);
  const auto& d = prim.dimensions_m;
  switch (prim.kind) {
    case ShapeKind::sphere: return std::abs(norm(rel) - d[0]);
    case ShapeKind::cylinder:
      return std::min({segment_distance(rho, h, d[0], -d[1] / 2, d[0], d[1] / 2),
                       segment_distance(rho, h, 0, d[1] / 2, d[0], d[1] / 2),
                       segment_distance(rho, h, 0, -d[1] / 2, d[0], -d[1] / 2)});
    case ShapeKind::cone:
      return std::min(segment_distance(rho, h, d[0], -d[1] / 2, 0, d[1] / 2),
                      segment_distance(rho, h, 0, -d[1] / 2, d[0], -d[1] / 2));
    case ShapeKind::torus: return std::abs(std::hypot(rho - d[0], h) - d[1]);
    case ShapeKind::box: {
      const double yaw = scene.objects[i].yaw_deg * kPi / 180;
      const Vec3 ex = table_to_camera_direction(scene, {std::cos(yaw), std::sin(yaw), 0});
      const Vec3 ey = table_to_camera_direction(scene, {-std::sin(yaw), std::cos(yaw), 0});
      const double q[3] = {std::abs(dot(rel, ex)) - d[0] / 2, std::abs(dot(rel, ey)) - d[1] / 2,
                           std::abs(h) - d[2] / 2};
      const double outside = std::hypot(std::max(q[0], 0.0), std::max(q[1], 0.0), std::max(q[2], 0.0));
      const double inside = std::min(std::max({q[0], q[1], q[2]}), 0.0);
      return std::abs(outside + inside);
    }
  }
  return 1e9;
}

SyntheticScene make_scene(std::uint64_t seed, int objects, std::vector<ShapeKind> kinds = {}) {
  SyntheticSceneParams p;
  p.seed = seed;
  p.object_count = objects;
  if (!kinds.empty()) p.kinds = kinds;
  Result<SyntheticScene> s = generate_scene(p);
  EXPECT_TRUE(s.ok()) << s.error().format();
  return s.ok() ? *s : SyntheticScene{};
}

SensorNoiseParams exact() {
  SensorNoiseParams n;
  n.enabled = false;
  return n;
}

// Bitwise equal coordinates (NaN where NaN) and equal colours.
bool same_points(const Frame& a, const Frame& b) {
  if (a.points.size() != b.points.size()) return false;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const PointXYZRGB &p = a.points[i], &q = b.points[i];
    if (std::memcmp(&p.x, &q.x, sizeof p.x) || std::memcmp(&p.y, &q.y, sizeof p.y) ||
        std::memcmp(&p.z, &q.z, sizeof p.z) || p.r != q.r || p.g != q.g || p.b != q.b)
      return false;
  }
  return true;
}

TEST(SyntheticScene, SameSeedSameFramesOtherSeedOtherFrames) {
  const SyntheticScene a = make_scene(7, 4);
  const SyntheticScene b = make_scene(7, 4);
  const SyntheticScene c = make_scene(8, 4);
  const SyntheticFrame fa = render_scene(a), fb = render_scene(b), fc = render_scene(c);
  EXPECT_TRUE(same_points(fa.frame, fb.frame));
  EXPECT_EQ(fa.labels, fb.labels);
  EXPECT_EQ(fa.truth, fb.truth);
  EXPECT_FALSE(same_points(fa.frame, fc.frame));
  EXPECT_NE(fa.truth, fc.truth);
}

TEST(SyntheticScene, KinectLikeOrganizedFrame) {
  const SyntheticFrame f = render_scene(make_scene(3, 4));
  EXPECT_EQ(f.frame.width, 640);
  EXPECT_EQ(f.frame.height, 480);
  EXPECT_TRUE(f.frame.organized());
  ASSERT_EQ(f.frame.points.size(), 640u * 480u);
  ASSERT_EQ(f.labels.size(), f.frame.points.size());
  int table = 0, finite = 0;
  for (std::size_t i = 0; i < f.labels.size(); ++i) {
    table += f.labels[i] == kLabelTable;
    finite += std::isfinite(f.frame.points[i].z);
  }
  EXPECT_GT(table, 640 * 480 / 5);  // the table fills a good part of the view
  EXPECT_GT(finite, 640 * 480 * 8 / 10);
}

TEST(SyntheticScene, HouseholdSizesRestingOnTheTableWithoutTouching) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const SyntheticScene s = make_scene(seed, 5);
    ASSERT_EQ(s.objects.size(), 5u);
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
      const SyntheticObject& o = s.objects[i];
      const auto& d = o.dimensions_m;
      ASSERT_EQ(static_cast<int>(d.size()), dimension_count(o.kind));
      switch (o.kind) {
        case ShapeKind::sphere:
          EXPECT_TRUE(d[0] >= 0.03 && d[0] <= 0.08);
          EXPECT_DOUBLE_EQ(o.center.z, d[0]);
          break;
        case ShapeKind::cylinder:
          EXPECT_TRUE(d[0] >= 0.03 && d[0] <= 0.06 && d[1] >= 0.08 && d[1] <= 0.30);
          EXPECT_DOUBLE_EQ(o.center.z, d[1] / 2);
          break;
        case ShapeKind::cone:
          EXPECT_TRUE(d[0] >= 0.04 && d[0] <= 0.08 && d[1] >= 0.08 && d[1] <= 0.25);
          EXPECT_DOUBLE_EQ(o.center.z, d[1] / 2);
          break;
        case ShapeKind::torus:
          EXPECT_TRUE(d[0] >= 0.04 && d[0] <= 0.08 && d[1] >= 0.015 && d[1] <= 0.03);
          EXPECT_DOUBLE_EQ(o.center.z, d[1]);
          break;
        case ShapeKind::box:
          for (double x : d) EXPECT_TRUE(x >= 0.05 && x <= 0.25);
          EXPECT_DOUBLE_EQ(o.center.z, d[2] / 2);
          break;
      }
      EXPECT_LT(std::abs(o.center.x), s.table_half_x_m);
      EXPECT_LT(std::abs(o.center.y), s.table_half_y_m);
      for (std::size_t j = 0; j < i; ++j) {
        const double gap = std::hypot(o.center.x - s.objects[j].center.x, o.center.y - s.objects[j].center.y);
        EXPECT_GT(gap, 0.06);  // at least two small radii apart
      }
    }
    const double distance = norm(s.camera_position - Vec3{0, 0, 0});
    EXPECT_GT(distance, 0.6);
    EXPECT_GE(s.camera_tilt_deg, 30);
    EXPECT_LE(s.camera_tilt_deg, 60);
  }
}

// The sensor model with its axial noise alone: every pixel kept where it was cast.
SensorNoiseParams axial_only() {
  SensorNoiseParams n;
  n.lateral_sigma_px = 0;
  n.dropout = 0;
  n.edge_dropout = 0;
  n.grazing_cos = 0;
  return n;
}

TEST(SyntheticScene, AxialNoiseFollowsTheKinectModel) {
  SyntheticSceneParams p;
  p.seed = 11;
  p.object_count = 0;
  p.camera_distance_min_m = p.camera_distance_max_m = 1.0;
  const Result<SyntheticScene> s = generate_scene(p);
  ASSERT_TRUE(s.ok());
  const SyntheticFrame noisy = render_scene(*s, axial_only());
  const SyntheticFrame clean = render_scene(*s, exact());
  double sum_at_1m = 0, sum2_at_1m = 0, sum2_normalized = 0;
  int n_at_1m = 0, n = 0;
  for (std::size_t i = 0; i < clean.frame.points.size(); ++i) {
    const double z = clean.frame.points[i].z;
    if (!std::isfinite(z)) continue;
    ASSERT_TRUE(std::isfinite(noisy.frame.points[i].z));
    const double dz = noisy.frame.points[i].z - z;
    sum2_normalized += (dz / sigma(z)) * (dz / sigma(z));
    ++n;
    if (std::abs(z - 1.0) < 0.02) {
      sum_at_1m += dz;
      sum2_at_1m += dz * dz;
      ++n_at_1m;
    }
    // The noise moves the point along its pixel's ray: x/z and y/z are kept.
    EXPECT_NEAR(noisy.frame.points[i].x / noisy.frame.points[i].z, clean.frame.points[i].x / z, 1e-5);
  }
  ASSERT_GT(n_at_1m, 5000);
  const double sigma_at_1m = std::sqrt(sum2_at_1m / n_at_1m);
  // 0.0012 + 0.0019 * 0.6^2 = 1.884 mm.
  EXPECT_NEAR(sigma_at_1m, 0.001884, 0.001884 * 0.05);
  EXPECT_NEAR(sum_at_1m / n_at_1m, 0.0, 0.0001);
  EXPECT_NEAR(std::sqrt(sum2_normalized / n), 1.0, 0.02);
}

// Flying pixels (SensorNoiseParams::flying_share): with every edge pixel kept and mixed,
// the depths that differ from the exact render are edge pixels' only, each between its
// own surface's depth and a neighbour's across the edge, on its own ray; none without.
TEST(SyntheticScene, FlyingPixelsLieBetweenAnEdgeAndWhatLiesBehindIt) {
  SyntheticSceneParams p;
  p.seed = 11;
  p.camera_distance_min_m = p.camera_distance_max_m = 1.0;
  const Result<SyntheticScene> s = generate_scene(p);
  ASSERT_TRUE(s.ok());
  SensorNoiseParams flying = axial_only();
  flying.axial = DepthNoise{1e-7, 0, 0};  // no noise to speak of
  flying.flying_share = 1;
  const SyntheticFrame mixed = render_scene(*s, flying);
  flying.flying_share = 0;
  const SyntheticFrame plain = render_scene(*s, flying);
  const SyntheticFrame clean = render_scene(*s, exact());
  const int w = clean.frame.width, h = clean.frame.height;
  int moved = 0;
  for (int v = 1; v + 1 < h; ++v)
    for (int u = 1; u + 1 < w; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      const double z = clean.frame.points[i].z;
      if (!std::isfinite(z)) continue;
      EXPECT_NEAR(plain.frame.points[i].z, z, 1e-5);
      const double got = mixed.frame.points[i].z;
      if (std::abs(got - z) < 1e-5) continue;
      ++moved;
      double lo = z, hi = z;
      for (const std::size_t j : {i - 1, i + 1, i - w, i + w}) {
        const double n = clean.frame.points[j].z;
        if (std::isfinite(n) && std::abs(n - z) > flying.edge_jump_m)
          lo = std::min(lo, n), hi = std::max(hi, n);
      }
      ASSERT_LT(lo, hi) << "a mixed depth at a pixel with no edge: " << u << "," << v;
      EXPECT_GE(got, lo - 1e-5);
      EXPECT_LE(got, hi + 1e-5);
      EXPECT_NEAR(mixed.frame.points[i].x / got, clean.frame.points[i].x / z, 1e-5);
    }
  EXPECT_GT(moved, 500);
}

TEST(SyntheticScene, DropoutAndLateralJitterStayModest) {
  const SyntheticScene s = make_scene(5, 5);
  const SyntheticFrame noisy = render_scene(s);
  const SyntheticFrame clean = render_scene(s, exact());
  int seen = 0, dropped = 0, relabelled = 0;
  for (std::size_t i = 0; i < clean.frame.points.size(); ++i) {
    if (clean.labels[i] != noisy.labels[i]) ++relabelled;
    if (!std::isfinite(clean.frame.points[i].z)) continue;
    ++seen;
    dropped += !std::isfinite(noisy.frame.points[i].z);
  }
  const double dropout = static_cast<double>(dropped) / seen;
  EXPECT_GT(dropout, 0.02);
  EXPECT_LT(dropout, 0.12);
  // Jitter moves rays across silhouettes: some pixels see another surface, few do.
  EXPECT_GT(relabelled, 50);
  EXPECT_LT(relabelled, 640 * 480 / 50);
}

TEST(SyntheticScene, EveryObjectIsVisible) {
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    const SyntheticFrame f = render_scene(make_scene(seed, 4));
    ASSERT_EQ(f.truth.objects.size(), 4u);
    for (const PhysicalObject& o : f.truth.objects)
      EXPECT_GT(o.point_count, 150) << "seed " << seed << " " << o.id << " "
                                    << shape_name(o.primitives[0].kind);
  }
}

TEST(SyntheticScene, GroundTruthTablePlaneAndCentres) {
  const SyntheticScene s = make_scene(9, 5);
  const PhysicalScene truth = ground_truth(s);
  ASSERT_TRUE(truth.support.has_value());
  const Plane& plane = *truth.support;
  EXPECT_NEAR(norm(plane.normal), 1.0, 1e-12);
  EXPECT_GT(plane.d, 0.3);   // the camera is above the table
  EXPECT_LT(plane.normal.y, -0.4);  // up is towards the image top, the camera looks down
  ASSERT_EQ(truth.objects.size(), 5u);
  for (std::size_t i = 0; i < truth.objects.size(); ++i) {
    const PhysicalObject& o = truth.objects[i];
    EXPECT_EQ(o.id, std::string("o").append(std::to_string(i + 1)));
    ASSERT_EQ(o.primitives.size(), 1u);
    const PhysicalPrimitive& prim = o.primitives[0];
    EXPECT_NEAR(dot(prim.axis, plane.normal), 1.0, 1e-12);
    const double height = dot(plane.normal, prim.center) + plane.d;
    const auto& d = prim.dimensions_m;
    const double expected = prim.kind == ShapeKind::sphere   ? d[0]
                            : prim.kind == ShapeKind::torus  ? d[1]
                            : prim.kind == ShapeKind::box    ? d[2] / 2
                                                             : d[1] / 2;
    EXPECT_NEAR(height, expected, 1e-9) << shape_name(prim.kind);
    EXPECT_GT(prim.center.z, 0.4);
  }
}

// Every point the renderer attributes to object i lies on that object's analytic
// surface: exactly without noise, within the axial noise with it.
TEST(SyntheticScene, PointsLieOnTheirObjectsSurfaces) {
  std::uint64_t seed = 100;
  for (ShapeKind kind : kSolidShapes) {
    const SyntheticScene s = make_scene(++seed, 3, {kind});
    const SyntheticFrame clean = render_scene(s, exact());
    const SyntheticFrame noisy = render_scene(s);
    int checked = 0, outliers = 0, on_table_top = 0, on_table_edge = 0;
    double worst_clean = 0;
    for (std::size_t i = 0; i < clean.labels.size(); ++i) {
      const int l = clean.labels[i];
      const PointXYZRGB& c = clean.frame.points[i];
      if (l == kLabelTable && std::isfinite(c.z)) {
        // On the table top, or on its front edge (thickness below the top).
        const Plane& pl = *clean.truth.support;
        const double height = dot(pl.normal, Vec3{c.x, c.y, c.z}) + pl.d;
        if (std::abs(height) < 1e-5) {
          ++on_table_top;
        } else {
          EXPECT_LT(height, 0.0);
          EXPECT_GT(height, -s.table_thickness_m - 1e-5);
          ++on_table_edge;
        }
      }
      if (l >= 0 && std::isfinite(c.z)) {
        worst_clean = std::max(worst_clean, surface_distance(s, clean.truth, l, {c.x, c.y, c.z}));
        ++checked;
      }
      const PointXYZRGB& p = noisy.frame.points[i];
      if (noisy.labels[i] >= 0 && std::isfinite(p.z)) {
        // Axial noise moves a point along its ray by dz * |ray| / z; 4.5 sigma bound.
        const double bound = 4.5 * sigma(p.z) * point_norm(p) / p.z + 1e-5;
        if (surface_distance(s, noisy.truth, noisy.labels[i], {p.x, p.y, p.z}) > bound) ++outliers;
      }
    }
    EXPECT_GT(checked, 600) << shape_name(kind);
    EXPECT_GT(on_table_top, 5 * on_table_edge) << shape_name(kind);
    EXPECT_LT(worst_clean, 2e-5) << shape_name(kind);
    EXPECT_LT(outliers, checked / 500 + 2) << shape_name(kind);
  }
}

TEST(SyntheticScene, SequencesMoveObjectsAFewMillimetresPerFrame) {
  SyntheticSceneParams p;
  p.seed = 21;
  p.object_count = 3;
  p.max_speed_m_per_frame = 0.004;
  p.max_spin_deg_per_frame = 3;
  const Result<SyntheticScene> s = generate_scene(p);
  ASSERT_TRUE(s.ok());
  const SyntheticScene later = scene_at_frame(*s, 10);
  double moved = 0;
  for (std::size_t i = 0; i < s->objects.size(); ++i) {
    const Vec3 step = later.objects[i].center - s->objects[i].center;
    EXPECT_LE(norm(step), 10 * 0.004 + 1e-12);
    EXPECT_DOUBLE_EQ(step.z, 0.0);  // still resting on the table
    moved += norm(step);
    double turn = std::fmod(std::abs(later.objects[i].yaw_deg - s->objects[i].yaw_deg), 360.0);
    turn = std::min(turn, 360 - turn);
    EXPECT_LE(turn, 30 + 1e-9);
  }
  EXPECT_GT(moved, 0.005);

  const SyntheticFrame f0 = render_scene(*s, {}, 0);
  const SyntheticFrame f5 = render_scene(*s, {}, 5);
  const SyntheticFrame f5_again = render_scene(*s, {}, 5);
  EXPECT_TRUE(same_points(f5.frame, f5_again.frame));
  EXPECT_FALSE(same_points(f0.frame, f5.frame));
  EXPECT_EQ(f5.frame.index, 5);
  EXPECT_NEAR(f5.frame.timestamp_s, 5 / 30.0, 1e-12);
  // Frame 5's ground truth is the moved scene's.
  EXPECT_EQ(f5.truth.objects[0].primitives[0].center,
            ground_truth(scene_at_frame(*s, 5)).objects[0].primitives[0].center);
}

TEST(SyntheticScene, OccluderCrossesTheView) {
  SyntheticSceneParams p;
  p.seed = 4;
  p.object_count = 3;
  p.occluder = true;
  const Result<SyntheticScene> s = generate_scene(p);
  ASSERT_TRUE(s.ok());
  std::vector<double> mean_u;
  for (int k = 0; k <= 60; k += 6) {
    const SyntheticFrame f = render_scene(*s, exact(), k);
    double sum_u = 0;
    int count = 0;
    for (std::size_t i = 0; i < f.labels.size(); ++i)
      if (f.labels[i] == kLabelOccluder) sum_u += static_cast<double>(i % 640), ++count;
    if (count > 500) mean_u.push_back(sum_u / count);
    EXPECT_EQ(f.truth.objects.size(), 3u);  // the occluder is not a table object
  }
  ASSERT_GE(mean_u.size(), 3u);
  for (std::size_t i = 1; i < mean_u.size(); ++i) EXPECT_GT(mean_u[i], mean_u[i - 1]);
}

TEST(SyntheticScene, ImpossibleLayoutsAreErrors) {
  SyntheticSceneParams p;
  p.object_count = 60;
  Result<SyntheticScene> s = generate_scene(p);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("could place only"), std::string::npos) << s.error().message;
  p.object_count = -1;
  EXPECT_FALSE(generate_scene(p).ok());
  p.object_count = 2;
  p.kinds.clear();
  EXPECT_FALSE(generate_scene(p).ok());
}

TEST(SyntheticScene, ChosenObjectsCanBeAddedToAGeneratedTable) {
  SyntheticSceneParams p;
  p.seed = 2;
  p.object_count = 0;
  Result<SyntheticScene> s = generate_scene(p);
  ASSERT_TRUE(s.ok());
  const Vec3 aim = s->camera_position + Vec3{0, std::cos(s->camera_tilt_deg * kPi / 180),
                                             -std::sin(s->camera_tilt_deg * kPi / 180)} *
                                            (s->camera_position.z / std::sin(s->camera_tilt_deg * kPi / 180));
  s->objects.push_back(resting_object(ShapeKind::cylinder, {0.05, 0.2}, aim.x, aim.y));
  EXPECT_DOUBLE_EQ(s->objects[0].center.z, 0.1);
  const SyntheticFrame f = render_scene(*s, exact());
  ASSERT_EQ(f.truth.objects.size(), 1u);
  EXPECT_GT(f.truth.objects[0].point_count, 1000);
  // The cylinder stands on the aim point, which the optical axis passes through.
  EXPECT_EQ(f.labels[240 * 640 + 320], 0);
}

TEST(SyntheticScene, AxialSigmaFormula) {
  EXPECT_DOUBLE_EQ(kinect_axial_sigma_m(0.4), 0.0012);
  EXPECT_NEAR(kinect_axial_sigma_m(1.0), 0.001884, 1e-9);
  EXPECT_NEAR(kinect_axial_sigma_m(3.0), 0.0012 + 0.0019 * 2.6 * 2.6, 1e-12);
}


// --- the widened generator (world_scene_params) ---

TEST(SyntheticWorld, FloorLegsFurnitureAndASecondSupportWithItsObjects) {
  int on_furniture = 0, leg_pixels = 0, furniture_pixels = 0;
  for (std::uint64_t seed = 2001; seed <= 2006; ++seed) {
    const Result<SyntheticScene> s = generate_scene(world_scene_params(seed));
    ASSERT_TRUE(s.ok()) << s.error().format();
    const SyntheticFrame f = render_scene(*s, exact());
    ASSERT_EQ(f.truth.supports.size(), 3u);  // table, floor, the second support's top
    EXPECT_EQ(f.truth.supports[0].plane, *f.truth.support);
    // The floor lies floor_depth_m below the table, parallel to it.
    EXPECT_NEAR(f.truth.supports[1].plane.d - f.truth.supports[0].plane.d, s->floor_depth_m, 1e-9);
    for (int l : f.labels) {
      leg_pixels += l == kLabelLeg;
      furniture_pixels += l == kLabelFurniture;
    }
    for (std::size_t i = 0; i < f.truth.objects.size(); ++i) {
      const PhysicalObject& o = f.truth.objects[i];
      const SupportSurface* support = nullptr;
      for (const SupportSurface& sp : f.truth.supports)
        if (sp.id == o.support_id) support = &sp;
      ASSERT_NE(support, nullptr) << o.support_id;
      on_furniture += o.support_id != "table";
      // Every exact point of the object lies on or above its support's plane, and the
      // lowest ones touch it (the object stands on it).
      double lowest = 1e9;
      for (std::size_t k = 0; k < f.labels.size(); ++k)
        if (f.labels[k] == static_cast<int>(i) && std::isfinite(f.frame.points[k].z)) {
          const PointXYZRGB& p = f.frame.points[k];
          lowest = std::min(lowest, dot(support->plane.normal, Vec3{p.x, p.y, p.z}) + support->plane.d);
        }
      if (lowest < 1e9) EXPECT_GT(lowest, -1e-6) << "seed " << seed << " object " << i;
    }
  }
  EXPECT_GT(on_furniture, 3);
  EXPECT_GT(leg_pixels, 1000);
  EXPECT_GT(furniture_pixels, 10000);
}

TEST(SyntheticWorld, CamerasFromHalfAMetreToThreeAndLevelToSixtyDegrees) {
  double near = 1e9, far = 0, level = 90, steep = 0;
  for (std::uint64_t seed = 2001; seed <= 2040; ++seed) {
    const Result<SyntheticScene> s = generate_scene(world_scene_params(seed));
    ASSERT_TRUE(s.ok()) << s.error().format();
    const double d = norm(s->camera_position);
    near = std::min(near, d), far = std::max(far, d);
    level = std::min(level, s->camera_tilt_deg), steep = std::max(steep, s->camera_tilt_deg);
    EXPECT_GE(s->camera_position.z, 0.25 - 1e-12);
  }
  EXPECT_LT(near, 0.9);
  EXPECT_GT(far, 2.4);
  EXPECT_LT(level, 10);
  EXPECT_GT(steep, 50);
}

// Distance from (rho, h) to a frustum's outline in its half-plane section: wide radius r
// at h = -H/2, narrow radius q at +H/2.
double frustum_distance(double rho, double h, double r, double q, double height) {
  return std::min({segment_distance(rho, h, r, -height / 2, q, height / 2),
                   segment_distance(rho, h, 0, -height / 2, r, -height / 2),
                   segment_distance(rho, h, 0, height / 2, q, height / 2)});
}

TEST(SyntheticWorld, FrustumsAndConesApexDownLieOnTheirSurfaces) {
  SyntheticSceneParams p;
  p.seed = 4;
  p.object_count = 0;
  Result<SyntheticScene> s = generate_scene(p);
  ASSERT_TRUE(s.ok());
  const double t = s->camera_tilt_deg * kPi / 180;
  const Vec3 aim = s->camera_position + Vec3{0, std::cos(t), -std::sin(t)} * (s->camera_position.z / std::sin(t));
  SyntheticObject cup = resting_object(ShapeKind::cone, {0.06, 0.1}, aim.x - 0.12, aim.y);
  cup.apex_down = true;
  cup.narrow_radius_m = 0.035;
  SyntheticObject bowl = resting_object(ShapeKind::cone, {0.1, 0.05}, aim.x + 0.14, aim.y);
  bowl.apex_down = true;
  bowl.narrow_radius_m = 0.05;
  s->objects = {cup, bowl};
  const SyntheticFrame f = render_scene(*s, exact());
  ASSERT_EQ(f.truth.objects.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const PhysicalPrimitive& prim = f.truth.objects[i].primitives[0];
    EXPECT_LT(dot(prim.axis, f.truth.support->normal), -0.999);  // wide end up
    EXPECT_EQ(prim.narrow_radius_m, s->objects[i].narrow_radius_m);
    int n = 0;
    double worst = 0;
    for (std::size_t k = 0; k < f.labels.size(); ++k) {
      if (f.labels[k] != static_cast<int>(i) || !std::isfinite(f.frame.points[k].z)) continue;
      const PointXYZRGB& q = f.frame.points[k];
      const Vec3 rel = Vec3{q.x, q.y, q.z} - prim.center;
      const double h = dot(rel, prim.axis);  // towards the narrow end
      const double rho = norm(rel - prim.axis * h);
      worst = std::max(worst, frustum_distance(rho, h, prim.dimensions_m[0], prim.narrow_radius_m,
                                               prim.dimensions_m[1]));
      ++n;
    }
    EXPECT_GT(n, 500);
    EXPECT_LT(worst, 1e-4);
  }
}

TEST(SyntheticWorld, CutObjectsCrossTheBorderAndAreMarkedPartial) {
  int cut = 0, placed_cut = 0;
  for (std::uint64_t seed = 2001; seed <= 2024; ++seed) {
    const Result<SyntheticScene> s = generate_scene(world_scene_params(seed));
    ASSERT_TRUE(s.ok()) << s.error().format();
    const SyntheticFrame f = render_scene(*s, exact());
    // Without noise only the sensor's range leaves a pixel without depth: an object's
    // pixel without depth lies nearer than the range (its blind zone).
    std::vector<char> at_border(f.truth.objects.size(), 0), too_near(f.truth.objects.size(), 0);
    for (int v = 0; v < 480; ++v)
      for (int u = 0; u < 640; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * 640 + u;
        const int l = f.labels[i];
        if (l < 0) continue;
        if (!std::isfinite(f.frame.points[i].z)) too_near[static_cast<std::size_t>(l)] = 1;
        if (u == 0 || v == 0 || u == 639 || v == 479) at_border[static_cast<std::size_t>(l)] = 1;
      }
    for (std::size_t i = 0; i < f.truth.objects.size(); ++i) {
      // Partial in the truth exactly when the object's pixels reach the border (its
      // image box may cross it while its silhouette does not) or the blind zone.
      EXPECT_EQ(f.truth.objects[i].partial, at_border[i] != 0 || too_near[i] != 0)
          << "seed " << seed << " object " << i;
      cut += at_border[i];
      placed_cut += s->objects[i].cut;
      // Whole objects keep a margin from the border; cut ones reach it unless hidden.
      if (!s->objects[i].cut) EXPECT_FALSE(at_border[i]) << "seed " << seed << " object " << i;
    }
  }
  EXPECT_GT(cut, 3);
  EXPECT_LE(cut, placed_cut);
}

TEST(SyntheticWorld, SameSeedSameScene) {
  const Result<SyntheticScene> a = generate_scene(world_scene_params(2003));
  const Result<SyntheticScene> b = generate_scene(world_scene_params(2003));
  ASSERT_TRUE(a.ok() && b.ok());
  const SyntheticFrame fa = render_scene(*a), fb = render_scene(*b);
  EXPECT_EQ(fa.truth, fb.truth);
  EXPECT_EQ(fa.labels, fb.labels);
}

// --- the held-out widening (room_scene_params) ---

TEST(SyntheticRooms, TableHeightsFromCoffeeTableToCounterAndARolledCamera) {
  double low = 9, high = 0, roll_min = 9, roll_max = -9;
  for (std::uint64_t seed = 5001; seed <= 5030; ++seed) {
    const Result<SyntheticScene> s = generate_scene(room_scene_params(seed));
    ASSERT_TRUE(s.ok()) << s.error().format();
    EXPECT_GE(s->floor_depth_m, 0.4);
    EXPECT_LE(s->floor_depth_m, 1.1);
    EXPECT_LE(std::abs(s->camera_roll_deg), 5.0);
    low = std::min(low, s->floor_depth_m), high = std::max(high, s->floor_depth_m);
    roll_min = std::min(roll_min, s->camera_roll_deg), roll_max = std::max(roll_max, s->camera_roll_deg);
    // The legs reach the floor whatever the table's height.
    for (const SyntheticBlock& b : s->furniture)
      if (b.role == SyntheticBlock::Role::leg)
        EXPECT_NEAR(b.center.z - b.size_m.z * 0.5, -s->floor_depth_m, 1e-9);
    // Rolled, the table's up leans sideways in the image by the roll: its x component
    // is -sin(roll) times its length in the image plane.
    const Vec3 up = table_to_camera_direction(*s, {0, 0, 1});
    const double in_image = std::hypot(up.x, up.y);
    EXPECT_NEAR(up.x / in_image, -std::sin(s->camera_roll_deg * 3.14159265358979 / 180), 1e-9);
    EXPECT_NEAR(norm(up), 1.0, 1e-12);
  }
  EXPECT_LT(low, 0.55);
  EXPECT_GT(high, 0.95);
  EXPECT_LT(roll_min, -2.5);
  EXPECT_GT(roll_max, 2.5);
  // The tuned set is what it was: level camera, tables 72 to 78 cm.
  const Result<SyntheticScene> w = generate_scene(world_scene_params(2003));
  ASSERT_TRUE(w.ok());
  EXPECT_EQ(w->camera_roll_deg, 0);
  EXPECT_GE(w->floor_depth_m, 0.72);
  EXPECT_LE(w->floor_depth_m, 0.78);
}

TEST(SyntheticRooms, RangesOutOfBoundsAreErrors) {
  SyntheticSceneParams p = room_scene_params(5001);
  p.table_height_max_m = 0.3;  // below the minimum
  EXPECT_FALSE(generate_scene(p).ok());
  p = room_scene_params(5001);
  p.camera_roll_max_deg = 45;
  EXPECT_FALSE(generate_scene(p).ok());
}

}  // namespace
}  // namespace annex
