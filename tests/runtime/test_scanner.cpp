// The scanning pipeline: accuracy on a fixed set of generated tabletop scenes with
// ground truth, failure paths, the config file, and the real Kinect scans in
// ../shared/data/real (skipped when absent).
#include "annex/runtime/scanner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <random>
#include <set>

#include "annex/runtime/pcd_io.h"
#include "annex/runtime/scan_overlay.h"
#include "annex/runtime/synthetic_scene.h"
#include "label_owner.h"
#include "room_scan.h"

namespace annex {
namespace {

const std::filesystem::path kReal = std::filesystem::path(ANNEX_SHARED_DIR) / "data" / "real";

double in_plane_distance(Vec3 a, Vec3 b, Vec3 n) {
  const Vec3 d = a - b;
  return norm(d - n * dot(d, n));
}

Vec3 centroid(const std::vector<Vec3>& pts) {
  Vec3 c;
  for (const Vec3& p : pts) c = c + p;
  return pts.empty() ? c : c * (1.0 / pts.size());
}

struct Accuracy {
  int objects = 0, correct = 0, found = 0;
  std::vector<double> size_errors_m;
};

// Matches each true object to the nearest scanned one (by position on the table) and
// compares shape and dimensions (box footprint sides compared sorted: the generator's
// size_x/size_y follow its yaw, ours the longer side).
void score_scene(const PhysicalScene& truth, const ScanResult& scan, Accuracy& acc) {
  const Vec3 n = truth.support->normal;
  for (const PhysicalObject& t : truth.objects) {
    const PhysicalPrimitive& tp = t.primitives.at(0);
    double largest = 0;
    for (double d : tp.dimensions_m) largest = std::max(largest, d);
    if (tp.kind == ShapeKind::sphere || tp.kind == ShapeKind::cylinder ||
        tp.kind == ShapeKind::cone || tp.kind == ShapeKind::torus)
      largest = std::max(largest, 2 * tp.dimensions_m[0]);
    if (largest < 0.05) continue;  // the requirement covers objects of 5 cm and more
    ++acc.objects;
    int best = -1;
    double best_d = 0.06;
    for (size_t k = 0; k < scan.scene.objects.size(); ++k) {
      const PhysicalObject& o = scan.scene.objects[k];
      const Vec3 c = o.primitives.empty() ? centroid(scan.clusters[k].points) : o.primitives[0].center;
      const double d = in_plane_distance(c, tp.center, n);
      if (d < best_d) {
        best_d = d;
        best = static_cast<int>(k);
      }
    }
    if (best < 0) continue;
    ++acc.found;
    const PhysicalObject& o = scan.scene.objects[best];
    if (o.primitives.empty() || o.primitives[0].kind != tp.kind) continue;
    ++acc.correct;
    std::vector<double> a = tp.dimensions_m, b = o.primitives[0].dimensions_m;
    ASSERT_EQ(a.size(), b.size());
    if (tp.kind == ShapeKind::box) {
      std::sort(a.begin(), a.begin() + 2);
      std::sort(b.begin(), b.begin() + 2);
    }
    for (size_t i = 0; i < a.size(); ++i) acc.size_errors_m.push_back(std::abs(a[i] - b[i]));
  }
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

SyntheticFrame synthetic(std::uint64_t seed) {
  SyntheticSceneParams p;
  p.seed = seed;
  const Result<SyntheticScene> scene = generate_scene(p);
  EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().format());
  SyntheticFrame f = render_scene(*scene);
  return f;
}

TEST(Scanner, AccuracyOnTheFixedGeneratedSet) {
  Accuracy acc;
  for (std::uint64_t seed = 1; seed <= 15; ++seed) {
    const SyntheticFrame f = synthetic(seed);
    const Result<ScanResult> scan = scan_frame(f.frame);
    ASSERT_TRUE(scan.ok()) << "seed " << seed << ": " << scan.error().format();
    score_scene(f.truth, *scan, acc);
  }
  ASSERT_GE(acc.objects, 40);
  const double class_accuracy = static_cast<double>(acc.correct) / acc.objects;
  EXPECT_GE(class_accuracy, 0.90) << acc.correct << " of " << acc.objects;
  EXPECT_GE(acc.found, acc.objects * 95 / 100);
  EXPECT_LE(median(acc.size_errors_m), 0.008);
}

TEST(Scanner, SupportPlaneMatchesTheTable) {
  const SyntheticFrame f = synthetic(21);
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_TRUE(scan.ok());
  const Plane& truth = *f.truth.support;
  EXPECT_GT(dot(scan->plane.normal, truth.normal), std::cos(1.0 * 3.14159265 / 180));
  EXPECT_NEAR(scan->plane.d, truth.d, 0.01);
  ASSERT_TRUE(scan->scene.support.has_value());
  EXPECT_EQ(*scan->scene.support, scan->plane);
}

TEST(Scanner, IdsRunLeftToRightAndRepeatForOneFrame) {
  const SyntheticFrame f = synthetic(22);
  const Result<ScanResult> a = scan_frame(f.frame), b = scan_frame(f.frame);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->scene, b->scene);
  ASSERT_GE(a->scene.objects.size(), 2u);
  double last = -1e9;
  for (size_t k = 0; k < a->scene.objects.size(); ++k) {
    EXPECT_EQ(a->scene.objects[k].id, std::to_string(k + 1).insert(0, 1, 'p'));
    const Vec3 c = centroid(a->clusters[k].points);
    EXPECT_GT(c.x / c.z, last);
    last = c.x / c.z;
  }
}

TEST(Scanner, ReportsEveryStage) {
  const Result<ScanResult> scan = scan_frame(synthetic(23).frame);
  ASSERT_TRUE(scan.ok());
  std::vector<std::string> names;
  for (const StageTime& s : scan->stages) names.push_back(s.name);
  EXPECT_EQ(names, (std::vector<std::string>{"plane", "prism", "clusters", "mls", "shapes"}));
}

TEST(Scanner, UnorganizedCloudsTakeTheSlowerPath) {
  SyntheticFrame f = synthetic(24);
  const Result<ScanResult> organized = scan_frame(f.frame);
  ASSERT_TRUE(organized.ok());
  Frame flat = f.frame;
  std::erase_if(flat.points, [](const PointXYZRGB& p) { return !std::isfinite(p.z); });
  std::shuffle(flat.points.begin(), flat.points.end(), std::mt19937_64(3));
  flat.width = static_cast<int>(flat.points.size());
  flat.height = 1;
  const Result<ScanResult> unorganized = scan_frame(flat);
  ASSERT_TRUE(unorganized.ok());
  // The re-projected grid has holes where jittered points collide: fragments there
  // are partial (too few points); the whole objects are the same.
  auto whole = [](const ScanResult& r) {
    std::vector<const PhysicalObject*> out;
    for (const PhysicalObject& o : r.scene.objects)
      if (!o.partial) out.push_back(&o);
    return out;
  };
  const auto a_objects = whole(*organized), b_objects = whole(*unorganized);
  ASSERT_EQ(b_objects.size(), a_objects.size());
  for (size_t k = 0; k < a_objects.size(); ++k) {
    const auto& a = a_objects[k]->primitives;
    const auto& b = b_objects[k]->primitives;
    ASSERT_EQ(a.empty(), b.empty());
    if (!a.empty()) {
      EXPECT_EQ(a[0].kind, b[0].kind);
    }
  }
}

TEST(Scanner, NoHorizontalPlaneIsAnError) {
  // A wall facing the camera: a plane, but not a support.
  Frame f;
  f.width = 64;
  f.height = 48;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      PointXYZRGB p;
      p.z = 1.5f;
      p.x = static_cast<float>((x - 32) * 1.5 / 525.0 * 10);
      p.y = static_cast<float>((y - 24) * 1.5 / 525.0 * 10);
      f.points.push_back(p);
    }
  ScanParams params;
  params.min_plane_points = 100;
  const Result<ScanResult> scan = scan_frame(f, params);
  ASSERT_FALSE(scan.ok());
  EXPECT_NE(scan.error().message.find("no horizontal plane"), std::string::npos);
}

TEST(Scanner, CloudInMillimetresIsNamedAsSuch) {
  SyntheticSceneParams p;
  p.seed = 3;
  Frame f = render_scene(generate_scene(p).value()).frame;
  for (PointXYZRGB& q : f.points) {
    q.x *= 1000;
    q.y *= 1000;
    q.z *= 1000;
  }
  const Result<ScanResult> scan = scan_frame(f);
  ASSERT_FALSE(scan.ok());
  EXPECT_NE(scan.error().message.find("no depth within max_depth_m (4 m)"), std::string::npos)
      << scan.error().message;
  EXPECT_NE(scan.error().message.find("millimetres"), std::string::npos);
}

TEST(Scanner, EmptyAndAllInvalidFramesAreErrors) {
  Frame f;
  f.width = 4;
  f.height = 4;
  PointXYZRGB nan;
  nan.x = nan.y = nan.z = std::numeric_limits<float>::quiet_NaN();
  f.points.assign(16, nan);
  const Result<ScanResult> a = scan_frame(f);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().message.find("no valid depth"), std::string::npos);
  f.points.resize(15);
  const Result<ScanResult> b = scan_frame(f);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().message.find("does not match"), std::string::npos);
}

// A source that says its camera has no focal length gave pixels that back-project
// nowhere: an error naming the frame, not a scan counting pixels with it.
TEST(Scanner, AFrameWhoseCameraHasNoFocalLengthIsAnError) {
  SyntheticFrame f = synthetic(25);
  f.frame.index = 7;
  f.frame.intrinsics.fx = 0;
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_FALSE(scan.ok());
  EXPECT_NE(scan.error().format().find("frame 7 intrinsics"), std::string::npos)
      << scan.error().format();
  EXPECT_NE(scan.error().format().find("fx"), std::string::npos) << scan.error().format();
}

