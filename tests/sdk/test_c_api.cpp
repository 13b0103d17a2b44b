// The C API (annex/annex.h) through libannex_c as a program would call it: versions and
// the ABI check, specs with line:column errors, frames from points and from depth
// images, scans, matches with explanations, sessions with two-call arrays and events,
// parameter checks, NULL arguments, the Unity pose. Synthetic scenes come from the C++
// runtime (linked statically beside libannex_c, whose C++ symbols are hidden).
#include "annex/annex.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/formats/haptic_format.h"
#include "annex/formats/scene_format.h"
#include "annex/runtime/synthetic_scene.h"

namespace {

std::string source_path(const std::string& rel) { return std::string(ANNEX_SOURCE_DIR) + "/" + rel; }

// Owns an annex_error for one call and prints it on failure.
struct Err {
  annex_error* e = nullptr;
  ~Err() { annex_error_destroy(e); }
  annex_error** operator&() {
    annex_error_destroy(e);
    e = nullptr;
    return &e;
  }
  std::string message() const { return e ? annex_error_message(e) : "(no error)"; }
};

annex::SyntheticScene make_scene(std::uint64_t seed, int objects) {
  annex::SyntheticSceneParams p;
  p.seed = seed;
  p.object_count = objects;
  p.kinds = {annex::ShapeKind::cylinder, annex::ShapeKind::sphere, annex::ShapeKind::box};
  annex::Result<annex::SyntheticScene> s = annex::generate_scene(p);
  EXPECT_TRUE(s.ok()) << s.error().format();
  return s ? *s : annex::SyntheticScene{};
}

// One virtual object per synthetic object, of its shape and size, as spec text.
std::string spec_text_for(const annex::SyntheticScene& scene) {
  annex::HapticSpec spec;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    annex::VirtualObject v;
    v.name = "v" + std::to_string(i);
    annex::Primitive p = annex::make_primitive(scene.objects[i].kind, "body");
    for (size_t d = 0; d < p.dimensions.size(); ++d)
      p.dimensions[d].value_m = scene.objects[i].dimensions_m[d];
    v.primitives.push_back(p);
    spec.objects.push_back(v);
  }
  return annex::write_haptic(spec);
}

// spec_text_for(scene) loaded through the C API; null, with a failure, on an error.
annex_spec* spec_for(const annex::SyntheticScene& scene) {
  Err err;
  annex_spec* spec = nullptr;
  EXPECT_EQ(annex_spec_load_text(spec_text_for(scene).c_str(), "synthetic.haptic", &spec, &err),
            ANNEX_OK)
      << err.message();
  return spec;
}

annex_session_params default_session_params() {
  annex_session_params p;
  annex_session_params_init(&p);
  return p;
}

std::vector<float> xyz_of(const annex::Frame& f) {
  std::vector<float> xyz;
  for (const annex::PointXYZRGB& p : f.points) xyz.insert(xyz.end(), {p.x, p.y, p.z});
  return xyz;
}

annex_frame* frame_of(const annex::Frame& f) {
  const std::vector<float> xyz = xyz_of(f);
  annex_frame* out = nullptr;
  Err err;
  EXPECT_EQ(annex_frame_from_points(xyz.data(), f.width, f.height, nullptr, &out, &err), ANNEX_OK)
      << err.message();
  return out;
}

// A 22 x 16 x 8 cm carton on a table seen from above, and a keypad panel of its top's size.
annex::SyntheticScene carton_on_table() {
  annex::SyntheticScene scene;
  scene.camera_position = {0, -0.75, 0.7};
  scene.objects.push_back(annex::resting_object(annex::ShapeKind::box, {0.22, 0.16, 0.08}, 0, 0));
  return scene;
}
constexpr const char* kKeypadSpec =
    "annex-haptic 1\nobject keypad\n  primitive face plane\n"
    "    size_x 0.22\n    size_y 0.16\n  end\nend\n";

TEST(CApi, VersionAndAbi) {
  EXPECT_STREQ(annex_version_string(), ANNEX_VERSION_STRING);
  EXPECT_STREQ(annex_version_string(), ANNEX_EXPECTED_VERSION);  // project(VERSION)
  EXPECT_EQ(annex_abi_version(), ANNEX_ABI_VERSION);
  Err err;
  EXPECT_EQ(annex_check_abi(ANNEX_ABI_VERSION, &err), ANNEX_OK);
  EXPECT_EQ(err.e, nullptr);
  EXPECT_EQ(annex_check_abi(ANNEX_ABI_VERSION + 1, &err), ANNEX_ABI_MISMATCH);
  ASSERT_NE(err.e, nullptr);
  EXPECT_EQ(annex_error_status(err.e), ANNEX_ABI_MISMATCH);
  EXPECT_NE(err.message().find("ABI " + std::to_string(ANNEX_ABI_VERSION + 1)), std::string::npos)
      << err.message();
  EXPECT_STREQ(annex_status_name(ANNEX_PARSE_ERROR), "ANNEX_PARSE_ERROR");
}

