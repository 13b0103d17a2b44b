// The Renderer (headless; skipped with a message when no OpenGL context can be made),
// the HMD config, primitive meshes and the shared mesh loader.
#include "annex/runtime/renderer.h"

#include <gtest/gtest.h>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <random>
#include <string>

#include "cli_runner.h"
#include "temp_dir.h"

namespace annex {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test (unique_temp_dir.h), removed at the end.
class TempDir : public test::TempDir {
 public:
  TempDir()
      : test::TempDir("renderer_" +
                      std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())) {}
};

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// ---- mesh loader ------------------------------------------------------------------

constexpr const char* kQuadCubeObj =
    "# unit cube with quad faces\n"
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

TEST(MeshIo, LoadsAndTriangulatesQuads) {
  TempDir dir;
  write_file(dir / "cube.obj", kQuadCubeObj);
  auto mesh = load_mesh(dir / "cube.obj");
  ASSERT_TRUE(mesh.ok()) << mesh.error().format();
  EXPECT_EQ(mesh->triangle_count(), 12u);
  EXPECT_EQ(mesh->normals.size(), mesh->positions.size());
  EXPECT_EQ(mesh->colors.size(), mesh->positions.size());
  EXPECT_DOUBLE_EQ(mesh->min.x, -0.5);
  EXPECT_DOUBLE_EQ(mesh->max.z, 0.5);
  EXPECT_TRUE(validate_mesh(*mesh, "cube").ok());
}

TEST(MeshIo, MissingFileNamesThePath) {
  TempDir dir;
  auto mesh = load_mesh(dir / "nope.obj");
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.error().location.origin, (dir / "nope.obj").string());
  EXPECT_NE(mesh.error().message.find("no such file"), std::string::npos);
}

TEST(MeshIo, UnreadableFileIsAnError) {
  TempDir dir;
  write_file(dir / "junk.stl", "solid x\n this is not an stl file at all \x01\x02\n");
  auto mesh = load_mesh(dir / "junk.stl");
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.error().location.origin, (dir / "junk.stl").string());
  EXPECT_NE(mesh.error().format().find("cannot read mesh"), std::string::npos);
}

TEST(MeshIo, LinesOnlyHaveNoTriangles) {
  TempDir dir;
  write_file(dir / "lines.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2\nl 2 3\n");
  auto mesh = load_mesh(dir / "lines.obj");
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.error().message.find("cannot read mesh"), std::string::npos);
}

TEST(MeshIo, EmptyFileIsAnError) {
  TempDir dir;
  write_file(dir / "empty.obj", "");
  EXPECT_FALSE(load_mesh(dir / "empty.obj").ok());
}

TEST(MeshIo, ValidateCatchesBadIndicesAndSizes) {
  MeshData m = primitive_mesh(ShapeKind::box, {1, 1, 1});
  ASSERT_TRUE(validate_mesh(m, "box").ok());
  MeshData bad_index = m;
  bad_index.indices[0] = static_cast<std::uint32_t>(m.vertex_count());
  auto st = validate_mesh(bad_index, "box");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("out of range"), std::string::npos);
  MeshData bad_normals = m;
  bad_normals.normals.pop_back();
  EXPECT_FALSE(validate_mesh(bad_normals, "box").ok());
  MeshData nan = m;
  nan.positions[4] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(validate_mesh(nan, "box").ok());
  EXPECT_FALSE(validate_mesh(MeshData{}, "empty").ok());
}

// ---- primitive meshes ------------------------------------------------------------

TEST(PrimitiveMesh, BoundsFollowTheFormatsConventions) {
  const MeshData cyl = primitive_mesh(ShapeKind::cylinder, {0.04, 0.2});
  EXPECT_NEAR(cyl.max.x, 0.04, 1e-6);
  EXPECT_NEAR(cyl.min.z, -0.1, 1e-6);
  EXPECT_NEAR(cyl.max.z, 0.1, 1e-6);
  const MeshData cone = primitive_mesh(ShapeKind::cone, {0.03, 0.1});
  EXPECT_NEAR(cone.max.z, 0.05, 1e-6);
  // The apex (+z) is a point; the base (-z) has the full radius.
  for (std::size_t i = 0; i < cone.vertex_count(); ++i) {
    if (cone.vertex(i).z > 0.0499) {
      EXPECT_NEAR(std::hypot(cone.vertex(i).x, cone.vertex(i).y), 0, 1e-6);
    }
  }
  const MeshData torus = primitive_mesh(ShapeKind::torus, {0.05, 0.01});
  EXPECT_NEAR(torus.max.x, 0.06, 1e-6);
  EXPECT_NEAR(torus.max.z, 0.01, 1e-6);
  const MeshData sphere = primitive_mesh(ShapeKind::sphere, {0.05});
  EXPECT_NEAR(sphere.min.z, -0.05, 1e-6);
  const MeshData box = primitive_mesh(ShapeKind::box, {0.1, 0.2, 0.3});
  EXPECT_NEAR(box.max.y, 0.1, 1e-6);
  EXPECT_EQ(box.triangle_count(), 12u);
  for (const MeshData* m : {&cyl, &cone, &torus, &sphere, &box})
    EXPECT_TRUE(validate_mesh(*m, "primitive").ok());
  EXPECT_THROW(primitive_mesh(ShapeKind::box, {0.1}), std::invalid_argument);
}