// Another camera (a quarter of the pixels; NYU's longer focal length; a narrow lens
// seeing the table from twice as far) sees the same tables: every rule that counts
// pixels counts with the frame's own focal length, so the objects come out as with
// the Kinect's 640x480 at 525 pixels.
TEST(Scanner, OtherCamerasFindWhatTheKinectDoes) {
  struct Camera {
    CameraIntrinsics k;
    double distance_scale;
  };
  const Camera cameras[] = {{{320, 240, 262.5, 262.5, 159.5, 119.5}, 1},
                            {{640, 480, 582.6, 582.2, 313.0, 238.4}, 1},
                            {{640, 480, 1050, 1050, 319.5, 239.5}, 2}};
  for (const Camera& camera : cameras) {
    Accuracy acc;
    for (std::uint64_t seed = 1; seed <= 15; ++seed) {
      SyntheticSceneParams p;
      p.seed = seed;
      p.camera = camera.k;
      p.camera_distance_min_m *= camera.distance_scale;
      p.camera_distance_max_m *= camera.distance_scale;
      const Result<SyntheticScene> scene = generate_scene(p);
      ASSERT_TRUE(scene.ok()) << scene.error().format();
      SyntheticFrame f = render_scene(*scene);
      ASSERT_DOUBLE_EQ(f.frame.intrinsics.fx, camera.k.fx);
      const Result<ScanResult> scan = scan_frame(f.frame);
      ASSERT_TRUE(scan.ok()) << "seed " << seed << ": " << scan.error().format();
      score_scene(f.truth, *scan, acc);
    }
    const std::string what = "fx " + std::to_string(camera.k.fx) + ": " +
                             std::to_string(acc.correct) + " of " + std::to_string(acc.objects);
    ASSERT_GE(acc.objects, 40) << what;
    EXPECT_GE(static_cast<double>(acc.correct) / acc.objects, 0.95) << what;
    EXPECT_GE(acc.found, acc.objects * 95 / 100) << what;
    EXPECT_LE(median(acc.size_errors_m), 0.003) << what;
  }
}

TEST(Scanner, OverlayHasTheFrameSizeAndEncodesAsPng) {
  const SyntheticFrame f = synthetic(25);
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_TRUE(scan.ok());
  const RgbImage img = draw_scan_overlay(f.frame, *scan);
  EXPECT_EQ(img.width, f.frame.width);
  EXPECT_EQ(img.height, f.frame.height);
  ASSERT_FALSE(scan->clusters.empty());
  // A cluster pixel is tinted, not left at the dimmed colour.
  const int i = scan->clusters[0].pixels[scan->clusters[0].pixels.size() / 2];
  const PointXYZRGB& p = f.frame.points[i];
  const std::uint8_t* o = &img.rgb[static_cast<size_t>(i) * 3];
  EXPECT_FALSE(o[0] == p.r * 2 / 5 && o[1] == p.g * 2 / 5 && o[2] == p.b * 2 / 5);
  const std::string png = encode_png(img);
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
}

// --- config file ---

TEST(ScanConfig, SampleFileHoldsTheDefaults) {
  const Result<ScanParams> p =
      read_scan_config_file(std::filesystem::path(ANNEX_SOURCE_DIR) / "samples/config/scan.conf");
  ASSERT_TRUE(p.ok()) << p.error().format();
  const ScanParams d;
  EXPECT_EQ(p->up, d.up);
  EXPECT_EQ(p->camera_tilt_deg, d.camera_tilt_deg);
  EXPECT_EQ(p->max_plane_angle_deg, d.max_plane_angle_deg);
  EXPECT_EQ(p->plane_distance_m, d.plane_distance_m);
  EXPECT_EQ(p->pixel_stride, d.pixel_stride);
  EXPECT_EQ(p->cluster_tolerance_m, d.cluster_tolerance_m);
  EXPECT_EQ(p->min_cluster_points, d.min_cluster_points);
  EXPECT_EQ(p->mls_radius_m, d.mls_radius_m);
  EXPECT_EQ(p->min_view_cos, d.min_view_cos);
  EXPECT_EQ(p->plane_noise_factor, d.plane_noise_factor);
  EXPECT_EQ(p->hull_margin_m, d.hull_margin_m);
  EXPECT_EQ(p->drop_cut_clusters, d.drop_cut_clusters);
  EXPECT_EQ(p->cut_join_column_share, d.cut_join_column_share);
  EXPECT_EQ(p->part_margin_m, d.part_margin_m);
  EXPECT_EQ(p->part_share, d.part_share);
  EXPECT_EQ(p->part_hang_reach_m, d.part_hang_reach_m);
  EXPECT_EQ(p->neck_min_slope_deg, d.neck_min_slope_deg);
  EXPECT_EQ(p->neck_max_width_share, d.neck_max_width_share);
  EXPECT_EQ(p->overhang_margin_m, d.overhang_margin_m);
  EXPECT_EQ(p->support_from_foot, d.support_from_foot);
  EXPECT_EQ(p->partial_when_seen_under, d.partial_when_seen_under);
  EXPECT_EQ(p->shape.min_coverage, d.shape.min_coverage);
  EXPECT_EQ(p->shape.pair_min_secondary_share, d.shape.pair_min_secondary_share);
  EXPECT_EQ(p->shape.pair_max_neck_share, d.shape.pair_max_neck_share);
  EXPECT_EQ(p->shape.max_fit_points, d.shape.max_fit_points);
  EXPECT_EQ(p->shape.box_azimuth_doubt_m, d.shape.box_azimuth_doubt_m);
  EXPECT_EQ(p->shape.refine_sample_points, d.shape.refine_sample_points);
  EXPECT_EQ(p->shape.min_foot_seen_pixels, d.shape.min_foot_seen_pixels);
  EXPECT_EQ(p->shape.min_foot_seen_share, d.shape.min_foot_seen_share);
  EXPECT_EQ(p->shape.foot_seen_model_share, d.shape.foot_seen_model_share);
  EXPECT_EQ(p->shape.own_side_hides, d.shape.own_side_hides);
  EXPECT_EQ(p->shape.one_face_box_partial, d.shape.one_face_box_partial);
  EXPECT_EQ(p->shape.seed, d.shape.seed);
  EXPECT_EQ(p->max_planes, d.max_planes);
  EXPECT_EQ(p->support_reach_m, d.support_reach_m);
  EXPECT_EQ(p->supports, d.supports);
  EXPECT_EQ(p->furniture_area_m2, d.furniture_area_m2);
  EXPECT_EQ(p->max_support_tilt_deg, d.max_support_tilt_deg);
  EXPECT_EQ(p->min_support_area_m2, d.min_support_area_m2);
  EXPECT_EQ(p->min_support_gap_m, d.min_support_gap_m);
  EXPECT_EQ(p->support_gap_reach_m, d.support_gap_reach_m);
  EXPECT_EQ(p->support_gap_reach_sigmas, d.support_gap_reach_sigmas);
  EXPECT_EQ(p->panel_span_share, d.panel_span_share);
  EXPECT_EQ(p->under_width_share, d.under_width_share);
  EXPECT_EQ(p->furniture_min_height_m, d.furniture_min_height_m);
  EXPECT_EQ(p->on_top_noise_factor, d.on_top_noise_factor);
  EXPECT_EQ(p->furniture_min_width_m, d.furniture_min_width_m);
  EXPECT_EQ(p->floor_margin_m, d.floor_margin_m);
  EXPECT_EQ(p->cluster_noise_factor, d.cluster_noise_factor);
  EXPECT_EQ(p->min_cluster_points_far, d.min_cluster_points_far);
  EXPECT_EQ(p->dropout_max_gap_px, d.dropout_max_gap_px);
  EXPECT_EQ(p->dropout_join_to_floor, d.dropout_join_to_floor);
  EXPECT_EQ(p->fitted_foot_at_border, d.fitted_foot_at_border);
  EXPECT_EQ(p->seen_under_raised_bands, d.seen_under_raised_bands);
  EXPECT_EQ(p->join_occluded, d.join_occluded);
  EXPECT_EQ(p->join_across_supports, d.join_across_supports);
  EXPECT_EQ(p->touching_max_coverage, d.touching_max_coverage);
  EXPECT_EQ(p->touching_part_coverage, d.touching_part_coverage);
  EXPECT_EQ(p->touching_two_feet_coverage, d.touching_two_feet_coverage);
  EXPECT_EQ(p->touching_gap_evidence, d.touching_gap_evidence);
  EXPECT_EQ(p->support_regions_seen_only, d.support_regions_seen_only);
  EXPECT_EQ(p->support_fit_height_alone, d.support_fit_height_alone);
  EXPECT_EQ(p->drop_above_band_cut, d.drop_above_band_cut);
  EXPECT_EQ(p->below_support_ends_at_objects, d.below_support_ends_at_objects);
  EXPECT_EQ(p->touching_waist_share, d.touching_waist_share);
  EXPECT_EQ(p->touching_min_part_size_m, d.touching_min_part_size_m);
  EXPECT_EQ(p->part_fit_slack, d.part_fit_slack);
  EXPECT_EQ(p->unseen_hold_no_parts, d.unseen_hold_no_parts);
  EXPECT_EQ(p->border_px, d.border_px);
  EXPECT_EQ(p->min_whole_points, d.min_whole_points);
  EXPECT_EQ(p->pixel_units_focal_px, d.pixel_units_focal_px);
  EXPECT_EQ(p->depth_noise, d.depth_noise);
  EXPECT_EQ(p->panel_flat_m, d.panel_flat_m);
}

TEST(ScanConfig, ReadsValuesAndComments) {
  const Result<ScanParams> p = parse_scan_config(
      "# comment\n\nup 0 0 -1  # trailing\ncamera_tilt_deg 45\nmin_cluster_points 50\nseed 9\n",
      "t.conf");
  ASSERT_TRUE(p.ok()) << p.error().format();
  EXPECT_EQ(p->up, (Vec3{0, 0, -1}));
  EXPECT_EQ(p->camera_tilt_deg, 45);
  EXPECT_EQ(p->min_cluster_points, 50);
  EXPECT_EQ(p->shape.seed, 9u);
}

void expect_error(std::string_view text, int line, int column, std::string_view words) {
  const Result<ScanParams> p = parse_scan_config(text, "t.conf");
  ASSERT_FALSE(p.ok()) << text;
  EXPECT_EQ(p.error().location, (Location{"t.conf", line, column})) << p.error().format();
  EXPECT_NE(p.error().message.find(words), std::string::npos) << p.error().format();
}