TEST(CApi, SpecsLoadWithLineAndColumnErrors) {
  Err err;
  annex_spec* spec = nullptr;
  ASSERT_EQ(annex_spec_load_file(source_path("samples/specs/study.haptic").c_str(), &spec, &err),
            ANNEX_OK)
      << err.message();
  ASSERT_GE(annex_spec_object_count(spec), 3u);
  EXPECT_NE(annex_spec_object_name(spec, 0), nullptr);
  EXPECT_EQ(annex_spec_object_name(spec, 1000), nullptr);
  annex_spec_destroy(spec);

  // "priority" wants a number: line 4, the column of the bad token.
  const char* bad =
      "annex-haptic 1\n"
      "object cup\n"
      "  primitive body cylinder\n"
      "    priority heavy\n"
      "  end\n"
      "end\n";
  spec = nullptr;
  EXPECT_EQ(annex_spec_load_text(bad, "cup.haptic", &spec, &err), ANNEX_PARSE_ERROR);
  EXPECT_EQ(spec, nullptr);
  ASSERT_NE(err.e, nullptr);
  EXPECT_STREQ(annex_error_origin(err.e), "cup.haptic");
  EXPECT_EQ(annex_error_line(err.e), 4);
  EXPECT_GT(annex_error_column(err.e), 0);
  EXPECT_EQ(err.message().rfind("cup.haptic:4:", 0), 0u) << err.message();
  EXPECT_EQ(annex_spec_validate_text(bad, nullptr, &err), ANNEX_PARSE_ERROR);
  EXPECT_EQ(err.message().rfind("<text>:4:", 0), 0u) << err.message();

  EXPECT_EQ(annex_spec_load_file("/no/such/file.haptic", &spec, &err), ANNEX_IO_ERROR);
  EXPECT_NE(err.message().find("/no/such/file.haptic"), std::string::npos) << err.message();
  // NULL arguments are errors, never crashes; a NULL error pointer is allowed.
  EXPECT_EQ(annex_spec_load_text(nullptr, nullptr, &spec, &err), ANNEX_INVALID_ARGUMENT);
  EXPECT_NE(err.message().find("text must not be NULL"), std::string::npos);
  EXPECT_EQ(annex_spec_load_text(bad, nullptr, &spec, nullptr), ANNEX_PARSE_ERROR);
}

// Each virtual object's mesh scale, as the spec gives it (1 when it does not).
TEST(CApi, SpecObjectsGiveTheirModelScale) {
  Err err;
  annex_spec* spec = nullptr;
  ASSERT_EQ(annex_spec_load_text("annex-haptic 1\n"
                                 "object duck\n  mesh duck.dae\n  model_scale 0.078\n"
                                 "  primitive body sphere\n    radius 0.05\n  end\nend\n"
                                 "object cup\n  primitive body cylinder\n    radius 0.04\n"
                                 "    height 0.1\n  end\nend\n",
                                 "units.haptic", &spec, &err),
            ANNEX_OK)
      << err.message();
  EXPECT_DOUBLE_EQ(annex_spec_object_model_scale(spec, 0), 0.078);
  EXPECT_DOUBLE_EQ(annex_spec_object_model_scale(spec, 1), 1.0);
  EXPECT_EQ(annex_spec_object_model_scale(spec, 2), 0.0);  // out of range
  EXPECT_EQ(annex_spec_object_model_scale(nullptr, 0), 0.0);
  annex_spec_destroy(spec);
}

// A scene with a tin standing on a box: the object it stands on, "" on the support.
TEST(CApi, SceneObjectsSayWhatTheyStandOn) {
  annex::PhysicalScene scene;
  scene.supports.push_back({"s1", annex::Plane{{0, -1, 0}, 0.5}, 1000});
  scene.support = scene.supports[0].plane;
  for (const char* id : {"p1", "p2"}) {
    annex::PhysicalObject o;
    o.id = id;
    o.support_id = "s1";
    annex::PhysicalPrimitive p;
    p.kind = annex::ShapeKind::box;
    p.dimensions_m = {0.2, 0.15, 0.1};
    p.center = {0, 0.45, 1.0};
    o.primitives.push_back(p);
    scene.objects.push_back(o);
  }
  scene.objects[1].on_object = "p1";
  const std::string path = testing::TempDir() + "/stacked.scene";
  ASSERT_TRUE(annex::write_scene_file(path, scene).ok());
  Err err;
  annex_scene* loaded = nullptr;
  ASSERT_EQ(annex_scene_load_file(path.c_str(), &loaded, &err), ANNEX_OK) << err.message();
  ASSERT_EQ(annex_scene_object_count(loaded), 2u);
  EXPECT_STREQ(annex_scene_object_on(loaded, 0), "");
  EXPECT_STREQ(annex_scene_object_on(loaded, 1), "p1");
  EXPECT_EQ(annex_scene_object_on(loaded, 2), nullptr);
  EXPECT_EQ(annex_scene_object_on(nullptr, 0), nullptr);
  annex_primitive prim;
  ASSERT_EQ(annex_scene_primitive(loaded, 1, 0, &prim, &err), ANNEX_OK);
  EXPECT_EQ(prim.shape, ANNEX_SHAPE_BOX);
  annex_scene_destroy(loaded);
}