// ---- HMD config ------------------------------------------------------------------

constexpr const char* kHmd =
    "annex-hmd 1\n"
    "sensor_to_hmd_translation 0 0.05 -0.02\n"
    "sensor_to_hmd_rotation 1 0 0 0\n"
    "eye_separation 0.063\n"
    "resolution 960 1080\n"
    "fov 90\n"
    "near 0.1\n"
    "far 10\n";

TEST(HmdConfig, ParsesEveryKey) {
  auto hmd = parse_hmd_config(kHmd, "hmd.conf");
  ASSERT_TRUE(hmd.ok()) << hmd.error().format();
  EXPECT_DOUBLE_EQ(hmd->hmd_from_sensor.position.y, 0.05);
  EXPECT_DOUBLE_EQ(hmd->eye_separation_m, 0.063);
  EXPECT_EQ(hmd->left.width, 960);
  EXPECT_EQ(hmd->right.height, 1080);
  // 90 degrees vertical: fy = (h / 2) / tan(45 degrees).
  EXPECT_NEAR(hmd->left.fy, 540.0, 1e-9);
  EXPECT_NEAR(hmd->left.cx, 479.5, 1e-9);
  EXPECT_DOUBLE_EQ(hmd->near_m, 0.1);
  EXPECT_DOUBLE_EQ(hmd->far_m, 10);
}

TEST(HmdConfig, SampleFileReads) {
  std::vector<Diagnostic> warnings;
  auto hmd = read_hmd_config(test::source_path("samples/config/hmd.conf"), &warnings);
  ASSERT_TRUE(hmd.ok()) << hmd.error().format();
  EXPECT_TRUE(warnings.empty());
  EXPECT_GT(hmd->eye_separation_m, 0.05);
}

TEST(HmdConfig, PerEyeIntrinsics) {
  auto hmd = parse_hmd_config(
      "annex-hmd 1\nresolution 100 80\nintrinsics 90 91 49.5 39.5\n"
      "right_intrinsics 90 91 45 39.5\n",
      "x");
  ASSERT_TRUE(hmd.ok()) << hmd.error().format();
  EXPECT_DOUBLE_EQ(hmd->left.cx, 49.5);
  EXPECT_DOUBLE_EQ(hmd->right.cx, 45);
  EXPECT_DOUBLE_EQ(hmd->right.fy, 91);
}

struct BadConfig {
  const char* text;
  int line;
  int column;
  const char* words;
};

TEST(HmdConfig, ErrorsCarryLineAndColumn) {
  const BadConfig cases[] = {
      {"", 1, 1, "expected the header"},
      {"annex-scene 1\n", 1, 1, "expected the header 'annex-hmd 1'"},
      {"annex-hmd 2\n", 1, 11, "unsupported format version"},
      {"annex-hmd 1\neye_separation abc\n", 2, 16, "expected a number"},
      {"annex-hmd 1\neye_separation -0.06\n", 2, 16, "eye_separation"},
      {"annex-hmd 1\nresolution 640\n", 2, 15, "expected a whole number"},
      {"annex-hmd 1\nresolution 640 0\n", 2, 16, "between 1 and"},
      {"annex-hmd 1\nfov 200\n", 2, 5, "field of view"},
      {"annex-hmd 1\nnear 0.1\nnear 0.2\n", 3, 1, "duplicate key 'near'"},
      {"annex-hmd 1\nsensor_to_hmd_rotation 1 0 0 0.5\n", 2, 1, "unit quaternion"},
      {"annex-hmd 1\nsensor_to_hmd_translation 0 0 0 0\n", 2, 33, "unexpected '0'"},
      {"annex-hmd 1\nfov 60\nintrinsics 500 500 319.5 239.5\n", 3, 1, "both set"},
      {"annex-hmd 1\nnear 2\nfar 1\n", 3, 1, "must be greater than 'near'"},
  };
  for (const BadConfig& c : cases) {
    auto hmd = parse_hmd_config(c.text, "bad.conf");
    ASSERT_FALSE(hmd.ok()) << c.text;
    EXPECT_EQ(hmd.error().location.origin, "bad.conf");
    EXPECT_EQ(hmd.error().location.line, c.line) << c.text << " -> " << hmd.error().format();
    EXPECT_EQ(hmd.error().location.column, c.column) << c.text << " -> " << hmd.error().format();
    EXPECT_NE(hmd.error().message.find(c.words), std::string::npos) << hmd.error().format();
  }
}

TEST(HmdConfig, UnknownKeyWarnsWithSuggestion) {
  std::vector<Diagnostic> warnings;
  auto hmd = parse_hmd_config("annex-hmd 1\neye_seperation 0.06\n", "w.conf", &warnings);
  ASSERT_TRUE(hmd.ok());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].location.line, 2);
  EXPECT_EQ(warnings[0].location.column, 1);
  EXPECT_NE(warnings[0].message.find("did you mean 'eye_separation'"), std::string::npos);
}