TEST(ScanConfig, ErrorsCarryLineAndColumn) {
  expect_error("pixel_stride 2\nclustr_tolerance_m 0.02\n", 2, 1, "unknown key");
  expect_error("mls_radius_m 0.01x\n", 1, 14, "expected a number");
  expect_error("  up 0 -1\n", 1, 10, "takes 3 values");
  expect_error("pixel_stride 2 3\n", 1, 16, "takes 1 value");
  expect_error("pixel_stride 0\n", 1, 14, "whole number >= 1");
  expect_error("pixel_stride 1.5\n", 1, 14, "whole number");
  expect_error("max_plane_angle_deg 120\n", 1, 21, "[0, 90]");
  expect_error("shape_min_coverage 1.5\n", 1, 20, "[0, 1]");
  expect_error("up 0 0 0\n", 1, 4, "zero vector");
  expect_error("seed -1\n", 1, 6, "whole number");
  expect_error("plane_distance_m nan\n", 1, 18, "expected a number");
}

TEST(ScanConfig, MissingFileIsAnError) {
  const Result<ScanParams> p = read_scan_config_file("/nonexistent/scan.conf");
  EXPECT_FALSE(p.ok());
}

// --- real Kinect scans ---

std::optional<Frame> real_frame(const std::string& name) {
  const auto path = kReal / name;
  if (!std::filesystem::exists(path)) return std::nullopt;
  Result<Frame> f = read_pcd(path);
  EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().format());
  if (!f.ok()) return std::nullopt;
  return std::move(*f);
}

const PhysicalObject* nearest(const ScanResult& scan, double col) {
  const PhysicalObject* best = nullptr;
  double best_d = 1e9;
  for (size_t k = 0; k < scan.scene.objects.size(); ++k) {
    const Vec3 c = centroid(scan.clusters[k].points);
    const double d = std::abs(525.0 * c.x / c.z + 319.5 - col);
    if (d < best_d) {
      best_d = d;
      best = &scan.scene.objects[k];
    }
  }
  return best;
}

TEST(ScannerReal, TheFloorBentAtTheImagesCornerIsNoSecondSupport) {
  // milk_cartoon: the carpet rises 2.5 cm above the floor's plane toward the image's
  // top right corner, 1.8 m away (the depth's distortion). The rise, above the floor's
  // band and mostly beyond its reach and hull, holds a support's area: with
  // support_edge_min_share it is a region of its own, and it meets the floor without a
  // step, so it is the floor's (support_floor_step_sigmas), not a second support.
  const auto f = real_frame("milk_cartoon_all_small_clorox.pcd");
  if (!f) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  ScanParams without;
  without.support_floor_step_sigmas = 0;
  const Result<ScanResult> on = scan_frame(*f);
  const Result<ScanResult> off = scan_frame(*f, without);
  ASSERT_TRUE(on.ok()) << on.error().format();
  ASSERT_TRUE(off.ok()) << off.error().format();
  EXPECT_EQ(on->supports.size(), 1u);
  EXPECT_EQ(off->supports.size(), 2u);
  EXPECT_EQ(on->scene.objects.size(), off->scene.objects.size());
}

TEST(ScannerReal, MilkCartoonSceneFindsFloorAndBottles) {
  const auto f = real_frame("milk_cartoon_all_small_clorox.pcd");
  if (!f) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  const Result<ScanResult> scan = scan_frame(*f);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  // The floor, seen from about 1 m at a downward tilt.
  EXPECT_LT(scan->plane.normal.y, -0.7);
  EXPECT_GT(scan->plane.d, 0.3);
  EXPECT_GE(scan->scene.objects.size(), 3u);
  // The bleach bottle on the right (image column ~450): a cylinder about 12-16 cm
  // across, its body 18-30 cm tall.
  const PhysicalObject* bleach = nearest(*scan, 450);
  ASSERT_NE(bleach, nullptr);
  ASSERT_FALSE(bleach->primitives.empty());
  EXPECT_EQ(bleach->primitives[0].kind, ShapeKind::cylinder);
  EXPECT_GT(bleach->primitives[0].dimensions_m[0], 0.05);
  EXPECT_LT(bleach->primitives[0].dimensions_m[0], 0.085);
  EXPECT_GT(bleach->primitives[0].dimensions_m[1], 0.18);
  EXPECT_LT(bleach->primitives[0].dimensions_m[1], 0.30);
  // Its handle, cut off by a depth edge, is part of it and not an object of its own.
  for (const PhysicalObject& o : scan->scene.objects)
    if (&o != bleach && !o.primitives.empty())
      EXPECT_GT(norm(o.primitives[0].center - bleach->primitives[0].center), 0.1) << o.id;
  // The detergent bottle on the left (column ~130, a jug with a handle): a box or a
  // cylinder (its body tapers, so a frustum fits and reads as a cylinder), 15-28 cm tall.
  const PhysicalObject* detergent = nearest(*scan, 130);
  ASSERT_NE(detergent, nullptr);
  ASSERT_FALSE(detergent->primitives.empty());
  const PhysicalPrimitive& jug = detergent->primitives[0];
  EXPECT_TRUE(jug.kind == ShapeKind::cylinder || jug.kind == ShapeKind::box)
      << shape_name(jug.kind);
  const double jug_height = jug.kind == ShapeKind::box ? jug.dimensions_m[2] : jug.dimensions_m[1];
  EXPECT_GT(jug_height, 0.15);
  EXPECT_LT(jug_height, 0.28);
  // The carton in the centre (column ~280): a box of household size.
  const PhysicalObject* carton = nearest(*scan, 280);
  ASSERT_NE(carton, nullptr);
  ASSERT_FALSE(carton->primitives.empty());
  EXPECT_EQ(carton->primitives[0].kind, ShapeKind::box);
  EXPECT_GT(carton->primitives[0].dimensions_m[2], 0.15);
  EXPECT_LT(carton->primitives[0].dimensions_m[2], 0.28);
  // Its faces are found where their points are: the box explains most of it.
  EXPECT_GT(carton->fit, 0.65);
}

class ScannerRealSequence : public ::testing::TestWithParam<const char*> {};

TEST_P(ScannerRealSequence, FindsTheCardboardBoxAndTheLaptopLid) {
  const auto f = real_frame(GetParam());
  if (!f) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  const Result<ScanResult> scan = scan_frame(*f);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  // The white box right of the laptop (column ~440): README guesses 20 x 12 x 10 cm;
  // its top face alone spans 24 x 16 cm in these clouds, and it stands 9 cm tall.
  const PhysicalObject* box = nearest(*scan, 440);
  ASSERT_NE(box, nullptr);
  ASSERT_FALSE(box->primitives.empty());
  EXPECT_EQ(box->primitives[0].kind, ShapeKind::box);
  std::vector<double> d = box->primitives[0].dimensions_m;
  std::sort(d.begin(), d.end());
  EXPECT_GT(d[2], 0.18);
  EXPECT_LT(d[2], 0.28);
  EXPECT_GT(d[1], 0.12);
  EXPECT_LT(d[1], 0.20);
  EXPECT_GT(d[0], 0.07);
  EXPECT_LT(d[0], 0.11);
  EXPECT_GT(box->fit, 0.8);  // its faces, not a footprint cut short by one side
  // The laptop lid leaning back (column ~250): a thin box about 37 x 25 cm.
  const PhysicalObject* lid = nearest(*scan, 250);
  ASSERT_NE(lid, nullptr);
  ASSERT_FALSE(lid->primitives.empty());
  EXPECT_EQ(lid->primitives[0].kind, ShapeKind::box);
  d = lid->primitives[0].dimensions_m;
  std::sort(d.begin(), d.end());
  EXPECT_LT(d[0], 0.03);
  EXPECT_GT(d[2], 0.3);
  EXPECT_LT(d[2], 0.42);
}

INSTANTIATE_TEST_SUITE_P(Frames, ScannerRealSequence,
                         ::testing::Values("frame_20121214T142255.814212.pcd",
                                           "frame_20121214T142256.068683.pcd",
                                           "frame_20121214T142256.332395.pcd"));

TEST(ScannerReal, OfficeIsClutteredButScans) {
  const auto f = real_frame("office1.pcd");
  if (!f) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  const Result<ScanResult> scan = scan_frame(*f);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  EXPECT_LT(scan->plane.normal.y, -0.8);  // the floor, seen nearly level
}

TEST(ScannerReal, OfficeFindsItsStorageBoxWithTheDefaults) {
  const auto f = real_frame("office1.pcd");
  if (!f) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  const Result<ScanResult> scan = scan_frame(*f);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  EXPECT_LT(scan->plane.normal.y, -0.95);  // the floor first, the camera level
  EXPECT_GT(scan->plane.d, 1.2);           // 1.33 m below the camera, not the desk
  // The grey storage box at the bottom right (column ~530), 2.5 m away, on the floor:
  // its top about 50 cm above it, 30 to 60 cm wide (its base is below the image).
  const PhysicalObject* box = nullptr;
  double best = 60;
  for (size_t k = 0; k < scan->scene.objects.size(); ++k) {
    const Vec3 c = centroid(scan->clusters[k].points);
    const double d = std::abs(525.0 * c.x / c.z + 319.5 - 530);
    if (scan->scene.objects[k].support_id == scan->scene.supports.front().id && d < best)
      best = d, box = &scan->scene.objects[k];
  }
  ASSERT_NE(box, nullptr);
  ASSERT_FALSE(box->primitives.empty());
  EXPECT_EQ(box->primitives[0].kind, ShapeKind::box);
  const std::vector<double>& d = box->primitives[0].dimensions_m;
  EXPECT_GT(std::max(d[0], d[1]), 0.3);
  EXPECT_LT(std::max(d[0], d[1]), 0.6);
  EXPECT_GT(d[2], 0.4);
  EXPECT_LT(d[2], 0.65);
  // Walls and cupboards run on above the height band: none of them is an object.
  for (const PhysicalObject& o : scan->scene.objects)
    if (!o.primitives.empty()) EXPECT_LT(o.primitives[0].dimensions_m.back(), 0.65) << o.id;
}

