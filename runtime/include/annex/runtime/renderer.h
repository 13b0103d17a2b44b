#pragma once
// The paper's Renderer: virtual meshes, fitted onto their props, drawn over what the
// depth camera sees (its colour image, or its points), in a live window or headless
// into RGBA images, for the sensor's own view or side by side for the two eyes of a
// head-mounted display. OpenGL, EGL, GLFW and assimp stay behind this header.
// docs/renderer.md describes the conventions and the backends.

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/physical_scene.h"
#include "annex/common/prop_fit.h"
#include "annex/common/result.h"
#include "annex/common/shape.h"
#include "annex/formats/haptic_format.h"
#include "annex/formats/mesh_io.h"
#include "annex/runtime/frame.h"

namespace annex {

// 8-bit RGBA, row-major, top row first (the order PNG files and the camera use).
struct RgbaImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  // 4 bytes per pixel
};

// Linear colour with opacity, each in [0, 1].
struct Rgba {
  float r = 1, g = 1, b = 1, a = 1;
};

// Distinct tints, cycling, so overlays drawn without their mesh stay apart.
inline Rgba overlay_tint(std::size_t index) {
  constexpr Rgba kPalette[] = {{0.95f, 0.55f, 0.20f, 1}, {0.30f, 0.60f, 0.95f, 1},
                               {0.85f, 0.40f, 0.75f, 1}, {0.90f, 0.30f, 0.30f, 1},
                               {0.95f, 0.85f, 0.30f, 1}};
  return kPalette[index % (sizeof kPalette / sizeof kPalette[0])];
}

// A mesh uploaded to a Renderer; valid only with the Renderer that returned it.
struct MeshId {
  int index = -1;
  bool valid() const { return index >= 0; }
  bool operator==(const MeshId&) const = default;
};

enum class OverlayStyle { solid, wireframe };

// One virtual object to draw: a mesh placed in the sensor frame.
struct Overlay {
  MeshId mesh;
  // Model to sensor coordinates; PropFit::world_from_model (any affine, so the
  // 3-DOF scale of a fit is drawn as is; normals are corrected for it).
  Affine world_from_model;
  // Multiplies the mesh's vertex colours (solid) or is the line colour (wireframe);
  // a < 1 blends the overlay over what is behind it.
  Rgba tint;
  OverlayStyle style = OverlayStyle::solid;
};

// What is drawn behind the overlays.
enum class Background {
  clear,         // RenderScene::clear_color only
  camera_image,  // the frame's colours as the camera's image (needs an organized frame)
  point_cloud,   // the frame's points as GL_POINTS, depth-tested against the overlays
};

// One viewpoint: a pinhole camera placed relative to the sensor. The sensor's own
// view (sensor_eye) uses the camera's intrinsics, so overlays line up pixel for pixel
// with the colour image.
struct Eye {
  CameraIntrinsics intrinsics;  // viewport size and projection (x right, y down, z forward)
  Affine eye_from_sensor;       // rigid: sensor coordinates to this eye's coordinates
  double near_m = 0.05;
  double far_m = 20.0;
};

struct RenderScene {
  const Frame* frame = nullptr;  // background source, not owned; may be null with `clear`
  Background background = Background::camera_image;
  CameraIntrinsics camera;  // the sensor's: maps frame pixels to rays
  std::vector<Overlay> overlays;
  Rgba clear_color{0.16f, 0.17f, 0.19f, 1.0f};
  float point_size_px = 2.0f;
  // Point cloud: draw every n-th point (organized frames: every n-th row and column,
  // with point_size_px about n keeping the cloud closed). Software GL (llvmpipe)
  // pays per point: docs/BENCHMARKS.md.
  int point_stride = 1;
  // For an eye that is not the sensor, the camera image is a plane at this depth
  // (0: the median depth of the frame), so both HMD eyes see it with a plausible
  // parallax. The sensor's own view is exact at any depth.
  double image_depth_m = 0;
  // Camera image background, sensor's own view: real surfaces nearer than an overlay by
  // more than this margin hide it (a hand in front of a virtual object), while the
  // annexed prop's own surface, close to its overlay, does not. Negative (the default):
  // overlays are drawn over the whole image. Eyes away from the sensor see the image
  // as a plane and are never occluded.
  double occlusion_margin_m = -1;
};