TEST(HmdConfig, ManyUnknownKeysGetTenWarningsAndOneSummary) {
  // A file that is not an hmd.conf (here 30 unknown lines, the 31st the valid 'fov')
  // gets the first ten unknown keys one by one and the rest as one located warning.
  std::string text = "annex-hmd 1\n";
  for (int i = 0; i < 30; ++i) text += "  key" + std::to_string(i) + " 1\n";
  text += "fov 50\n";
  std::vector<Diagnostic> warnings;
  auto hmd = parse_hmd_config(text, "many.conf", &warnings);
  ASSERT_TRUE(hmd.ok()) << hmd.error().format();
  ASSERT_EQ(warnings.size(), 11u);
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(warnings[i].location.line, i + 2);
    EXPECT_EQ(warnings[i].location.column, 3);
    EXPECT_NE(warnings[i].message.find("unknown key 'key" + std::to_string(i) + "' ignored"),
              std::string::npos)
        << warnings[i].message;
  }
  EXPECT_EQ(warnings[10].location, (Location{"many.conf", 12, 3}));
  EXPECT_EQ(warnings[10].message, "20 more unknown keys ignored, from here to line 31");
  EXPECT_GT(hmd->left.fy, 0.0);  // the known key after them is still read

  // Exactly ten: no summary.
  std::string ten = "annex-hmd 1\n";
  for (int i = 0; i < 10; ++i) ten += "k" + std::to_string(i) + " 1\n";
  warnings.clear();
  ASSERT_TRUE(parse_hmd_config(ten, "ten.conf", &warnings).ok());
  EXPECT_EQ(warnings.size(), 10u);
}

TEST(HmdConfig, MutatedInputNeverCrashesAndErrorsPointIntoTheText) {
  // Deterministic byte-level mutations of a valid config (a small in-test fuzzer;
  // the sanitizer build catches memory errors).
  const std::string base = kHmd;
  std::mt19937 rng(7);
  for (int i = 0; i < 3000; ++i) {
    std::string text = base;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits && !text.empty(); ++e) {
      const std::size_t at = rng() % text.size();
      switch (rng() % 4) {
        case 0:
          text[at] = static_cast<char>(rng() % 256);
          break;
        case 1:
          text.erase(at, 1 + rng() % 8);
          break;
        case 2:
          text.insert(at, 1, " \n#\"-.9e0"[rng() % 10]);
          break;
        default:
          text.resize(at);
          break;
      }
    }
    std::vector<Diagnostic> warnings;
    auto hmd = parse_hmd_config(text, "m.conf", &warnings);
    if (hmd.ok()) {
      EXPECT_GT(hmd->left.width, 0);
      EXPECT_GT(hmd->far_m, hmd->near_m);
      continue;
    }
    EXPECT_EQ(hmd.error().location.origin, "m.conf");
    EXPECT_GE(hmd.error().location.line, 1) << hmd.error().format();
    EXPECT_GE(hmd.error().location.column, 1) << hmd.error().format();
  }
}

TEST(HmdConfig, MissingFileNamesThePath) {
  auto hmd = read_hmd_config("/nonexistent/hmd.conf");
  ASSERT_FALSE(hmd.ok());
  EXPECT_NE(hmd.error().format().find("/nonexistent/hmd.conf"), std::string::npos);
}

TEST(HmdEyes, EyesSitHalfTheSeparationAside) {
  HmdConfig hmd;
  hmd.eye_separation_m = 0.064;
  hmd.hmd_from_sensor.position = {0, 0.1, 0};
  const auto eyes = hmd_eyes(hmd);
  // A point 1 m ahead of the sensor is right of the left eye, left of the right one.
  const Vec3 l = eyes[0].eye_from_sensor.apply({0, 0, 1});
  const Vec3 r = eyes[1].eye_from_sensor.apply({0, 0, 1});
  EXPECT_NEAR(l.x, 0.032, 1e-12);
  EXPECT_NEAR(r.x, -0.032, 1e-12);
  EXPECT_NEAR(l.y, 0.1, 1e-12);
  EXPECT_NEAR(l.z, 1.0, 1e-12);
}

// ---- rendering ------------------------------------------------------------------

constexpr CameraIntrinsics kKinect{640, 480, 525, 525, 319.5, 239.5};

class RendererTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto r = Renderer::create();
    if (!r) GTEST_SKIP() << "no OpenGL context, rendering not tested: " << r.error().message;
    renderer_.emplace(std::move(*r));
  }
  std::optional<Renderer> renderer_;
};

Affine translation(Vec3 t) {
  Affine a;
  a.m[3] = t.x;
  a.m[7] = t.y;
  a.m[11] = t.z;
  return a;
}

struct Coverage {
  long count = 0;
  double cu = 0, cv = 0;  // centroid
  int min_u = 1 << 30, max_u = -1, min_v = 1 << 30, max_v = -1;
};

// Pixels of `img` in columns [u0, u1) that differ from the clear colour (black).
Coverage coverage(const RgbaImage& img, int u0 = 0, int u1 = -1) {
  if (u1 < 0) u1 = img.width;
  Coverage c;
  for (int v = 0; v < img.height; ++v)
    for (int u = u0; u < u1; ++u) {
      const std::uint8_t* p = &img.rgba[(static_cast<std::size_t>(v) * img.width + u) * 4];
      if (p[0] + p[1] + p[2] == 0) continue;
      ++c.count;
      c.cu += u - u0;
      c.cv += v;
      c.min_u = std::min(c.min_u, u - u0);
      c.max_u = std::max(c.max_u, u - u0);
      c.min_v = std::min(c.min_v, v);
      c.max_v = std::max(c.max_v, v);
    }
  if (c.count > 0) {
    c.cu /= c.count;
    c.cv /= c.count;
  }
  return c;
}