TEST(ScannerReal, NyuBasementHasTheFloorAndNoWardrobeSlices) {
  const auto f = real_frame("nyu_basement.pcd");
  if (!f) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  const Result<ScanResult> scan = scan_frame(*f);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  // The concrete floor, about 1.5 m below the camera.
  EXPECT_LT(scan->plane.normal.y, -0.9);
  EXPECT_NEAR(scan->plane.d, 1.5, 0.1);
  // The cloth wardrobe (columns 170 to 350) runs on above the band: no whole object
  // stands there (before depth-scaled clustering it came out as a row of thin boxes).
  for (size_t k = 0; k < scan->scene.objects.size(); ++k) {
    if (scan->scene.objects[k].partial) continue;
    const Vec3 c = centroid(scan->clusters[k].points);
    const double col = 582.6 * c.x / c.z + 313.0;
    EXPECT_FALSE(col > 170 && col < 350 && c.z > 3.0) << scan->scene.objects[k].id << " at column " << col;
  }
  // The stacked blue bins on the left (columns 0 to 110, 3.5 m away), seen face-on:
  // whatever of them is whole is a box, not a disc on its rim (their face's outline is a
  // rectangle; at this depth most of it lies within the noise tolerance of a circle, so
  // only the outline energies of circle and rectangle tell them apart). The bins above
  // the lower one run on above the band: 20 of the 26 columns whose topmost pixel lies at
  // the band's top continue above it, so that slice is furniture cut by the band (no
  // prop, since session 19). The lower bin is a box (NyuBasementLowerBinIsABox).
  for (size_t k = 0; k < scan->scene.objects.size(); ++k) {
    const Vec3 c = centroid(scan->clusters[k].points);
    const double col = 582.6 * c.x / c.z + 313.0;
    if (scan->scene.objects[k].partial || col > 110 || c.z < 3.2 || c.z > 3.8) continue;
    if (scan->scene.objects[k].point_count < 3000) continue;
    ASSERT_FALSE(scan->scene.objects[k].primitives.empty());
    EXPECT_EQ(scan->scene.objects[k].primitives[0].kind, ShapeKind::box) << scan->scene.objects[k].id;
  }
}

// A solid resting on its support touches it and does not pass through it: no cylinder
// lying or leaning in a real frame has the cross-section through its centre below its
// support by more than twice the noise tolerance at its depth (its centre's height and
// its radius are each fitted to within about one; nyu_basement's lower bin was a
// cylinder r 0.32 m whose centre lay at the floor's height, 7 tolerances through it).
TEST(ScannerReal, NoLyingCylinderPassesThroughItsSupport) {
  for (const char* name : {"nyu_basement.pcd", "office1.pcd", "frame_20121214T142256.068683.pcd",
                           "frame_20121214T142256.332395.pcd", "milk_cartoon_all_small_clorox.pcd"}) {
    const auto f = real_frame(name);
    if (!f) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
    const Result<ScanResult> scan = scan_frame(*f);
    ASSERT_TRUE(scan.ok()) << scan.error().format();
    for (const PhysicalObject& o : scan->scene.objects) {
      if (o.primitives.empty() || o.primitives[0].kind != ShapeKind::cylinder) continue;
      const PhysicalPrimitive& c = o.primitives[0];
      const auto s = std::find_if(scan->scene.supports.begin(), scan->scene.supports.end(),
                                  [&](const SupportSurface& x) { return x.id == o.support_id; });
      ASSERT_NE(s, scan->scene.supports.end()) << name << " " << o.id;
      const double nn = std::sqrt(dot(s->plane.normal, s->plane.normal));
      const Vec3 axis = c.axis * (1.0 / std::sqrt(dot(c.axis, c.axis)));
      const double up = std::abs(dot(axis, s->plane.normal)) / nn;
      if (up > std::cos(3.14159265358979 / 4)) continue;  // upright: stands on its base
      const double centre_h = (dot(s->plane.normal, c.center) + s->plane.d) / nn;
      const double lowest = centre_h - c.dimensions_m[0] * std::sqrt(1 - up * up);
      const double z = std::abs(c.center.z);
      const double tol = std::max(0.004, 2.5 * (0.0012 + 0.0019 * (z - 0.4) * (z - 0.4)));
      EXPECT_GT(lowest, -2 * tol) << name << " " << o.id << " r " << c.dimensions_m[0];
    }
  }
}

// nyu_basement's lower bin (left edge, about 3.2 m away, on the floor): a box, as its
// README line asks. Its any-axis cylinder passed through the floor; the upright cylinder
// inscribed in it (r 0.15 m) ranked first by the half credit its box corners got as a
// rim's parts, though the box explains more of the points and closer.
TEST(ScannerReal, NyuBasementLowerBinIsABox) {
  const auto f = real_frame("nyu_basement.pcd");
  if (!f) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  const Result<ScanResult> scan = scan_frame(*f);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  bool bin = false;
  for (size_t k = 0; k < scan->scene.objects.size(); ++k) {
    const PhysicalObject& o = scan->scene.objects[k];
    const Vec3 c = centroid(scan->clusters[k].points);
    const double col = 582.6 * c.x / c.z + 313.0;
    if (o.partial || col > 110 || c.z < 2.9 || c.z > 3.4 || o.point_count < 1000) continue;
    bin = true;
    ASSERT_FALSE(o.primitives.empty()) << o.id;
    EXPECT_EQ(o.primitives[0].kind, ShapeKind::box) << o.id;
  }
  EXPECT_TRUE(bin);
}

// The laptop frames' lying objects cut by the image's top edge stay cylinders: their
// fits' centres sit one radius above the floor (their axes, fixed by a partial view,
// dip into it at one end).
TEST(ScannerReal, LaptopFramesLyingCylindersAtTheTopEdgeStayCylinders) {
  for (const char* name : {"frame_20121214T142256.068683.pcd", "frame_20121214T142256.332395.pcd"}) {
    const auto f = real_frame(name);
    if (!f) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
    const Result<ScanResult> scan = scan_frame(*f);
    ASSERT_TRUE(scan.ok()) << scan.error().format();
    int lying = 0;
    for (size_t k = 0; k < scan->scene.objects.size(); ++k) {
      const PhysicalObject& o = scan->scene.objects[k];
      int top = f->height;
      for (int i : scan->clusters[k].pixels) top = std::min(top, i / f->width);
      const Vec3 c = centroid(scan->clusters[k].points);
      const double col = 525.0 * c.x / c.z + 319.5;
      if (top > 30 || col > 380 || o.point_count < 800) continue;
      ASSERT_FALSE(o.primitives.empty()) << name << " " << o.id;
      EXPECT_EQ(o.primitives[0].kind, ShapeKind::cylinder) << name << " " << o.id;
      ++lying;
    }
    EXPECT_GE(lying, 1) << name;
  }
}

TEST(ScannerReal, MilkCartoonBorderSliversArePartial) {
  const auto f = real_frame("milk_cartoon_all_small_clorox.pcd");
  if (!f) GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  const Result<ScanResult> scan = scan_frame(*f);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  // The objects at the image's top edge, 1.6 to 1.8 m away (slivers of things cut by
  // the border), are flagged partial: the sensor's depth starts a few rows down.
  int at_top = 0;
  for (size_t k = 0; k < scan->clusters.size(); ++k) {
    int top = f->height;
    for (int i : scan->clusters[k].pixels) top = std::min(top, i / f->width);
    // The sensor's depth starts at row 16 here; whole objects start far below it.
    if (top > 30) {
      if (top > 50) EXPECT_FALSE(scan->scene.objects[k].partial) << scan->scene.objects[k].id;
      continue;
    }
    ++at_top;
    EXPECT_TRUE(scan->scene.objects[k].partial) << scan->scene.objects[k].id << " top row " << top;
  }
  EXPECT_GE(at_top, 1);
}

// --- every support, on the widened generator ---

SyntheticFrame world(std::uint64_t seed) {
  const Result<SyntheticScene> scene = generate_scene(world_scene_params(seed));
  EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().format());
  return render_scene(*scene);
}

TEST(ScannerWorld, TableObjectsFoundOnTheirSupportsAndNoLegsOrSlivers) {
  // Legs, border slivers and the bodies of second supports holding objects (furniture)
  // are not props.
  int truth_near = 0, found_near = 0, on_right_support = 0, found = 0, legs = 0, slivers = 0,
      furniture = 0, truth_mid = 0, classed_mid = 0;
  for (std::uint64_t seed = 2001; seed <= 2012; ++seed) {
    const SyntheticFrame f = world(seed);
    const Result<ScanResult> scan = scan_frame(f.frame);
    ASSERT_TRUE(scan.ok()) << "seed " << seed << ": " << scan.error().format();
    std::vector<int> owner;
    for (const ScanCluster& c : scan->clusters) owner.push_back(majority_label(f, c));
    for (size_t k = 0; k < owner.size(); ++k) {
      const PhysicalObject& o = scan->scene.objects[k];
      if (o.partial) continue;
      legs += owner[k] == kLabelLeg;
      furniture += owner[k] == kLabelFurniture;
      if (owner[k] >= 0 && f.truth.objects[static_cast<size_t>(owner[k])].partial) ++slivers;
      if (owner[k] < 0) continue;
      ++found;
      // The scanned support is the truth one: same height within 3 cm.
      const PhysicalObject& t = f.truth.objects[static_cast<size_t>(owner[k])];
      const SupportSurface* truth_support = nullptr;
      for (const SupportSurface& sp : f.truth.supports)
        if (sp.id == t.support_id) truth_support = &sp;
      for (const SupportSurface& sp : scan->scene.supports)
        if (sp.id == o.support_id && truth_support &&
            std::abs(sp.plane.d - truth_support->plane.d) < 0.03)
          ++on_right_support;
    }
    for (size_t t = 0; t < f.truth.objects.size(); ++t) {
      const PhysicalPrimitive& tp = f.truth.objects[t].primitives[0];
      if (f.truth.objects[t].partial || norm(tp.center) > 2.5) continue;
      double largest = *std::max_element(tp.dimensions_m.begin(), tp.dimensions_m.end());
      if (tp.kind != ShapeKind::box) largest = std::max(largest, 2 * tp.dimensions_m[0]);
      if (largest < 0.05) continue;
      if (norm(tp.center) >= 1.5) {
        // 1.5 to 2.5 m: the shape class of the object most of whose pixels it shows.
        ++truth_mid;
        const auto it = std::find(owner.begin(), owner.end(), static_cast<int>(t));
        if (it == owner.end()) continue;
        const PhysicalObject& o = scan->scene.objects[static_cast<size_t>(it - owner.begin())];
        classed_mid += !o.primitives.empty() && o.primitives[0].kind == tp.kind;
        continue;
      }
      ++truth_near;
      found_near += std::find(owner.begin(), owner.end(), static_cast<int>(t)) != owner.end();
    }
  }
  ASSERT_GT(truth_mid, 8);
  // Measured: 21 of 25 (18 before the margins in millimetres and the rim check: far
  // boxes came out as tins on their rim, frustums as cylinders).
  EXPECT_GE(classed_mid, truth_mid * 84 / 100) << classed_mid << " of " << truth_mid;
  ASSERT_GT(truth_near, 8);
  EXPECT_GE(found_near, truth_near * 90 / 100) << found_near << " of " << truth_near;
  // Measured: every object found on the right support, no leg and no sliver reported
  // whole (the generator's truth marks an object cut when its pixels reach the border).
  EXPECT_GE(on_right_support, found * 90 / 100) << on_right_support << " of " << found;
  EXPECT_EQ(legs, 0);
  EXPECT_EQ(slivers, 0);
  // No furniture body reported whole on these seeds (4 before the furniture rule, 1
  // before every up-facing height was searched).
  EXPECT_EQ(furniture, 0);
}