// A session whose spec has a virtual panel lays it on a box's top, reported with the
// props: its pose is the face's centre, its normal the box's up.
TEST(CApi, SessionLaysAPanelOnABoxTop) {
  const annex::SyntheticScene scene = carton_on_table();
  Err err;
  annex_spec* spec = nullptr;
  ASSERT_EQ(annex_spec_load_text(kKeypadSpec, "keypad.haptic", &spec, &err),
            ANNEX_OK)
      << err.message();
  annex_session_params params;
  annex_session_params_init(&params);
  params.background_scan = 0;
  annex_session* session = nullptr;
  ASSERT_EQ(annex_session_create(spec, &params, &session, &err), ANNEX_OK) << err.message();
  annex_spec_destroy(spec);
  const annex::SyntheticFrame f = annex::render_scene(scene, {}, 0);
  annex_frame* frame = frame_of(f.frame);
  ASSERT_EQ(annex_session_push(session, frame, &err), ANNEX_OK) << err.message();
  annex_frame_destroy(frame);
  size_t count = 0;
  annex_object objects[2];
  ASSERT_EQ(annex_session_objects(session, objects, 2, &count, &err), ANNEX_OK) << err.message();
  ASSERT_EQ(count, 1u);
  EXPECT_STREQ(objects[0].virtual_name, "keypad");
  EXPECT_STREQ(objects[0].physical_id, "p1.top");
  ASSERT_TRUE(f.truth.support.has_value());
  const annex::Vec3 up = annex::normalized(f.truth.support->normal);
  const annex::PhysicalPrimitive& box = f.truth.objects.at(0).primitives.at(0);
  const annex::Vec3 top = box.center + up * (box.dimensions_m[2] / 2);
  const annex::Vec3 at{objects[0].position[0], objects[0].position[1], objects[0].position[2]};
  EXPECT_LT(annex::norm(at - top), 0.02);
  const annex::Quat q{objects[0].rotation[0], objects[0].rotation[1], objects[0].rotation[2],
                      objects[0].rotation[3]};
  EXPECT_GT(annex::dot(annex::rotate(q, {0, 0, 1}), up), 0.97);  // the panel's normal
  EXPECT_NEAR(objects[0].scale[0], 1.0, 0.15);
  EXPECT_NEAR(objects[0].scale[1], 1.0, 0.15);
  annex_session_destroy(session);
}