const std::uint8_t* pixel(const RgbaImage& img, int u, int v) {
  return &img.rgba[(static_cast<std::size_t>(v) * img.width + u) * 4];
}

RenderScene black_scene() {
  RenderScene s;
  s.background = Background::clear;
  s.camera = kKinect;
  s.clear_color = {0, 0, 0, 1};
  return s;
}

TEST(Renderer, NoBackendIsAnErrorNotACrash) {
  RendererParams p;
  p.try_egl = false;
  p.try_hidden_window = false;
  auto r = Renderer::create(p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("no OpenGL context"), std::string::npos);
}

TEST_F(RendererTest, CubeCentreLandsAtItsProjection) {
  auto cube = renderer_->add_mesh(primitive_mesh(ShapeKind::box, {0.1, 0.1, 0.1}), "cube");
  ASSERT_TRUE(cube.ok()) << cube.error().format();
  RenderScene s = black_scene();
  const Vec3 c{0.1, -0.05, 1.0};
  s.overlays.push_back({*cube, translation(c), {1, 1, 1, 1}, OverlayStyle::solid});
  const Eye eye = sensor_eye(kKinect);
  auto img = renderer_->render(s, std::span(&eye, 1));
  ASSERT_TRUE(img.ok()) << img.error().format();
  ASSERT_EQ(img->width, 640);
  ASSERT_EQ(img->height, 480);

  const Coverage cov = coverage(*img);
  ASSERT_GT(cov.count, 0);
  // Silhouette: the projection of the 8 corners, whose extremes bound it.
  double min_u = 1e9, max_u = -1e9, min_v = 1e9, max_v = -1e9;
  for (int i = 0; i < 8; ++i) {
    const Vec3 p = c + Vec3{i & 1 ? 0.05 : -0.05, i & 2 ? 0.05 : -0.05, i & 4 ? 0.05 : -0.05};
    const double u = kKinect.fx * p.x / p.z + kKinect.cx, v = kKinect.fy * p.y / p.z + kKinect.cy;
    min_u = std::min(min_u, u);
    max_u = std::max(max_u, u);
    min_v = std::min(min_v, v);
    max_v = std::max(max_v, v);
  }
  EXPECT_NEAR(cov.min_u, min_u, 2);
  EXPECT_NEAR(cov.max_u, max_u, 2);
  EXPECT_NEAR(cov.min_v, min_v, 2);
  EXPECT_NEAR(cov.max_v, max_v, 2);

  // A thin plate facing the camera at the same centre: its silhouette's centroid is
  // the projection of its centre, (372, 213.25).
  auto plate = renderer_->add_mesh(primitive_mesh(ShapeKind::box, {0.1, 0.1, 0.002}), "plate");
  ASSERT_TRUE(plate.ok());
  s.overlays = {{*plate, translation(c), {1, 1, 1, 1}, OverlayStyle::solid}};
  auto plate_img = renderer_->render(s, std::span(&eye, 1));
  ASSERT_TRUE(plate_img.ok());
  const Coverage pc = coverage(*plate_img);
  EXPECT_NEAR(pc.cu, 372.0, 2.0);
  EXPECT_NEAR(pc.cv, 213.25, 2.0);
  EXPECT_NEAR(static_cast<double>(pc.count), 52.5 * 52.5, 0.1 * 52.5 * 52.5);
}

TEST_F(RendererTest, WritesAPngThatReadsBackTheSame) {
  auto cube = renderer_->add_mesh(primitive_mesh(ShapeKind::sphere, {0.05}), "ball");
  ASSERT_TRUE(cube.ok());
  RenderScene s = black_scene();
  s.overlays.push_back(
      {*cube, translation({0, 0, 0.8}), {0.9f, 0.3f, 0.2f, 1}, OverlayStyle::solid});
  const Eye eye = sensor_eye({160, 120, 131.25, 131.25, 79.5, 59.5});
  auto img = renderer_->render(s, std::span(&eye, 1));
  ASSERT_TRUE(img.ok()) << img.error().format();
  TempDir dir;
  ASSERT_TRUE(write_rgba_png(dir / "ball.png", *img).ok());
  int w = 0, h = 0, n = 0;
  stbi_uc* data = stbi_load((dir / "ball.png").c_str(), &w, &h, &n, 4);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(w, 160);
  EXPECT_EQ(h, 120);
  EXPECT_TRUE(std::equal(img->rgba.begin(), img->rgba.end(), data));
  stbi_image_free(data);
  // The centre pixel is lit reddish, the corner is the clear colour.
  EXPECT_GT(pixel(*img, 80, 60)[0], pixel(*img, 80, 60)[2]);
  EXPECT_EQ(pixel(*img, 0, 0)[0], 0);
}