// No object reported whole (not partial) on these world seeds is mostly `label`'s pixels.
void expect_none_whole(std::initializer_list<std::uint64_t> seeds, int label, const char* what) {
  for (std::uint64_t seed : seeds) {
    const SyntheticFrame f = world(seed);
    const Result<ScanResult> scan = scan_frame(f.frame);
    ASSERT_TRUE(scan.ok()) << scan.error().format();
    for (size_t k = 0; k < scan->clusters.size(); ++k) {
      const PhysicalObject& o = scan->scene.objects[k];
      if (!o.partial)
        EXPECT_NE(majority_label(f, scan->clusters[k]), label)
            << "seed " << seed << " " << o.id << " is " << what << " reported whole";
    }
  }
}

TEST(ScannerWorld, TallFurnitureSeenSteeplyFromAboveIsNoProp) {
  // Seeds 2031 and 2056: a cupboard 1.6 to 2 m tall beside the table, 3 m away, seen
  // from above at a steep angle: its front's rows lie 2 to 3 cm apart, more than the
  // cluster tolerance, so its slice in the height band looked like it ended there and
  // came out as a box of 0.59 m (the band's top). Its rows are evenly spaced: the
  // front continues above the band and the slice is dropped.
  expect_none_whole({2031, 2056}, kLabelFurniture, "a furniture slice");
}

TEST(ScannerWorld, EverySupportOfARoomFullOfCabinetsIsFound) {
  // Six cabinets of different heights beside the table (15 to 65 cm), with the table and
  // the floor eight horizontal surfaces and walls, legs and objects between them: each
  // cabinet's top is a support, however many surfaces the frame holds. (Six plane
  // searches, walls included, could not reach them all.)
  Result<SyntheticScene> scene = generate_scene(world_scene_params(2005));
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  SyntheticScene s = *scene;
  // Only the table's objects and legs stay; the cabinets, 40 cm wide and deep, stand in
  // two rows beside the table, lower ones nearer to the camera.
  std::vector<SyntheticBlock> kept;
  for (const SyntheticBlock& b : s.furniture)
    if (b.role == SyntheticBlock::Role::leg) kept.push_back(b);
  s.furniture = kept;
  std::erase_if(s.objects, [](const SyntheticObject& o) { return o.support != 0; });
  s.camera_tilt_deg = 40;
  s.camera_position = Vec3{0, 0, 0} - Vec3{0, std::cos(40 * 3.14159265358979 / 180), -std::sin(40 * 3.14159265358979 / 180)} * 2.2;
  s.wall_y_m = 1.4;
  // The tallest top is 10 cm under the table's (min_support_gap_m apart).
  const double heights[2][3] = {{0.15, 0.35, 0.55}, {0.25, 0.45, 0.65}};
  for (int side = 0; side < 2; ++side)
    for (int row = 0; row < 3; ++row) {
      const double h = heights[side][row];
      s.furniture.push_back({{(side ? 1 : -1) * (s.table_half_x_m + 0.3), -0.4 + 0.5 * row,
                              -s.floor_depth_m + h * 0.5},
                             {0.4, 0.4, h},
                             SyntheticBlock::Role::support});
    }
  const SyntheticFrame f = render_scene(s);
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  // Each cabinet's top centre lies on a support found (within 2 cm: a plane's offset
  // alone is off by more 2 m away, where a tenth of a degree of tilt moves it).
  int found = 0;
  for (const SyntheticBlock& b : s.furniture) {
    if (b.role != SyntheticBlock::Role::support) continue;
    const Vec3 top = table_to_camera_point(s, b.center + Vec3{0, 0, b.size_m.z * 0.5});
    bool seen = false;
    for (const ScanSupport& got : scan->supports)
      seen = seen || std::abs(dot(got.surface.plane.normal, top) + got.surface.plane.d) < 0.02;
    found += seen;
    EXPECT_TRUE(seen) << "the cabinet " << b.size_m.z << " m tall is not a support";
  }
  EXPECT_EQ(found, 6);
}

TEST(ScannerFar, SmallFarToriAndBallsAreNotBoxesOrCones) {
  // 2.2 to 3 m away, seen by 50 to 160 points: the residual tolerance (2.5 sigma_z, 16 to
  // 25 mm) is as thick as a torus's tube or a small ball, so a box, a cone and a cylinder
  // explain every point too and their RMS differs from the true shape's by under a
  // millimetre. A box (6 parameters) or a cone (5) follows the noise that closely by
  // chance; the information criterion keeps the torus (4) and the sphere (4). Measured:
  // all 4 right (boxes or cones before it: seeds 2041 and 2059's tori, 2057's torus at
  // 2.27 m, 2056's ball of 49 points at 2.99 m).
  int checked = 0;
  for (std::uint64_t seed : {2041u, 2056u, 2057u, 2059u}) {
    const SyntheticFrame f = world(seed);
    const Result<ScanResult> scan = scan_frame(f.frame);
    ASSERT_TRUE(scan.ok()) << scan.error().format();
    for (size_t k = 0; k < scan->clusters.size(); ++k) {
      const int owner = majority_label(f, scan->clusters[k]);
      if (owner < 0) continue;
      const PhysicalObject& t = f.truth.objects[static_cast<size_t>(owner)];
      const ShapeKind kind = t.primitives[0].kind;
      const double dist = norm(t.primitives[0].center);
      if (t.partial || (kind != ShapeKind::torus && kind != ShapeKind::sphere) || dist < 2.2 || dist > 3.0)
        continue;
      const PhysicalObject& o = scan->scene.objects[k];
      if (o.point_count > 200) continue;
      ++checked;
      const bool ok = !o.primitives.empty() && o.primitives[0].kind == kind;
      EXPECT_TRUE(ok) << "seed " << seed << " " << o.id << " (" << shape_name(kind) << ", "
                      << o.point_count << " points at " << dist << " m) is "
                      << (o.primitives.empty() ? "unknown" : shape_name(o.primitives[0].kind));
    }
  }
  EXPECT_GE(checked, 4);
}

TEST(ScannerFar, FlatBowlSeenFromAboveIsRoundNotABox) {
  // A flat bowl widening up (closed at its rim, as the generator draws it) seen from
  // 1.6 m and 55 degrees above: its side hides under the rim, so a box explains the disc
  // of its top as its top face and the rest as inside it; the outline of that top is a
  // circle, which the box's rectangle fits far worse.
  int round = 0, seen = 0;
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    SyntheticSceneParams p;
    p.seed = seed;
    p.object_count = 0;
    p.camera_distance_min_m = p.camera_distance_max_m = 1.6;
    p.camera_tilt_min_deg = p.camera_tilt_max_deg = 55;
    Result<SyntheticScene> scene = generate_scene(p);
    ASSERT_TRUE(scene.ok()) << scene.error().format();
    const double t = scene->camera_tilt_deg * 3.14159265358979323846 / 180;
    const Vec3 aim = scene->camera_position +
                     Vec3{0, std::cos(t), -std::sin(t)} * (scene->camera_position.z / std::sin(t));
    SyntheticObject bowl = resting_object(ShapeKind::cone, {0.11, 0.08}, aim.x, aim.y);
    bowl.apex_down = true;
    bowl.narrow_radius_m = 0.06;
    scene->objects = {bowl};
    const SyntheticFrame f = render_scene(*scene);
    const Result<ScanResult> scan = scan_frame(f.frame);
    ASSERT_TRUE(scan.ok()) << scan.error().format();
    for (size_t k = 0; k < scan->clusters.size(); ++k) {
      if (majority_label(f, scan->clusters[k]) != 0) continue;
      const PhysicalObject& o = scan->scene.objects[k];
      ASSERT_FALSE(o.primitives.empty()) << "seed " << seed;
      const PhysicalPrimitive& prim = o.primitives[0];
      ++seen;
      if (prim.kind == ShapeKind::cylinder || prim.kind == ShapeKind::cone) {
        ++round;
        // Its wide radius is the rim's.
        EXPECT_NEAR(prim.dimensions_m[0], 0.11, 0.015) << "seed " << seed;
      }
    }
  }
  ASSERT_EQ(seen, 2);
  EXPECT_EQ(round, 2);
}

TEST(ScannerFar, AFlatBowlsRimBlurredByTheNoiseIsStillRound) {
  // Fresh rooms 10030, 9532 and 9924 (session 26): flat bowls 21 to 23 cm wide, 2.3 to
  // 2.4 m away, seen from above. The depth noise there blurs the rim: the rectangle
  // left 1.4, 1.8 and 1.2 times the circle's residual energy on the outline, under the
  // former bar of 2, and they were boxes. At 1 (the circle, with two parameters fewer,
  // explains the outline as well) they are round; no box of those sets gave over 0.8.
  struct Bowl {
    std::uint64_t seed;
    double radius;  // the truth's, to tell it among the room's objects
  };
  ShapeRecognizerParams strict;
  strict.min_footprint_roundness = 2;
  // Since session 27 the table seen under a rim along the rays (foot_seen_along_ray)
  // contradicts the box of some of these bowls too: off here, to compare the roundness
  // alone.
  strict.foot_seen_along_ray = false;
  // ... and so does the lid setting the top (session 34): 9924's bowl is a cylinder.
  strict.lid_spread_sigmas = 0;
  ScanParams before;
  before.shape = strict;
  // ... and the band as before session 27 (band_along_ray): with the band along the rays
  // 9924's bowl is no box at the strict bar either (a cylinder).
  before.band_along_ray = false;
  for (const Bowl& b : {Bowl{10030u, 0.117}, Bowl{9532u, 0.102}, Bowl{9924u, 0.071}}) {
    for (const bool now : {true, false}) {
      const RoomScan r = scan_room(b.seed, now ? ScanParams{} : before);
      const int t = find_object(r.scene, [&](const SyntheticObject& o) {
        return o.kind == ShapeKind::cone && o.apex_down &&
               std::abs(o.dimensions_m[0] - b.radius) < 0.001;
      });
      ASSERT_GE(t, 0) << "seed " << b.seed;
      const std::optional<PhysicalObject>& o = r.of[static_cast<size_t>(t)];
      ASSERT_TRUE(o && !o->primitives.empty()) << "seed " << b.seed;
      const ShapeKind kind = o->primitives[0].kind;
      if (now)
        EXPECT_TRUE(kind == ShapeKind::cylinder || kind == ShapeKind::cone)
            << "seed " << b.seed << ": " << shape_name(kind);
      else
        EXPECT_EQ(kind, ShapeKind::box) << "seed " << b.seed << ": " << shape_name(kind);
    }
  }
}