// A scan's flat surfaces come apart from its objects: annex_scene_with_surfaces appends
// them (the box's top where the generator put it, each one plane with its size_x side),
// and a keypad spec matches the box's top only through that scene.
TEST(CApi, ScanReportsSurfacesForPanels) {
  const annex::SyntheticScene scene = carton_on_table();
  const annex::SyntheticFrame f = annex::render_scene(scene, {}, 0);
  Err err;
  annex_scanner* scanner = nullptr;
  ASSERT_EQ(annex_scanner_create(nullptr, &scanner, &err), ANNEX_OK) << err.message();
  annex_frame* frame = frame_of(f.frame);
  annex_scene* scanned = nullptr;
  ASSERT_EQ(annex_scan(scanner, frame, &scanned, &err), ANNEX_OK) << err.message();
  annex_frame_destroy(frame);
  annex_scanner_destroy(scanner);

  const size_t objects = annex_scene_object_count(scanned);
  const size_t surfaces = annex_scene_surface_count(scanned);
  ASSERT_GE(surfaces, 1u);
  annex_scene* both = nullptr;
  ASSERT_EQ(annex_scene_with_surfaces(scanned, &both, &err), ANNEX_OK) << err.message();
  ASSERT_EQ(annex_scene_object_count(both), objects + surfaces);
  EXPECT_EQ(annex_scene_surface_count(both), 0u);

  ASSERT_TRUE(f.truth.support.has_value());
  const annex::Vec3 up = annex::normalized(f.truth.support->normal);
  const annex::PhysicalPrimitive& box = f.truth.objects.at(0).primitives.at(0);
  const annex::Vec3 top = box.center + up * (box.dimensions_m[2] / 2);
  bool found_top = false;
  for (size_t i = objects; i < objects + surfaces; ++i) {
    annex_physical_object o;
    ASSERT_EQ(annex_scene_object(both, i, &o, &err), ANNEX_OK) << err.message();
    ASSERT_EQ(o.primitive_count, 1) << o.id;
    annex_primitive p;
    ASSERT_EQ(annex_scene_primitive(both, i, 0, &p, &err), ANNEX_OK) << err.message();
    EXPECT_EQ(p.shape, ANNEX_SHAPE_PLANE) << o.id;
    EXPECT_STREQ(p.shape_name, "plane");
    ASSERT_EQ(p.dimension_count, 2);
    EXPECT_STREQ(p.dimension_names[0], "size_x");
    EXPECT_GE(p.dimensions_m[0], p.dimensions_m[1]) << o.id;
    const annex::Vec3 normal{p.axis[0], p.axis[1], p.axis[2]};
    double x[3];
    ASSERT_EQ(annex_scene_primitive_x_axis(both, i, 0, x), 1) << o.id;
    const annex::Vec3 x_axis{x[0], x[1], x[2]};
    EXPECT_NEAR(annex::norm(x_axis), 1.0, 1e-6) << o.id;
    EXPECT_LT(std::abs(annex::dot(x_axis, normal)), 1e-6) << o.id;
    if (std::string(o.id) != "p1.top") continue;
    found_top = true;
    const annex::Vec3 c{p.center[0], p.center[1], p.center[2]};
    EXPECT_LT(annex::norm(c - top), 0.02);
    EXPECT_GT(annex::dot(normal, up), 0.97);
    EXPECT_NEAR(p.dimensions_m[0], 0.22, 0.03);
    EXPECT_NEAR(p.dimensions_m[1], 0.16, 0.03);
  }
  EXPECT_TRUE(found_top);
  // The box itself is no plane: its primitive has no x axis to give.
  ASSERT_GE(objects, 1u);
  double unused[3];
  EXPECT_EQ(annex_scene_primitive_x_axis(both, 0, 0, unused), 0);
  EXPECT_EQ(annex_scene_primitive_x_axis(both, objects + surfaces, 0, unused), 0);

  annex_spec* spec = nullptr;
  ASSERT_EQ(annex_spec_load_text(kKeypadSpec, "keypad.haptic", &spec, &err),
            ANNEX_OK)
      << err.message();
  auto matched = [&](const annex_scene* against) {
    annex_match* match = nullptr;
    EXPECT_EQ(annex_match_objects(spec, against, &match, &err), ANNEX_OK) << err.message();
    annex_match_entry e{};
    EXPECT_EQ(annex_match_entry_at(match, 0, &e, &err), ANNEX_OK) << err.message();
    const std::string id = e.physical_id ? e.physical_id : "(virtual-only)";
    annex_match_destroy(match);
    return id;
  };
  EXPECT_EQ(matched(both), "p1.top");
  EXPECT_EQ(matched(scanned), "(virtual-only)");  // the objects alone hold no plane
  annex_spec_destroy(spec);

  // A scene read from a file has no surfaces; NULL arguments are errors, not crashes.
  annex_scene* loaded = nullptr;
  ASSERT_EQ(annex_scene_load_file(source_path("samples/figure3/figure3.scene").c_str(), &loaded,
                                  &err),
            ANNEX_OK)
      << err.message();
  EXPECT_EQ(annex_scene_surface_count(loaded), 0u);
  EXPECT_EQ(annex_scene_surface_count(nullptr), 0u);
  annex_scene* none = nullptr;
  EXPECT_EQ(annex_scene_with_surfaces(nullptr, &none, &err), ANNEX_INVALID_ARGUMENT);
  EXPECT_EQ(none, nullptr);
  EXPECT_EQ(annex_scene_with_surfaces(loaded, nullptr, &err), ANNEX_INVALID_ARGUMENT);
  annex_scene_destroy(loaded);
  annex_scene_destroy(both);
  annex_scene_destroy(scanned);
}