TEST_F(RendererTest, StereoIsTwiceAsWideWithParallax) {
  auto plate = renderer_->add_mesh(primitive_mesh(ShapeKind::box, {0.05, 0.05, 0.002}), "plate");
  ASSERT_TRUE(plate.ok());
  RenderScene s = black_scene();
  s.overlays.push_back({*plate, translation({0, 0, 0.5}), {1, 1, 1, 1}, OverlayStyle::solid});
  HmdConfig hmd;
  hmd.eye_separation_m = 0.064;
  hmd.left = hmd.right = {320, 240, 262.5, 262.5, 159.5, 119.5};
  const auto eyes = hmd_eyes(hmd);
  auto img = renderer_->render(s, eyes);
  ASSERT_TRUE(img.ok()) << img.error().format();
  EXPECT_EQ(img->width, 640);
  EXPECT_EQ(img->height, 240);
  const Coverage left = coverage(*img, 0, 320), right = coverage(*img, 320, 640);
  ASSERT_GT(left.count, 0);
  ASSERT_GT(right.count, 0);
  // The plate sits 0.032 m right of the left eye and as far left of the right eye.
  EXPECT_NEAR(left.cu, 262.5 * 0.032 / 0.5 + 159.5, 2.0);
  EXPECT_NEAR(right.cu, -262.5 * 0.032 / 0.5 + 159.5, 2.0);
  EXPECT_NEAR(left.cv, 119.5, 2.0);
}

// An organized frame as camera `k` sees it: pixel (u, v) holds the point at depth
// depth(u, v) on its ray, coloured by paint(u, v, point).
template <typename Depth, typename Paint>
Frame pinhole_frame(const CameraIntrinsics& k, Depth depth, Paint paint) {
  Frame f;
  f.width = k.width;
  f.height = k.height;
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      PointXYZRGB p;
      p.z = depth(u, v);
      p.x = static_cast<float>((u - k.cx) / k.fx * p.z);
      p.y = static_cast<float>((v - k.cy) / k.fy * p.z);
      paint(u, v, p);
      f.points.push_back(p);
    }
  return f;
}

TEST_F(RendererTest, CameraImageLinesUpWithThePixels) {
  // A 64x48 organized frame: each pixel's colour encodes its column and row.
  const CameraIntrinsics k{64, 48, 52.5, 52.5, 31.5, 23.5};
  const Frame f = pinhole_frame(
      k, [](int u, int) { return 1.0f + 0.01f * u; },
      [](int u, int v, PointXYZRGB& p) {
        p.r = static_cast<std::uint8_t>(u * 4);
        p.g = static_cast<std::uint8_t>(v * 5);
        p.b = 77;
      });
  RenderScene s;
  s.frame = &f;
  s.background = Background::camera_image;
  s.camera = k;
  const Eye eye = sensor_eye(k);
  auto img = renderer_->render(s, std::span(&eye, 1));
  ASSERT_TRUE(img.ok()) << img.error().format();
  for (int v = 0; v < 48; v += 7)
    for (int u = 0; u < 64; u += 9) {
      const std::uint8_t* p = pixel(*img, u, v);
      EXPECT_NEAR(p[0], u * 4, 1) << u << "," << v;
      EXPECT_NEAR(p[1], v * 5, 1) << u << "," << v;
      EXPECT_NEAR(p[2], 77, 1);
    }
  // At twice the resolution the image is drawn as the camera's image plane (not
  // copied): output pixel 2u + 1 samples the source at u + 0.75.
  const CameraIntrinsics k2{128, 96, 105, 105, 63.5, 47.5};
  const Eye eye2 = sensor_eye(k2);
  auto big = renderer_->render(s, std::span(&eye2, 1));
  ASSERT_TRUE(big.ok()) << big.error().format();
  ASSERT_EQ(big->width, 128);
  for (int v = 0; v < 47; v += 7)
    for (int u = 0; u < 63; u += 9) {
      const std::uint8_t* p = pixel(*big, 2 * u + 1, 2 * v + 1);
      EXPECT_NEAR(p[0], u * 4 + 1, 2) << u << "," << v;
      EXPECT_NEAR(p[1], v * 5 + 1.25, 2) << u << "," << v;
    }
}

TEST_F(RendererTest, RealSurfacesInFrontOfAnOverlayHideItOnlyWhenAsked) {
  // A 64x48 frame: a near surface (0.5 m) on the left third, the annexed prop's own
  // surface 1.5 cm in front of the overlay in the middle, far floor (2 m) on the right;
  // the image is green, NaN in row 0. A red plate fills the view at 1 m.
  const CameraIntrinsics k{64, 48, 52.5, 52.5, 31.5, 23.5};
  const Frame f = pinhole_frame(
      k,
      [](int u, int v) {
        return v == 0 ? std::numeric_limits<float>::quiet_NaN()
                      : u < 21 ? 0.5f : u < 42 ? 0.985f : 2.0f;
      },
      [](int, int, PointXYZRGB& p) { p.g = 200; });
  auto plate = renderer_->add_mesh(primitive_mesh(ShapeKind::box, {4, 4, 0.01}), "wide plate");
  ASSERT_TRUE(plate.ok());
  RenderScene s;
  s.frame = &f;
  s.background = Background::camera_image;
  s.camera = k;
  s.overlays = {{*plate, translation({0, 0, 1.0}), {1, 0, 0, 1}, OverlayStyle::solid}};
  const Eye eye = sensor_eye(k);
  auto over = renderer_->render(s, std::span(&eye, 1));
  ASSERT_TRUE(over.ok()) << over.error().format();
  for (int u : {5, 30, 55}) EXPECT_GT(pixel(*over, u, 24)[0], 0) << u;  // default: on top
  s.occlusion_margin_m = 0.03;
  auto occluded = renderer_->render(s, std::span(&eye, 1));
  ASSERT_TRUE(occluded.ok()) << occluded.error().format();
  EXPECT_EQ(pixel(*occluded, 5, 24)[0], 0);  // the near surface hides the plate
  EXPECT_EQ(pixel(*occluded, 5, 24)[1], 200);
  EXPECT_GT(pixel(*occluded, 30, 24)[0], 0);  // the prop, within the margin, does not
  EXPECT_GT(pixel(*occluded, 55, 24)[0], 0);  // the far floor is behind the plate
  EXPECT_GT(pixel(*occluded, 5, 0)[0], 0);    // no depth: no occlusion
}