TEST(ScannerFar, AConeWiderAtItsFootThanItsBoxIsStillACone) {
  // Fresh room 9855 (session 27): a cone 12 cm wide at its foot and 17 cm tall on the
  // floor 2 m away, seen past a neighbour. Its box's faces sit at their points' median,
  // at the cone's middle: 6 cm wide. The cone's radius (6.3 cm) passed that width, the
  // bound for a flat face read as a huge arc, and the cone was dropped: a cylinder 2 cm
  // thick was what stood. The bound is now the points' widest extent (8 cm).
  const Result<SyntheticScene> scene = generate_scene(room_scene_params(9855));
  ASSERT_TRUE(scene.ok());
  const int t = find_object(*scene, [](const SyntheticObject& o) {
    return o.kind == ShapeKind::cone && !o.apex_down && std::abs(o.dimensions_m[0] - 0.061) < 0.001;
  });
  ASSERT_GE(t, 0);
  const SyntheticFrame f = render_scene(*scene);
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  const ScanCluster* cone = nullptr;
  for (const ScanCluster& c : scan->clusters)
    if (majority_label(f, c) == t) cone = &c;
  ASSERT_NE(cone, nullptr);
  ASSERT_FALSE(cone->shape.primitives.empty());
  const PhysicalPrimitive& got = cone->shape.primitives[0].primitive;
  ASSERT_EQ(got.kind, ShapeKind::cone) << shape_name(got.kind);
  EXPECT_NEAR(got.dimensions_m[0], 0.061, 0.005);  // radius at the foot
  EXPECT_NEAR(got.dimensions_m[1], 0.169, 0.015);  // height
  // The case: the box is narrower than the cone's radius.
  for (const ShapeFit& c : cone->shape.candidates)
    if (c.primitive.kind == ShapeKind::box)
      EXPECT_LT(std::max(c.primitive.dimensions_m[0], c.primitive.dimensions_m[1]),
                got.dimensions_m[0]);
}

TEST(ScannerFar, ACylinderBesideABoardsSeenPartStandsOnTheBoard) {
  // Fresh room 9902 (session 28): a shelf's board 12 cm below the camera's height, 1.5 m
  // away, seen at five degrees: its top shows as a patch 17 cm wide between a ball and a
  // lamp. A cylinder 10 cm wide and 15 cm tall stands on the board 13 cm to the patch's
  // left, where the board's top is lost to the grazing view: no support's hull or reach
  // held it, 62 cm above the floor it was in no prism, and it was missed. Around a small
  // support's seen part its surface may run on unseen (seen_part_reach_m): the cylinder's
  // foot lies on the board's plane, and the board, nearer, lies under it.
  const Result<SyntheticScene> scene = generate_scene(room_scene_params(9902));
  ASSERT_TRUE(scene.ok());
  const int t = find_object(*scene, [](const SyntheticObject& o) {
    return o.kind == ShapeKind::cylinder && o.support > 0 &&
           std::abs(o.dimensions_m[0] - 0.0516) < 0.001;
  });
  ASSERT_GE(t, 0);
  const SyntheticFrame f = render_scene(*scene);
  const auto cylinder_of = [&](const ScanResult& scan) -> const ScanCluster* {
    for (const ScanCluster& c : scan.clusters)
      if (majority_label(f, c) == t) return &c;
    return nullptr;
  };
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  const ScanCluster* got = cylinder_of(*scan);
  ASSERT_NE(got, nullptr);
  ASSERT_FALSE(got->shape.primitives.empty());
  const PhysicalPrimitive& cyl = got->shape.primitives[0].primitive;
  ASSERT_EQ(cyl.kind, ShapeKind::cylinder) << shape_name(cyl.kind);
  EXPECT_NEAR(cyl.dimensions_m[0], 0.0516, 0.004);  // radius
  EXPECT_NEAR(cyl.dimensions_m[1], 0.147, 0.01);    // height
  // It stands on the board: the support under it is 12 cm below the camera, not the
  // table (27 cm) or the floor (74 cm).
  EXPECT_NEAR(got->support.d, 0.12, 0.02);
  // The case: without the reach around the seen part no cluster holds it, with the
  // surface normals of then (taken across depth edges). With today's, the board's
  // support holds 1,728 points rather than 604 and holds the cylinder without the reach.
  ScanParams before;
  before.seen_part_reach_m = 0;
  before.surface_max_incidence_deg = 90;
  // ... and every region of the board's plane kept, as then: with only the regions seen
  // from above (support_regions_seen_only, session 36) the board holds the cylinder
  // without the reach too.
  before.support_regions_seen_only = false;
  const Result<ScanResult> old = scan_frame(f.frame, before);
  ASSERT_TRUE(old.ok()) << old.error().format();
  EXPECT_EQ(cylinder_of(*old), nullptr);
}

TEST(ScannerFar, AFlatBowlSeenFromAboveTwoMetresAwayIsAFrustum) {
  // Plain worlds 5018 and 3012 (session 27): solid bowls 14 and 19 cm wide at the rim,
  // 4.4 and 3.6 cm tall, 2 m away, seen from above: the rim hides the side, and the
  // cylinder of the rim explains every point. The table shows under the rim, where the
  // cylinder would stand, but the tolerance there is 1.5 cm: shrunk by it in every
  // direction the cylinder had next to no solid left to be seen through. The depth
  // noise moves a point along its ray, so a table point whose ray runs inside the
  // cylinder for more than the tolerance is seen through it (foot_seen_along_ray).
  struct Bowl {
    std::uint64_t seed;
    double radius;  // the truth's, to tell it among the scene's objects
  };
  ScanParams before;
  before.shape.foot_seen_along_ray = false;
  // The lid setting the top (session 34) makes both frustums another way: off here.
  before.shape.lid_spread_sigmas = 0;
  for (const Bowl& b : {Bowl{5018u, 0.072}, Bowl{3012u, 0.096}}) {
    const Result<SyntheticScene> scene = generate_scene(world_scene_params(b.seed));
    ASSERT_TRUE(scene.ok());
    const int t = find_object(*scene, [&](const SyntheticObject& o) {
      return o.kind == ShapeKind::cone && o.apex_down &&
             std::abs(o.dimensions_m[0] - b.radius) < 0.001;
    });
    ASSERT_GE(t, 0) << "seed " << b.seed;
    const SyntheticFrame f = render_scene(*scene);
    for (const bool now : {true, false}) {
      const Result<ScanResult> scan = scan_frame(f.frame, now ? ScanParams{} : before);
      ASSERT_TRUE(scan.ok()) << scan.error().format();
      std::optional<ShapeKind> kind;
      for (size_t k = 0; k < scan->clusters.size(); ++k)
        if (majority_label(f, scan->clusters[k]) == t &&
            !scan->scene.objects[k].primitives.empty()) {
          EXPECT_FALSE(scan->scene.objects[k].partial) << "seed " << b.seed;
          kind = scan->scene.objects[k].primitives[0].kind;
        }
      ASSERT_TRUE(kind) << "seed " << b.seed;
      EXPECT_EQ(*kind, now ? ShapeKind::cone : ShapeKind::cylinder)
          << "seed " << b.seed << ": " << shape_name(*kind);
    }
  }
}

TEST(ScannerFar, ABoxOnAShelfTwoAndAHalfMetresAwayIsAnObjectOfItsOwn) {
  // Fresh room 9823 (session 27): a box 24 x 14 x 7 cm on a shelf's board 2.4 m away. The
  // band over a support was 2.5 sigma_z, 2.4 cm there, whatever the view; 1,452 of the
  // box's 2,015 pixels went into a background cluster of 4,450 and the box was missed.
  // The depth noise moves a point along its ray, off the board by sigma_z |n . ray|: the
  // band is 2.5 times that (band_along_ray), here the 1.2 cm floor, and the box is whole.
  ScanParams before;
  before.band_along_ray = false;
  for (const bool now : {true, false}) {
    const RoomScan r = scan_room(9823u, now ? ScanParams{} : before);
    const int t = find_object(r.scene, [](const SyntheticObject& o) {
      return o.kind == ShapeKind::box && std::abs(o.dimensions_m[0] - 0.237) < 0.001;
    });
    ASSERT_GE(t, 0);
    const std::optional<PhysicalObject>& o = r.of[static_cast<size_t>(t)];
    if (!now) {
      EXPECT_FALSE(o && !o->partial) << "whole before";
      continue;
    }
    ASSERT_TRUE(o);
    EXPECT_FALSE(o->partial);
    ASSERT_FALSE(o->primitives.empty());
    EXPECT_EQ(o->primitives[0].kind, ShapeKind::box) << shape_name(o->primitives[0].kind);
  }
}

TEST(ScannerFar, ATableFittedOffByDegreesWidensItsOwnBand) {
  // Fresh room 9934 (session 27): the table 3 m away is fitted 5 degrees off. With the
  // band along the rays alone (1.2 cm there) its far part rose out of the band into three
  // clusters of 700 to 3,300 pixels reported whole, which swallowed the cone, the torus
  // and the box standing there. The table's own surface lies off its plane by several
  // times the noise across it, and its band widens by that (surface_noise_scale): no part
  // of the table is a prop, and the three are found.
  const Result<SyntheticScene> scene = generate_scene(room_scene_params(9934u));
  ASSERT_TRUE(scene.ok());
  const SyntheticFrame f = render_scene(*scene);
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  std::set<int> found;
  for (size_t k = 0; k < scan->clusters.size(); ++k) {
    const int owner = majority_label(f, scan->clusters[k]);
    found.insert(owner);
    if (owner == kLabelTable)
      EXPECT_TRUE(scan->scene.objects[k].partial)
          << scan->scene.objects[k].id << " is the table reported whole";
  }
  for (int t : {0, 1, 2}) EXPECT_TRUE(found.count(t)) << "truth " << t << " missed";
}