// Scanning an organized cloud and the same scene as a depth image in millimetres and in
// 100 um units find the same objects where the generator put them.
TEST(CApi, ScansPointsAndDepthImages) {
  const annex::SyntheticScene scene = make_scene(41, 3);
  const annex::SyntheticFrame f = annex::render_scene(scene);
  annex_scanner* scanner = nullptr;
  Err err;
  ASSERT_EQ(annex_scanner_create(nullptr, &scanner, &err), ANNEX_OK) << err.message();

  auto check_scene = [&](annex_frame* frame, const char* what) {
    annex_scene* found = nullptr;
    ASSERT_EQ(annex_scan(scanner, frame, &found, &err), ANNEX_OK) << what << ": " << err.message();
    // The three objects have a shape; the wall behind the table, standing on the floor
    // seen beyond it (a second support) and cut by the image's top, has none (unknown).
    size_t shaped = 0;
    for (size_t i = 0; i < annex_scene_object_count(found); ++i) {
      annex_physical_object o;
      ASSERT_EQ(annex_scene_object(found, i, &o, &err), ANNEX_OK);
      shaped += o.primitive_count >= 1;
    }
    ASSERT_EQ(shaped, 3u) << what;
    double n[3], d;
    EXPECT_EQ(annex_scene_support(found, n, &d), 1);
    for (const annex::PhysicalObject& truth : f.truth.objects) {
      double best = 1e9;
      for (size_t i = 0; i < annex_scene_object_count(found); ++i) {
        annex_physical_object o;
        ASSERT_EQ(annex_scene_object(found, i, &o, &err), ANNEX_OK);
        if (o.primitive_count < 1) continue;
        annex_primitive p;
        ASSERT_EQ(annex_scene_primitive(found, i, 0, &p, &err), ANNEX_OK);
        if (p.shape != static_cast<annex_shape>(truth.primitives[0].kind)) continue;
        EXPECT_EQ(p.dimension_count, annex::dimension_count(truth.primitives[0].kind));
        const annex::Vec3 c{p.center[0], p.center[1], p.center[2]};
        best = std::min(best, annex::norm(c - truth.primitives[0].center));
      }
      EXPECT_LT(best, 0.02) << what << ": " << annex::shape_name(truth.primitives[0].kind);
    }
    annex_scene_destroy(found);
  };

  annex_frame* points = frame_of(f.frame);
  ASSERT_NE(points, nullptr);
  EXPECT_EQ(annex_frame_width(points), f.frame.width);
  size_t n = 0;
  ASSERT_EQ(annex_frame_points(points, nullptr, 0, &n, &err), ANNEX_OK);
  EXPECT_EQ(n, f.frame.points.size() * 3);
  check_scene(points, "points");
  annex_frame_destroy(points);

  annex_intrinsics k;
  annex_intrinsics_init(&k);  // the generator's default camera
  for (const double scale : {0.001, 0.0001}) {
    std::vector<std::uint16_t> depth(f.frame.points.size(), 0);
    for (size_t i = 0; i < depth.size(); ++i)
      if (std::isfinite(f.frame.points[i].z))
        depth[i] = static_cast<std::uint16_t>(std::lround(f.frame.points[i].z / scale));
    annex_frame* frame = nullptr;
    ASSERT_EQ(annex_frame_from_depth(depth.data(), f.frame.width, f.frame.height, &k, scale,
                                     nullptr, &frame, &err),
              ANNEX_OK)
        << err.message();
    check_scene(frame, scale == 0.001 ? "depth mm" : "depth 100um");
    annex_frame_destroy(frame);
  }

  // Bad depth input: a scale of 0, intrinsics of another size.
  std::vector<std::uint16_t> depth(16, 1000);
  annex_frame* frame = nullptr;
  EXPECT_EQ(annex_frame_from_depth(depth.data(), 4, 4, &k, 0.0, nullptr, &frame, &err),
            ANNEX_INVALID_ARGUMENT);
  EXPECT_NE(err.message().find("intrinsics are for 640 x 480"), std::string::npos) << err.message();
  k.width = 4;
  k.height = 4;
  k.cx = k.cy = 1.5;
  EXPECT_EQ(annex_frame_from_depth(depth.data(), 4, 4, &k, 0.0, nullptr, &frame, &err),
            ANNEX_INVALID_ARGUMENT);
  EXPECT_NE(err.message().find("depth_scale_m must be greater than 0"), std::string::npos)
      << err.message();
  // A flat 4x4 frame holds no support of enough points: a scan failure, not a crash.
  ASSERT_EQ(annex_frame_from_depth(depth.data(), 4, 4, &k, 0.001, nullptr, &frame, &err), ANNEX_OK);
  annex_scene* none = nullptr;
  EXPECT_EQ(annex_scan(scanner, frame, &none, &err), ANNEX_SCAN_FAILED);
  EXPECT_EQ(none, nullptr);
  annex_frame_destroy(frame);
  annex_scanner_destroy(scanner);
}

TEST(CApi, ScanParamsAreCheckedAtCreation) {
  annex_scan_params p;
  annex_scan_params_init(&p);
  p.max_height_m = -0.5;
  annex_scanner* scanner = nullptr;
  Err err;
  EXPECT_EQ(annex_scanner_create(&p, &scanner, &err), ANNEX_INVALID_ARGUMENT);
  EXPECT_EQ(scanner, nullptr);
  EXPECT_NE(err.message().find("annex_scan_params.max_height_m must be greater than 0, got -0.5"),
            std::string::npos)
      << err.message();
  annex_scan_params_init(&p);
  p.threads = 0;
  EXPECT_EQ(annex_scanner_create(&p, &scanner, &err), ANNEX_INVALID_ARGUMENT);
  EXPECT_NE(err.message().find("threads"), std::string::npos) << err.message();
  EXPECT_EQ(annex_scanner_create_from_config(source_path("samples/config/room.conf").c_str(),
                                             &scanner, &err),
            ANNEX_OK)
      << err.message();
  annex_scanner_destroy(scanner);
}