TEST_F(RendererTest, PointCloudDrawsPointsWhereTheyProjectAndSkipsNaN) {
  Frame f;
  f.width = 3;
  f.height = 1;
  // Placed so that each point's centre falls on a pixel centre (cx, cy = 320, 240).
  PointXYZRGB a;
  a.x = 0.2f;
  a.y = 0.2f;
  a.z = 1.0f;
  a.r = 255;
  PointXYZRGB nan;
  nan.x = nan.y = nan.z = std::numeric_limits<float>::quiet_NaN();
  nan.g = 255;
  PointXYZRGB b;
  b.x = -0.4f;
  b.y = -0.4f;
  b.z = 2.0f;
  b.b = 255;
  f.points = {a, nan, b};
  const CameraIntrinsics k{640, 480, 525, 525, 320, 240};
  RenderScene s = black_scene();
  s.frame = &f;
  s.background = Background::point_cloud;
  s.camera = k;
  s.point_size_px = 3;
  const Eye eye = sensor_eye(k);
  auto img = renderer_->render(s, std::span(&eye, 1));
  ASSERT_TRUE(img.ok()) << img.error().format();
  // a projects to (425, 345), b to (215, 135).
  EXPECT_EQ(pixel(*img, 425, 345)[0], 255);
  EXPECT_EQ(pixel(*img, 215, 135)[2], 255);
  const Coverage cov = coverage(*img);
  EXPECT_EQ(cov.count, 18);  // two 3x3 points, nothing from the NaN one
  EXPECT_NEAR(cov.cu, (425 + 215) / 2.0, 1e-9);
}

TEST_F(RendererTest, PointStrideThinsRowsAndColumns) {
  // A 4x4 organized frame, every point valid, each on its own pixel centre.
  const CameraIntrinsics k{8, 8, 8, 8, 4, 4};
  Frame f;
  f.width = 4;
  f.height = 4;
  for (int v = 0; v < 4; ++v)
    for (int u = 0; u < 4; ++u) {
      PointXYZRGB p;
      p.z = 1;
      p.x = (2 * u - 4) / 8.0f;
      p.y = (2 * v - 4) / 8.0f;
      p.r = p.g = p.b = 200;
      f.points.push_back(p);
    }
  RenderScene s = black_scene();
  s.frame = &f;
  s.background = Background::point_cloud;
  s.camera = k;
  s.point_size_px = 1;
  const Eye eye = sensor_eye(k);
  auto all = renderer_->render(s, std::span(&eye, 1));
  ASSERT_TRUE(all.ok()) << all.error().format();
  EXPECT_EQ(coverage(*all).count, 16);
  s.point_stride = 2;
  auto thinned = renderer_->render(s, std::span(&eye, 1));
  ASSERT_TRUE(thinned.ok());
  EXPECT_EQ(coverage(*thinned).count, 4);
  EXPECT_EQ(pixel(*thinned, 0, 0)[0], 200);  // rows and columns 0 and 2 are kept
  EXPECT_EQ(pixel(*thinned, 4, 4)[0], 200);
  EXPECT_EQ(pixel(*thinned, 2, 2)[0], 0);
}

TEST_F(RendererTest, NearerOverlayHidesFartherOneAndPointsOccludeMeshes) {
  auto box = renderer_->add_mesh(primitive_mesh(ShapeKind::box, {0.1, 0.1, 0.01}), "plate");
  ASSERT_TRUE(box.ok());
  RenderScene s = black_scene();
  // Drawn far first, near second, then the reverse: the near one wins either way.
  for (int order = 0; order < 2; ++order) {
    s.overlays.clear();
    const Overlay far{*box, translation({0, 0, 1.0}), {0, 0, 1, 1}, OverlayStyle::solid};
    const Overlay near{*box, translation({0, 0, 0.8}), {1, 0, 0, 1}, OverlayStyle::solid};
    s.overlays = order == 0 ? std::vector<Overlay>{far, near} : std::vector<Overlay>{near, far};
    const Eye eye = sensor_eye(kKinect);
    auto img = renderer_->render(s, std::span(&eye, 1));
    ASSERT_TRUE(img.ok());
    EXPECT_GT(pixel(*img, 320, 240)[0], 0);
    EXPECT_EQ(pixel(*img, 320, 240)[2], 0);
  }
  // A green point 0.5 m ahead hides a plate at 1 m, and a plate at 0.4 m hides it.
  Frame f;
  f.width = 1;
  f.height = 1;
  PointXYZRGB p;
  p.z = 0.5f;
  p.g = 255;
  f.points = {p};
  s.frame = &f;
  s.background = Background::point_cloud;
  s.point_size_px = 5;
  const Eye eye = sensor_eye(kKinect);
  s.overlays = {{*box, translation({0, 0, 1.0}), {1, 0, 0, 1}, OverlayStyle::solid}};
  auto behind = renderer_->render(s, std::span(&eye, 1));
  ASSERT_TRUE(behind.ok());
  EXPECT_EQ(pixel(*behind, 320, 240)[1], 255);
  EXPECT_EQ(pixel(*behind, 320, 240)[0], 0);
  s.overlays[0].world_from_model = translation({0, 0, 0.4});
  auto in_front = renderer_->render(s, std::span(&eye, 1));
  ASSERT_TRUE(in_front.ok());
  EXPECT_GT(pixel(*in_front, 320, 240)[0], 0);
  EXPECT_EQ(pixel(*in_front, 320, 240)[1], 0);
}