TEST(ScannerFar, AFarFloorsPlaneIsFittedOnTheSensorsNoiseModel) {
  // Plain scene 6102 (session 29): a camera tilted 49 degrees over a floor 2.6 to 3.7 m
  // away, the table 2 to 2.8 m. RANSAC's band (1.2 cm) is under one sigma_z there, and
  // least squares on the strip it cut from the floor kept the triple's tilt: every
  // support 9 degrees off, the two bowls a cylinder and a torus, the bottle a box.
  // Fitted again in the noise-scaled band, weighted by the noise model, until it
  // settles (first_plane_noise_fit), every support lies within a degree of up and the
  // three are a frustum, a frustum and a cylinder.
  const Result<SyntheticScene> scene = generate_scene(world_scene_params(6102u));
  ASSERT_TRUE(scene.ok());
  const SyntheticFrame f = render_scene(*scene);
  const Vec3 up = f.truth.supports[0].plane.normal;
  const auto worst_tilt_deg = [&](const ScanResult& scan) {
    double worst = 0;
    for (const SupportSurface& sp : scan.scene.supports)
      worst =
          std::max(worst, std::acos(std::min(1.0, dot(sp.plane.normal, up))) * 180 / 3.14159265);
    return worst;
  };
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  EXPECT_LT(worst_tilt_deg(*scan), 1.0);
  std::map<int, ShapeKind> kind_of;
  for (size_t k = 0; k < scan->clusters.size(); ++k)
    if (!scan->clusters[k].shape.primitives.empty())
      kind_of[majority_label(f, scan->clusters[k])] =
          scan->clusters[k].shape.primitives[0].primitive.kind;
  int compared = 0;
  for (size_t t = 0; t < f.truth.objects.size(); ++t) {
    const PhysicalObject& o = f.truth.objects[t];
    if (o.partial || o.primitives.empty() || !kind_of.count(static_cast<int>(t))) continue;
    const ShapeKind want = o.primitives[0].kind;
    if (want != ShapeKind::cone && want != ShapeKind::cylinder) continue;
    ++compared;
    EXPECT_EQ(kind_of[static_cast<int>(t)], want) << "truth " << t << " is a " << shape_name(want);
  }
  EXPECT_EQ(compared, 3);
  // The case: in the fixed band alone the planes are 9 degrees off.
  ScanParams before;
  before.first_plane_noise_fit = false;
  const Result<ScanResult> old = scan_frame(f.frame, before);
  ASSERT_TRUE(old.ok()) << old.error().format();
  EXPECT_GT(worst_tilt_deg(*old), 5.0);
}

// How many of the room's objects on its table are found whole, standing on a scanned
// support within 2 cm of the table's height.
int whole_on_the_table(const RoomScan& r) {
  const SupportSurface& table = r.truth.supports[0];
  int found = 0;
  for (size_t t = 0; t < r.truth.objects.size(); ++t) {
    const std::optional<PhysicalObject>& o = r.of[t];
    if (r.truth.objects[t].support_id != table.id || !o || o->partial) continue;
    for (const SupportSurface& sp : r.supports)
      if (sp.id == o->support_id && std::abs(sp.plane.d - table.plane.d) < 0.02) ++found;
  }
  return found;
}

TEST(ScannerFar, ASurfaceNormalIsTakenWhereTheNeighboursHaveDepth) {
  // Fresh room 8025 (session 30): dark objects on a table 1.8 to 2.1 m away, the camera
  // 25 cm above it. A pixel's normal was taken only from neighbours a full reach (four
  // grid steps) away, and none where those had no depth: the first plane came out 10
  // degrees off, and the table's four objects were lost. Taken from nearer neighbours
  // where the far ones have no depth, the table is found and its ball stands on it.
  ScanParams before;
  before.surface_max_incidence_deg = 90;
  const RoomScan now = scan_room(8025u, ScanParams{});
  ASSERT_FALSE(now.truth.supports.empty());
  EXPECT_GE(whole_on_the_table(now), 1);
  const RoomScan old = scan_room(8025u, before);
  EXPECT_EQ(whole_on_the_table(old), 0);
  const Vec3 up = now.truth.supports[0].plane.normal;
  ASSERT_FALSE(old.supports.empty());
  EXPECT_LT(dot(old.supports[0].plane.normal, up), std::cos(5 * 3.14159265 / 180));
}

TEST(ScannerFar, ATablesFrontFaceOverTheFloorBehindDoesNotFaceUp) {
  // Fresh room 9559 (session 30), its floor fitted on the noise model at any turn: a
  // table 1.5 to 2.3 m away seen from 25 cm above. The pixels at the foot of its front
  // face took their normal through a neighbour on the floor a metre behind, which faces
  // up: some 720 of them lay 0.5 to 3 cm under the top, outnumbering the top's own 320
  // in the height histogram, and the table's plane went 1.4 cm under it and was
  // dropped. A neighbour further than a surface seen at 85 degrees spans lies across a
  // depth edge, and the table is found at its height.
  ScanParams params;
  params.noise_fit_min_turn_deg = 0;
  ScanParams before = params;
  before.surface_max_incidence_deg = 90;
  const RoomScan now = scan_room(9559u, params);
  ASSERT_FALSE(now.truth.supports.empty());
  const double table_d = now.truth.supports[0].plane.d;
  const auto at_table = [&](const RoomScan& r) {
    return std::count_if(r.supports.begin(), r.supports.end(), [&](const SupportSurface& sp) {
      return std::abs(sp.plane.d - table_d) < 0.02;
    });
  };
  EXPECT_EQ(at_table(now), 1);
  EXPECT_GE(whole_on_the_table(now), 3);
  EXPECT_EQ(at_table(scan_room(9559u, before)), 0);
}

TEST(ScannerFar, ADarkTorusFragmentsTheSizeFloorWouldDropAreJoined) {
  // Fresh rooms 9851 (session 31): a dark torus 2.13 m away keeps 182 of its pixels, in
  // four grid fragments of 9 to 11 grid pixels parted by missing depth. Each passed the
  // grid's coarse floor (half the size floor) and so was left out of the dropout join,
  // then fell under the size floor itself and was dropped: the torus was missed. Every
  // fragment under the size floor is now offered to the join (dropout_join_to_floor).
  const RoomScan r = scan_room(9851u, ScanParams{});
  const int t = find_object(
      r.scene, [](const SyntheticObject& o) { return o.kind == ShapeKind::torus && o.albedo < 1; });
  ASSERT_GE(t, 0);
  const std::optional<PhysicalObject>& got = r.of[static_cast<size_t>(t)];
  ASSERT_TRUE(got.has_value());
  ASSERT_FALSE(got->primitives.empty());
  EXPECT_EQ(got->primitives[0].kind, ShapeKind::torus);
  EXPECT_EQ(r.pieces[static_cast<size_t>(t)], 1);
  ScanParams half;
  half.dropout_join_to_floor = false;
  EXPECT_FALSE(scan_room(9851u, half).of[static_cast<size_t>(t)].has_value());
}

TEST(ScannerFar, AFurnitureSideSeenAtAGrazingAngleIsOneFaceNotAProp) {
  // Fresh room 10111 (session 31): a cabinet's side 2.4 m away seen at about 72 degrees
  // of incidence loses most of its depth, as a dark face does; its fragments, joined,
  // were fitted as an upright box 30 x 23 cm and 1.1 cm thick and reported whole. A box
  // no thicker than its points' tolerance is one face's noise, its depth not measured:
  // partial, as a box seen by one side face alone is (shape_one_face_box_partial).
  const Result<SyntheticScene> s = generate_scene(room_scene_params(10111));
  ASSERT_TRUE(s.ok()) << s.error().format();
  const SyntheticFrame f = render_scene(*s);
  // The furniture's boxes at least 20 cm long reported, and how many of them whole.
  const auto panels = [&](const ScanParams& params) {
    std::array<int, 2> n{0, 0};
    const Result<ScanResult> scan = scan_frame(f.frame, params);
    EXPECT_TRUE(scan.ok()) << scan.error().format();
    if (!scan) return n;
    for (size_t k = 0; k < scan->clusters.size(); ++k) {
      if (majority_label(f, scan->clusters[k]) != kLabelFurniture) continue;
      const PhysicalObject& o = scan->scene.objects[k];
      if (o.primitives.empty() || o.primitives[0].kind != ShapeKind::box) continue;
      const std::vector<double>& d = o.primitives[0].dimensions_m;
      if (*std::max_element(d.begin(), d.end()) < 0.2) continue;
      ++n[0];
      n[1] += !o.partial;
    }
    return n;
  };
  const std::array<int, 2> now = panels(ScanParams{});
  EXPECT_GE(now[0], 1);
  EXPECT_EQ(now[1], 0);
  ScanParams before;
  before.shape.one_face_box_partial = false;
  EXPECT_GE(panels(before)[1], 1);
}

// World scene `seed` scanned: a support lies at the table's height, at least
// `min_on_table` objects (whole ones only if `whole_only`) stand on it, and its legs and
// the wall are never reported whole.
void expect_table_without_legs_or_wall(std::uint64_t seed, int min_on_table, bool whole_only) {
  const SyntheticFrame f = world(seed);
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  const SupportSurface* table = nullptr;
  for (const SupportSurface& sp : scan->scene.supports)
    if (std::abs(sp.plane.d - f.truth.supports[0].plane.d) < 0.03) table = &sp;
  ASSERT_NE(table, nullptr) << "no support at the table's height";
  int on_table = 0;
  for (size_t k = 0; k < scan->clusters.size(); ++k) {
    const int owner = majority_label(f, scan->clusters[k]);
    const PhysicalObject& o = scan->scene.objects[k];
    if (owner >= 0 && o.support_id == table->id && !(whole_only && o.partial)) ++on_table;
    if (owner == kLabelLeg) EXPECT_TRUE(o.partial) << o.id << " is a leg reported whole";
    if (owner == kLabelWall) EXPECT_TRUE(o.partial) << o.id << " is the wall reported whole";
  }
  EXPECT_GE(on_table, min_on_table);
}

TEST(ScannerWorld, FarTableSeenFromJustAboveIsFoundAndItsLegsAreNotProps) {
  // Seed 2007: a level camera 27 cm above the table, which is 2.4 to 3.3 m away. The
  // table's top is one plane region with the wall band beside it at its height, whose
  // columns are short: the region's run of columns seen from above is the support.
  // Before, the region was dropped as a wall band and the legs were four props.
  expect_table_without_legs_or_wall(2007, 1, true);
}