// The paper's Figure 3 through the C API: the matches the CLI prints, and explanations.
TEST(CApi, MatchesFigure3WithExplanations) {
  Err err;
  annex_spec* spec = nullptr;
  annex_scene* scene = nullptr;
  ASSERT_EQ(annex_spec_load_file(source_path("samples/figure3/figure3.haptic").c_str(), &spec, &err),
            ANNEX_OK)
      << err.message();
  ASSERT_EQ(annex_scene_load_file(source_path("samples/figure3/figure3.scene").c_str(), &scene, &err),
            ANNEX_OK)
      << err.message();
  annex_match* match = nullptr;
  ASSERT_EQ(annex_match_objects(spec, scene, &match, &err), ANNEX_OK) << err.message();
  annex_spec_destroy(spec);  // the match keeps its own names
  std::map<std::string, std::pair<std::string, double>> got;
  ASSERT_EQ(annex_match_count(match), 3u);
  for (size_t i = 0; i < annex_match_count(match); ++i) {
    annex_match_entry e;
    ASSERT_EQ(annex_match_entry_at(match, i, &e, &err), ANNEX_OK);
    got[e.virtual_name] = {e.physical_id ? e.physical_id : "-", e.vote};
  }
  EXPECT_EQ(got["v1"].first, "p2");
  EXPECT_NEAR(got["v1"].second, 34.0, 0.005);
  EXPECT_EQ(got["v2"].first, "p3");
  EXPECT_NEAR(got["v2"].second, 65.0, 0.005);
  EXPECT_EQ(got["v3"].first, "p1");
  EXPECT_NEAR(got["v3"].second, 48.0, 0.005);
  const char* why = annex_match_explanation(match, 0, 1);
  ASSERT_NE(why, nullptr);
  EXPECT_NE(std::string(why).find("v1 x p2"), std::string::npos) << why;
  EXPECT_EQ(annex_match_explanation(match, 0, 99), nullptr);
  EXPECT_NE(std::string(annex_match_report(match)).find("v3"), std::string::npos);
  annex_match_entry e;
  EXPECT_EQ(annex_match_entry_at(match, 3, &e, &err), ANNEX_INVALID_ARGUMENT);
  annex_match_destroy(match);
  annex_scene_destroy(scene);
}