TEST_F(RendererTest, WireframeCoversLessThanSolid) {
  auto ball = renderer_->add_mesh(primitive_mesh(ShapeKind::sphere, {0.1}, 12), "ball");
  ASSERT_TRUE(ball.ok());
  RenderScene s = black_scene();
  const Eye eye = sensor_eye(kKinect);
  s.overlays = {{*ball, translation({0, 0, 1}), {1, 1, 1, 1}, OverlayStyle::solid}};
  const long solid = coverage(*renderer_->render(s, std::span(&eye, 1))).count;
  s.overlays[0].style = OverlayStyle::wireframe;
  const long wire = coverage(*renderer_->render(s, std::span(&eye, 1))).count;
  EXPECT_GT(wire, 0);
  EXPECT_LT(wire, solid / 2);
}

TEST_F(RendererTest, FittedScaleStretchesTheOverlay) {
  // A cylinder primitive fitted to a prop twice its height (limits allow it).
  Primitive body = make_primitive(ShapeKind::cylinder, "body");
  body.dimensions[0] = {0.04, 1, 0.5, 2};
  body.dimensions[1] = {0.1, 1, 0.5, 2};
  const PhysicalPrimitive prop{ShapeKind::cylinder, {0.04, 0.2}, {0, 0, 1}, {0, -1, 0}, 1};
  const PropFit fit = fit_to_prop(body, prop);
  auto mesh = renderer_->add_mesh(primitive_mesh(ShapeKind::cylinder, {0.04, 0.1}), "body");
  ASSERT_TRUE(mesh.ok());
  RenderScene s = black_scene();
  s.overlays = {{*mesh, fit.world_from_model, {1, 1, 1, 1}, OverlayStyle::solid}};
  const Eye eye = sensor_eye(kKinect);
  auto img = renderer_->render(s, std::span(&eye, 1));
  ASSERT_TRUE(img.ok());
  const Coverage cov = coverage(*img);
  // 0.2 m tall at about 1 m: about 105 px high (the caps add a few); 0.08 m wide: 42 px.
  EXPECT_NEAR(cov.max_v - cov.min_v, 525 * 0.2, 6);
  EXPECT_NEAR(cov.max_u - cov.min_u, 525 * 0.08, 4);
}

TEST_F(RendererTest, MeshesAreCachedByPath) {
  TempDir dir;
  write_file(dir / "cube.obj", kQuadCubeObj);
  write_file(dir / "cube2.obj", kQuadCubeObj);
  auto a = renderer_->load_mesh(dir / "cube.obj");
  ASSERT_TRUE(a.ok()) << a.error().format();
  auto again = renderer_->load_mesh(dir / "." / "cube.obj");
  auto b = renderer_->load_mesh(dir / "cube2.obj");
  ASSERT_TRUE(again.ok());
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(*a, *again);
  EXPECT_NE(*a, *b);
  auto missing = renderer_->load_mesh(dir / "missing.obj");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().location.origin, (dir / "missing.obj").string());
}

TEST_F(RendererTest, BadRequestsAreErrors) {
  RenderScene s = black_scene();
  const Eye eye = sensor_eye(kKinect);
  EXPECT_FALSE(renderer_->render(s, std::span<const Eye>()).ok());
  s.overlays = {{MeshId{42}, Affine{}, {}, OverlayStyle::solid}};
  auto unknown = renderer_->render(s, std::span(&eye, 1));
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().message.find("unknown mesh id"), std::string::npos);
  s.overlays.clear();
  Frame cloud;
  cloud.width = 2;
  cloud.height = 1;
  cloud.index = 7;
  cloud.points.resize(2);
  s.frame = &cloud;
  s.background = Background::camera_image;
  auto unorganized = renderer_->render(s, std::span(&eye, 1));
  ASSERT_FALSE(unorganized.ok());
  EXPECT_EQ(unorganized.error().location.origin, "frame 7");
  cloud.points.resize(5);
  s.background = Background::point_cloud;
  EXPECT_FALSE(renderer_->render(s, std::span(&eye, 1)).ok());
  Eye zero = eye;
  zero.intrinsics.width = 0;
  s.background = Background::clear;
  EXPECT_FALSE(renderer_->render(s, std::span(&zero, 1)).ok());
  EXPECT_FALSE(renderer_->present(s, std::span(&eye, 1)).ok());  // headless
}