// Sensor-to-HMD extrinsics and the HMD's two displays (samples/config/hmd.conf).
// The HMD frame has the camera convention: x right, y down, z forward; the eyes sit
// at x = -/+ eye_separation_m / 2 in it.
struct HmdConfig {
  Pose hmd_from_sensor;  // p_hmd = R p_sensor + t
  double eye_separation_m = 0.064;
  CameraIntrinsics left;  // per-eye resolution and projection
  CameraIntrinsics right;
  double near_m = 0.05;
  double far_m = 20.0;
};

// Parses `key value...` lines (docs/renderer.md). Pure: no file IO. Errors carry
// origin:line:col; unknown keys are warnings.
Result<HmdConfig> parse_hmd_config(std::string_view text, std::string_view origin,
                                   std::vector<Diagnostic>* warnings = nullptr);
Result<HmdConfig> read_hmd_config(const std::filesystem::path& path,
                                  std::vector<Diagnostic>* warnings = nullptr);

// The sensor's own viewpoint with its intrinsics.
Eye sensor_eye(const CameraIntrinsics& camera);
// Left and right eye of the HMD, in that order (rendered left to right).
std::array<Eye, 2> hmd_eyes(const HmdConfig& hmd);

// A primitive as a triangle mesh in its own frame (axis +Z, centred as the .scene
// format places it: cylinder and cone span z in [-h/2, h/2], the cone's apex at
// +h/2; the torus ring lies in the xy plane). `segments` around the axis, >= 3.
MeshData primitive_mesh(ShapeKind kind, const std::vector<double>& dimensions_m, int segments = 32);
// Where a physical primitive's own frame sits in the sensor frame.
Affine world_from_physical(const PhysicalPrimitive& primitive);

enum class RenderTarget {
  headless,  // offscreen: EGL surfaceless (no X server), else a hidden GLFW window
  window,    // a visible GLFW window; present() shows frames in it
};

struct RendererParams {
  RenderTarget target = RenderTarget::headless;
  bool try_egl = true;            // headless: try EGL surfaceless first
  bool try_hidden_window = true;  // headless: then a hidden GLFW window (needs DISPLAY)
  int window_width = 1280;        // window: initial size and title
  int window_height = 480;
  std::string window_title = "Annex";
};

// An OpenGL context with the meshes uploaded to it and reusable framebuffers.
// Meshes are uploaded once (cached by path); each render() draws into the same
// offscreen framebuffer and reads it back. Use a Renderer from one thread at a time:
// each call makes its context current on the calling thread.
class Renderer {
 public:
  // An Error (never a crash) when no OpenGL 3.3 core context can be created, e.g.
  // without EGL and without DISPLAY; the message says which backends were tried.
  static Result<Renderer> create(const RendererParams& params = {});

  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;
  ~Renderer();

  // "EGL surfaceless: llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6"
  std::string backend() const;

  // Loads with load_mesh() and uploads; the same path (canonicalised) returns the
  // cached id without reading the file again.
  Result<MeshId> load_mesh(const std::filesystem::path& path);
  // Validates and uploads a mesh built in memory; `origin` names it in errors.
  Result<MeshId> add_mesh(const MeshData& mesh, const std::string& origin);

  // Draws the scene once per eye, side by side from left to right (width: the sum
  // of the eyes' widths; height: the largest), into `out`, whose buffer is reused.
  // Errors: no eyes, a bad eye size, an unknown mesh id, a frame that does not suit
  // the background (an unorganized frame as a camera image, a size mismatch).
  Status render(const RenderScene& scene, std::span<const Eye> eyes, RgbaImage& out);
  Result<RgbaImage> render(const RenderScene& scene, std::span<const Eye> eyes);

  // Window target: draws the scene, shows it scaled to the window (aspect kept) and
  // polls events. Returns false once the user has closed the window. Headless: Error.
  Result<bool> present(const RenderScene& scene, std::span<const Eye> eyes);

 private:
  struct Impl;
  explicit Renderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// PNG bytes of an image (stb_image_write), and an atomic file write of them.
std::string encode_rgba_png(const RgbaImage& image);
Status write_rgba_png(const std::filesystem::path& path, const RgbaImage& image);

}  // namespace annex