// A background session on a still synthetic scene: no push waits for the scan, the
// matches appear one push later, objects are read with two calls, poses lie on the props.
TEST(CApi, SessionAnnexesTracksAndReportsEvents) {
  const annex::SyntheticScene scene = make_scene(31, 3);
  Err err;
  annex_spec* spec = spec_for(scene);
  ASSERT_NE(spec, nullptr);
  annex_session_params params = default_session_params();
  EXPECT_EQ(params.background_scan, 1);
  params.scan_every = 4;
  params.release_after_frames = 3;
  params.has_intrinsics = 1;  // the generator's camera, known
  annex_session* session = nullptr;
  ASSERT_EQ(annex_session_create(spec, &params, &session, &err), ANNEX_OK) << err.message();
  annex_spec_destroy(spec);  // the session keeps a copy

  size_t count = 99;
  annex_frame_info info;
  EXPECT_EQ(annex_session_frame_info(session, &info, &err), ANNEX_INVALID_ARGUMENT);
  std::map<std::string, int> annexed_at, lost_at, released_at;
  std::map<std::string, std::string> prop_of;
  int first_objects = -1;
  // Until the first scan applies, frame 0 is pushed every 5 ms: how many pushes the
  // background scan takes depends on the machine's load (and a sanitizer), not on the
  // session. Then the 32 frames of the sequence; push numbers count from the first push.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(180);
  int warmup = 0;
  const auto push = [&](const annex::Frame& f) {
    annex_frame* frame = frame_of(f);
    const annex_status st = annex_session_push(session, frame, &err);
    annex_frame_destroy(frame);
    return st;
  };
  const annex::Frame still = annex::render_scene(scene, {}, 0).frame;
  for (;; ++warmup) {
    ASSERT_EQ(push(still), ANNEX_OK) << err.message();
    ASSERT_EQ(annex_session_objects(session, nullptr, 0, &count, &err), ANNEX_OK);
    if (warmup == 0) EXPECT_EQ(count, 0u) << "the first scan is still running or just applied";
    if (count > 0) break;
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "no scan applied in 3 minutes";
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  first_objects = warmup;
  ASSERT_EQ(annex_session_events(session, nullptr, 0, &count, &err), ANNEX_OK);
  std::vector<annex_event> first_events(count);
  ASSERT_EQ(annex_session_events(session, first_events.data(), first_events.size(), &count, &err),
            ANNEX_OK);
  for (const annex_event& e : first_events) {
    EXPECT_EQ(e.kind, ANNEX_EVENT_ANNEXED);
    EXPECT_EQ(e.frame, warmup);
    annexed_at.emplace(e.virtual_name, warmup);
  }
  const int hidden_from = 14;  // v0's prop disappears from this frame of the sequence on
  for (int k = 0; k < 32; ++k) {
    const int n = warmup + 1 + k;  // the push's number
    annex::SyntheticFrame f = annex::render_scene(scene, {}, k);
    if (k >= hidden_from) {
      // Hide the prop of v0 (the scene's object 0).
      for (size_t i = 0; i < f.labels.size(); ++i)
        if (f.labels[i] == 0) f.frame.points[i].z = std::numeric_limits<float>::quiet_NaN();
    }
    ASSERT_EQ(push(f.frame), ANNEX_OK) << err.message();
    ASSERT_EQ(annex_session_frame_info(session, &info, &err), ANNEX_OK);
    EXPECT_EQ(info.frame, n);
    if (info.scan_applied) {
      EXPECT_LT(info.scan_frame, n) << "a background scan applies a push later";
      EXPECT_EQ(info.scan_failed, 0) << (info.scan_error ? info.scan_error : "");
    }
    ASSERT_EQ(annex_session_objects(session, nullptr, 0, &count, &err), ANNEX_OK);
    std::vector<annex_object> objects(count);
    if (count > 1) {
      size_t small = 0;
      EXPECT_EQ(annex_session_objects(session, objects.data(), 1, &small, &err),
                ANNEX_BUFFER_TOO_SMALL);
      EXPECT_EQ(small, count);
    }
    ASSERT_EQ(annex_session_objects(session, objects.data(), objects.size(), &count, &err),
              ANNEX_OK);
    for (const annex_object& o : objects) {
      const std::string name = o.virtual_name;
      if (!prop_of.count(name)) prop_of[name] = o.physical_id;
      if (name != "v0" || k < hidden_from) {
        EXPECT_EQ(prop_of[name], o.physical_id) << name << " push " << k;
        EXPECT_EQ(o.state, ANNEX_STATE_TRACKING) << name << " push " << k;
        // The model's origin is the primitive's centre: on the prop.
        const int truth = std::stoi(name.substr(1));
        const annex::Vec3 c = annex::table_to_camera_point(
            scene, annex::scene_at_frame(scene, k).objects[static_cast<size_t>(truth)].center);
        const annex::Vec3 p{o.position[0], o.position[1], o.position[2]};
        EXPECT_LT(annex::norm(p - c), 0.015) << name << " push " << k;
        const double qn = std::sqrt(o.rotation[0] * o.rotation[0] + o.rotation[1] * o.rotation[1] +
                                    o.rotation[2] * o.rotation[2] + o.rotation[3] * o.rotation[3]);
        EXPECT_NEAR(qn, 1.0, 1e-9);
        for (double s : o.scale) EXPECT_NEAR(s, 1.0, 0.3) << name;  // made from the props' sizes
      }
    }
    ASSERT_EQ(annex_session_events(session, nullptr, 0, &count, &err), ANNEX_OK);
    std::vector<annex_event> events(count);
    ASSERT_EQ(annex_session_events(session, events.data(), events.size(), &count, &err), ANNEX_OK);
    for (const annex_event& e : events) {
      EXPECT_EQ(e.frame, n);
      const std::string name = e.virtual_name;
      auto& at = e.kind == ANNEX_EVENT_ANNEXED ? annexed_at
                 : e.kind == ANNEX_EVENT_LOST  ? lost_at
                                               : released_at;
      if (!at.count(name)) at[name] = k;
    }
  }
  // Annexed together, one push after the first scan's frame at the earliest.
  EXPECT_GE(first_objects, 1);
  ASSERT_EQ(annexed_at.size(), 3u);
  for (const auto& [name, k] : annexed_at) EXPECT_EQ(k, first_objects) << name;
  // v0's prop went: lost within the tracker's failure budget, then released.
  ASSERT_TRUE(lost_at.count("v0"));
  EXPECT_GT(lost_at["v0"], hidden_from);
  ASSERT_TRUE(released_at.count("v0"));
  EXPECT_GT(released_at["v0"], lost_at["v0"]);
  EXPECT_EQ(lost_at.size(), 1u);
  EXPECT_EQ(released_at.size(), 1u);
  annex_session_destroy(session);
}

TEST(CApi, SessionParamsAreCheckedAtCreation) {
  Err err;
  annex_spec* spec = nullptr;
  ASSERT_EQ(annex_spec_load_file(source_path("samples/specs/study.haptic").c_str(), &spec, &err),
            ANNEX_OK);
  annex_session_params params;
  annex_session* session = nullptr;
  struct Case {
    void (*set)(annex_session_params&);
    const char* field;
  };
  const Case cases[] = {
      {[](annex_session_params& p) { p.scan.min_height_m = -0.01; }, "scan.min_height_m"},
      {[](annex_session_params& p) { p.scan_every = 0; }, "scan_every"},
      {[](annex_session_params& p) { p.threads = -2; }, "threads"},
      {[](annex_session_params& p) { p.release_after_frames = 0; }, "release_after_frames"},
      {[](annex_session_params& p) {
         p.has_intrinsics = 1;
         p.intrinsics.fx = -525;
       },
       "camera.fx"},
      {[](annex_session_params& p) { p.scan.max_depth_m = std::nan(""); }, "scan.max_depth_m"},
  };
  for (const Case& c : cases) {
    annex_session_params_init(&params);
    c.set(params);
    EXPECT_EQ(annex_session_create(spec, &params, &session, &err), ANNEX_INVALID_ARGUMENT) << c.field;
    EXPECT_EQ(session, nullptr);
    EXPECT_NE(err.message().find(std::string("SessionParams.") + c.field), std::string::npos)
        << err.message();
  }
  EXPECT_EQ(annex_session_create(nullptr, nullptr, &session, &err), ANNEX_INVALID_ARGUMENT);
  EXPECT_EQ(annex_session_push(nullptr, nullptr, &err), ANNEX_INVALID_ARGUMENT);
  ASSERT_EQ(annex_session_create(spec, nullptr, &session, &err), ANNEX_OK) << err.message();
  EXPECT_EQ(annex_session_push(session, nullptr, &err), ANNEX_INVALID_ARGUMENT);
  size_t count = 0;
  EXPECT_EQ(annex_session_objects(session, nullptr, 0, nullptr, &err), ANNEX_INVALID_ARGUMENT);
  EXPECT_EQ(annex_session_objects(session, nullptr, 0, &count, &err), ANNEX_OK);
  EXPECT_EQ(count, 0u);
  annex_session_destroy(session);
  annex_spec_destroy(spec);
}

// A session whose scan parameters come from a config file (its camera's noise model,
// its supports): the file's scan is the one the session runs, and its errors name it.
TEST(CApi, SessionTakesItsScanFromAConfigFile) {
  const annex::SyntheticScene scene = make_scene(31, 3);
  Err err;
  annex_spec* spec = spec_for(scene);
  ASSERT_NE(spec, nullptr);
  annex_session_params params = default_session_params();
  params.background_scan = 0;  // the push scans and reports at once
  const std::string dir = testing::TempDir();
  const auto write = [&](const std::string& name, const std::string& text) {
    const std::string path = dir + "/" + name;
    std::FILE* f = std::fopen(path.c_str(), "w");
    EXPECT_NE(f, nullptr);
    if (f) std::fputs(text.c_str(), f), std::fclose(f);
    return path;
  };
  // A support no frame has: the session's scan fails naming it, so it ran the file's.
  const std::string stereo = write("stereo.conf", "depth_noise stereo\nsupports s9\n");
  annex_session* session = nullptr;
  ASSERT_EQ(annex_session_create_with_scan_config(spec, &params, stereo.c_str(), &session, &err),
            ANNEX_OK)
      << err.message();
  annex_frame* frame = frame_of(annex::render_scene(scene, {}, 0).frame);
  ASSERT_EQ(annex_session_push(session, frame, &err), ANNEX_OK) << err.message();
  annex_frame_info info;
  ASSERT_EQ(annex_session_frame_info(session, &info, &err), ANNEX_OK);
  EXPECT_EQ(info.scan_failed, 1);
  ASSERT_NE(info.scan_error, nullptr);
  EXPECT_NE(std::string(info.scan_error).find("no support 's9'"), std::string::npos)
      << info.scan_error;
  annex_session_destroy(session);
  annex_frame_destroy(frame);

  const std::string bad = write("bad.conf", "depth_noise stereo\ndepth_noise lidar\n");
  session = nullptr;
  EXPECT_EQ(annex_session_create_with_scan_config(spec, &params, bad.c_str(), &session, &err),
            ANNEX_PARSE_ERROR);
  EXPECT_EQ(session, nullptr);
  EXPECT_NE(err.message().find("bad.conf:2:13"), std::string::npos) << err.message();
  EXPECT_EQ(annex_session_create_with_scan_config(spec, &params, (dir + "/none.conf").c_str(),
                                                  &session, &err),
            ANNEX_IO_ERROR);
  EXPECT_EQ(annex_session_create_with_scan_config(spec, &params, nullptr, &session, &err),
            ANNEX_INVALID_ARGUMENT);
  annex_spec_destroy(spec);
}

annex::Quat unity_quat(const double q[4]) {  // Unity x, y, z, w -> our w, x, y, z
  return {q[3], q[0], q[1], q[2]};
}

// Unity's pose is the sensor pose mirrored in y: for any pose, rotating a mirrored model
// point with Unity's quaternion and adding Unity's position gives the mirrored sensor point.
TEST(CApi, UnityPoseIsTheMirroredPose) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0, 1);
  for (int i = 0; i < 50; ++i) {
    annex::Quat q{g(rng), g(rng), g(rng), g(rng)};
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    q = {q.w / n, q.x / n, q.y / n, q.z / n};
    const double pos[3] = {g(rng), g(rng), g(rng)};
    const double rot[4] = {q.w, q.x, q.y, q.z};
    double upos[3], urot[4];
    annex_pose_to_unity(pos, rot, upos, urot);
    const annex::Vec3 m{g(rng), g(rng), g(rng)};  // a model point
    const annex::Vec3 sensor = annex::rotate(q, m) + annex::Vec3{pos[0], pos[1], pos[2]};
    const annex::Vec3 unity =
        annex::rotate(unity_quat(urot), {m.x, -m.y, m.z}) + annex::Vec3{upos[0], upos[1], upos[2]};
    EXPECT_NEAR(unity.x, sensor.x, 1e-12);
    EXPECT_NEAR(unity.y, -sensor.y, 1e-12);
    EXPECT_NEAR(unity.z, sensor.z, 1e-12);
  }
  // In place.
  double p[3] = {1, 2, 3};
  double r[4] = {1, 0, 0, 0};
  annex_pose_to_unity(p, r, p, r);
  EXPECT_EQ(p[1], -2);
  EXPECT_EQ(r[3], 1);
}

}  // namespace