TEST_F(RendererTest, ReusedOutputKeepsItsSizeAcrossFrames) {
  RenderScene s = black_scene();
  const Eye small = sensor_eye({32, 24, 26, 26, 15.5, 11.5});
  const Eye big = sensor_eye({64, 48, 52, 52, 31.5, 23.5});
  RgbaImage out;
  ASSERT_TRUE(renderer_->render(s, std::span(&big, 1), out).ok());
  EXPECT_EQ(out.rgba.size(), 64u * 48 * 4);
  ASSERT_TRUE(renderer_->render(s, std::span(&small, 1), out).ok());
  EXPECT_EQ(out.width, 32);
  EXPECT_EQ(out.rgba.size(), 32u * 24 * 4);
}

// ---- annex-runtime render ----------------------------------------------------------

TEST(RenderCommand, RendersFigure3) {
  TempDir dir;
  const std::string out = (dir / "fig3.png").string();
  const auto run = test::run_cli(
      "render " + test::shell_quote(test::source_path("samples/figure3/figure3.haptic")) + " " +
      test::shell_quote(test::source_path("samples/figure3/figure3.scene")) + " --out " +
      test::shell_quote(out));
  if (run.exit_code == 1 && run.output.find("no OpenGL context") != std::string::npos)
    GTEST_SKIP() << "no OpenGL context: " << run.output;
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("render v1 on p2"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("render v2 on p3"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("render v3 on p1"), std::string::npos) << run.output;
  int w = 0, h = 0, n = 0;
  stbi_uc* data = stbi_load(out.c_str(), &w, &h, &n, 4);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(w, 640);
  EXPECT_EQ(h, 480);
  stbi_image_free(data);

  const auto stereo = test::run_cli(
      "render " + test::shell_quote(test::source_path("samples/figure3/figure3.haptic")) + " " +
      test::shell_quote(test::source_path("samples/figure3/figure3.scene")) + " --stereo --hmd " +
      test::shell_quote(test::source_path("samples/config/hmd.conf")) + " --out " +
      test::shell_quote(out));
  ASSERT_EQ(stereo.exit_code, 0) << stereo.output;
  data = stbi_load(out.c_str(), &w, &h, &n, 4);
  ASSERT_NE(data, nullptr);
  stbi_image_free(data);
  const auto hmd = read_hmd_config(test::source_path("samples/config/hmd.conf"));
  ASSERT_TRUE(hmd.ok());
  EXPECT_EQ(w, hmd->left.width + hmd->right.width);
}

TEST(RenderCommand, BadArgumentsExitTwo) {
  EXPECT_EQ(test::run_cli("render").exit_code, 2);
  const auto no_out = test::run_cli(
      "render " + test::shell_quote(test::source_path("samples/figure3/figure3.haptic")) + " " +
      test::shell_quote(test::source_path("samples/figure3/figure3.scene")));
  EXPECT_EQ(no_out.exit_code, 2);
  EXPECT_NE(no_out.output.find("--out"), std::string::npos);
}

// run's overlay PNGs name what is annexed onto what: the labelled image differs from
// the --no-labels one only in label pixels (white text on black boxes), and there are
// as many label boxes' worth as annexed objects.
TEST(RunCommand, OverlaysAreLabelledUnlessNoLabels) {
  TempDir dir;
  auto run = [&](const std::string& sub, const std::string& extra) {
    return test::run_cli("run " + test::shell_quote(test::source_path("samples/specs/study.haptic")) +
                         " --source " +
                         test::shell_quote(test::source_path("samples/recordings/tabletop")) +
                         " --frames 1 --out " + test::shell_quote((dir / sub).string()) + extra);
  };
  const auto labelled = run("labelled", ""), plain = run("plain", " --no-labels");
  if (labelled.output.find("warning: no overlay images") != std::string::npos)
    GTEST_SKIP() << "no OpenGL context: " << labelled.output;
  ASSERT_EQ(labelled.exit_code, 0) << labelled.output;
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  int w = 0, h = 0, n = 0, w2 = 0, h2 = 0;
  stbi_uc* a = stbi_load((dir / "labelled" / "overlay_00000.png").c_str(), &w, &h, &n, 4);
  stbi_uc* b = stbi_load((dir / "plain" / "overlay_00000.png").c_str(), &w2, &h2, &n, 4);
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  ASSERT_EQ(w, w2);
  ASSERT_EQ(h, h2);
  int differ = 0, label_pixels = 0, text_pixels = 0, top = h, bottom = -1;
  for (int i = 0; i < w * h; ++i) {
    const stbi_uc* p = a + 4 * i;
    const stbi_uc* q = b + 4 * i;
    if (p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) continue;
    ++differ;
    const bool black = p[0] == 0 && p[1] == 0 && p[2] == 0;
    const bool white = p[0] == 255 && p[1] == 255 && p[2] == 255;
    label_pixels += black || white;
    text_pixels += white;
    top = std::min(top, i / w), bottom = std::max(bottom, i / w);
  }
  stbi_image_free(a);
  stbi_image_free(b);
  EXPECT_EQ(label_pixels, differ);
  EXPECT_GT(text_pixels, 300);
  // Two annexed objects (bottle and lamp), 14-pixel text: more than one label's height.
  EXPECT_NE(labelled.output.find("annexed champagne_bottle"), std::string::npos);
  EXPECT_NE(labelled.output.find("annexed lamp"), std::string::npos);
  EXPECT_GT(bottom - top, 18);
}

}  // namespace
}  // namespace annex