TEST(ScannerWorld, BodyOfASupportHoldingObjectsIsFurniture) {
  // Seeds 2001, 2012 and 2025: a cabinet beside the table whose top is found as a support
  // with objects standing on it. Its body rises from the floor to that top: furniture,
  // not a box prop (before: one box of 1,000 to 5,000 points each). What stands on the
  // top is still found, on that support. A body with nothing on it stays an object
  // (office1's storage box, ScannerReal.OfficeFindsItsStorageBoxWithTheDefaults).
  for (std::uint64_t seed : {2001u, 2012u, 2025u}) {
    const SyntheticFrame f = world(seed);
    const Result<ScanResult> scan = scan_frame(f.frame);
    ASSERT_TRUE(scan.ok()) << scan.error().format();
    const SupportSurface* top = nullptr;
    for (const SupportSurface& sp : f.truth.supports)
      if (sp.id != "table" && sp.id != "floor") {
        // 2.5 to 3 m away a plane's offset is off by a few centimetres (the floor too).
        for (const SupportSurface& got : scan->scene.supports)
          if (std::abs(got.plane.d - sp.plane.d) < 0.05) top = &got;
      }
    ASSERT_NE(top, nullptr) << "seed " << seed << ": the cabinet's top is not a support";
    int on_top = 0;
    for (size_t k = 0; k < scan->clusters.size(); ++k) {
      const int owner = majority_label(f, scan->clusters[k]);
      // Tall furniture cut by the image border may be reported partial (it never votes).
      if (!scan->scene.objects[k].partial)
        EXPECT_NE(owner, kLabelFurniture) << "seed " << seed << " " << scan->scene.objects[k].id
                                          << " is furniture reported as an object";
      on_top += owner >= 0 && scan->scene.objects[k].support_id == top->id;
    }
    EXPECT_GE(on_top, 1) << "seed " << seed;
  }
}

TEST(ScannerWorld, TableSeenFromJustAboveItsTop) {
  // Seed 2011: a level camera 25 cm above the table, 2 m away. The top is a thin strip
  // that dropout holes (grazing incidence); the floor is the first plane. The table
  // is found as the support parallel to the floor, its objects stand on it, its legs
  // are not props and the wall seen under it is partial (its top hidden by the table).
  expect_table_without_legs_or_wall(2011, 2, false);
}

TEST(ScannerWorld, SupportSelection) {
  // A scene with the table, the floor and a second support in view.
  const SyntheticFrame f = world(2005);
  const Result<ScanResult> all = scan_frame(f.frame);
  ASSERT_TRUE(all.ok()) << all.error().format();
  ASSERT_GE(all->scene.supports.size(), 2u);
  for (const PhysicalObject& o : all->scene.objects) {
    bool known = false;
    for (const SupportSurface& s : all->scene.supports) known = known || s.id == o.support_id;
    EXPECT_TRUE(known) << o.id << " on '" << o.support_id << "'";
  }
  auto only = [&](std::string_view choice) {
    const Result<ScanParams> p = with_support_selection({}, choice);
    EXPECT_TRUE(p.ok());
    const Result<ScanResult> r = scan_frame(f.frame, *p);
    EXPECT_TRUE(r.ok()) << r.error().format();
    EXPECT_EQ(r->scene.supports.size(), 1u) << choice;
    for (const PhysicalObject& o : r->scene.objects) EXPECT_EQ(o.support_id, r->scene.supports[0].id);
    return r->scene.supports.empty() ? SupportSurface{} : r->scene.supports[0];
  };
  const SupportSurface largest = only("largest"), highest = only("highest"), nearest = only("nearest");
  for (const ScanSupport& s : all->supports) {
    EXPECT_LE(s.surface.point_count, largest.point_count);
    EXPECT_GE(s.surface.plane.d, highest.plane.d - 1e-12);
  }
  EXPECT_EQ(only("s2").id, "s2");
  const Result<ScanParams> missing = with_support_selection({}, "s9");
  ASSERT_TRUE(missing.ok());
  const Result<ScanResult> none = scan_frame(f.frame, *missing);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("no support 's9'"), std::string::npos);
  (void)nearest;
}

TEST(ScanConfig, SupportChoices) {
  const Result<ScanParams> p = parse_scan_config("supports nearest\nsupport_reach_m 2.5\n", "t.conf");
  ASSERT_TRUE(p.ok()) << p.error().format();
  EXPECT_EQ(p->supports, SupportSelection::nearest);
  EXPECT_EQ(p->support_reach_m, 2.5);
  const Result<ScanParams> id = parse_scan_config("supports s3\n", "t.conf");
  ASSERT_TRUE(id.ok());
  EXPECT_EQ(id->supports, SupportSelection::id);
  EXPECT_EQ(id->support_id, "s3");
  expect_error("\nsupports tallest\n", 2, 10, "supports must be all, nearest, highest, largest");
  expect_error("supports s0\n", 1, 10, "support id such as s2");
}

TEST(ScanConfig, PlanesAndSeenPartReachAreChecked) {
  // A pixel's prism mark holds 1 + a support's index, or around a seen part 1 + the count
  // + the index, in a byte: at most 60 planes.
  ScanParams many;
  many.max_planes = 61;
  Frame f;
  f.width = 2;
  f.height = 1;
  f.points.resize(2);
  const Result<ScanResult> r = scan_frame(f, many);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("max_planes"), std::string::npos) << r.error().message;
  const Result<ScanParams> p = parse_scan_config("seen_part_reach_m 0.25\n", "t.conf");
  ASSERT_TRUE(p.ok()) << p.error().format();
  EXPECT_EQ(p->seen_part_reach_m, 0.25);
  EXPECT_FALSE(parse_scan_config("seen_part_reach_m -1\n", "t.conf").ok());
}

TEST(ScanConfig, NoiseFitKeysAreReadAndChecked) {
  const Result<ScanParams> p =
      parse_scan_config("first_plane_noise_fit 1\nnoise_fit_min_turn_deg 1.5\n", "t.conf");
  ASSERT_TRUE(p.ok()) << p.error().format();
  EXPECT_TRUE(p->first_plane_noise_fit);
  EXPECT_EQ(p->noise_fit_min_turn_deg, 1.5);
  const Result<ScanParams> bad = parse_scan_config("\nnoise_fit_min_turn_deg 120\n", "t.conf");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().format().find("t.conf:2:"), std::string::npos) << bad.error().format();
}

TEST(ScanConfig, SurfaceIncidenceKeyIsReadAndChecked) {
  const Result<ScanParams> p = parse_scan_config("surface_max_incidence_deg 80\n", "t.conf");
  ASSERT_TRUE(p.ok()) << p.error().format();
  EXPECT_EQ(p->surface_max_incidence_deg, 80);
  EXPECT_EQ(ScanParams{}.surface_max_incidence_deg, 85);
  const Result<ScanParams> bad = parse_scan_config("\n\nsurface_max_incidence_deg -3\n", "t.conf");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().format().find("t.conf:3:"), std::string::npos) << bad.error().format();
}

TEST(ScannerWorld, RecordingsWallBandBelowTheTableIsNoFloor) {
  // samples/recordings/tabletop: a table seen from 62 cm above it and the wall behind.
  // A height band 32 cm below the table cuts the wall where depth noise tilts a few
  // normals up; no column of it runs away from the camera, so it is no support (taken
  // for the floor, it renumbered the recording's objects and made the wall's strip a
  // 73,330-point object on it).
  Result<Frame> f = read_pcd(std::filesystem::path(ANNEX_SOURCE_DIR) / "samples/recordings/tabletop/frame_0000.pcd");
  ASSERT_TRUE(f.ok()) << f.error().format();
  const Result<ScanResult> scan = scan_frame(*f);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  ASSERT_EQ(scan->supports.size(), 1u);
  EXPECT_NEAR(scan->supports[0].surface.plane.d, 0.623, 0.005);
  // The cylinder, the wall's strip (partial), the roll of tape, the ball: the ids the
  // recording's README, the CLI and the binding tests name.
  ASSERT_EQ(scan->scene.objects.size(), 4u);
  EXPECT_EQ(scan->scene.objects[0].primitives.at(0).kind, ShapeKind::cylinder);
  EXPECT_TRUE(scan->scene.objects[1].partial);
  EXPECT_EQ(scan->scene.objects[2].primitives.at(0).kind, ShapeKind::torus);
  EXPECT_EQ(scan->scene.objects[3].primitives.at(0).kind, ShapeKind::sphere);
}

TEST(ScannerWorld, LegsSeenFromJustAboveTheTableAreNoProps) {
  // Held-out seeds 5005, 5035 and 5114 (never tuned on): a level camera 25 to 30 cm
  // above a table 2.4 to 3.3 m away sees its legs from the floor up to the band's top,
  // three to five grid pixels wide, while the table top is found in part or not at all.
  // The legs rose through the band's top by fewer joins than a wider surface needs, and
  // nothing above them was a support's region: five legs reported as cylinders and
  // boxes of 0.55 to 0.59 m. A member standing on the floor narrower than
  // min_stand_ratio of its height cannot stand free: none is a prop now.
  expect_none_whole({5005, 5035, 5114}, kLabelLeg, "a table leg");
}

TEST(ScannerWorld, ANarrowObjectOnACabinetIsNotALeg) {
  // Held-out seed 5102: a cylinder stands on a cabinet whose top is no support found, so
  // it belongs to the floor's band and its top crosses the band's top, cut by the image
  // border to a strip 9 cm wide. It is narrow and runs on above the band like a leg, but
  // its lowest point is the cabinet's top, 47 cm up: it does not reach down to its
  // support, so it is kept (partial).
  const SyntheticFrame f = world(5102);
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_TRUE(scan.ok()) << scan.error().format();
  int on_cabinet = -1;
  for (size_t t = 0; t < f.truth.objects.size(); ++t)
    if (f.truth.objects[t].support_id != "table" &&
        f.truth.objects[t].primitives[0].kind == ShapeKind::cylinder)
      on_cabinet = static_cast<int>(t);
  ASSERT_GE(on_cabinet, 0);
  bool found = false;
  for (const ScanCluster& c : scan->clusters) found = found || majority_label(f, c) == on_cabinet;
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace annex
