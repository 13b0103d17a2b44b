// annex-runtime render SPEC.haptic SCENE.scene --out OUT.png: matches the spec to a
// scene, fits each matched virtual object onto its prop and renders it, to check
// the Renderer by eye.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "annex/common/object_finder.h"
#include "annex/common/prop_fit.h"
#include "annex/formats/haptic_format.h"
#include "annex/formats/scene_format.h"
#include "annex/runtime/annex_session.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/plane_candidates.h"
#include "annex/runtime/scanner.h"
#include "annex/runtime/overlay_labels.h"
#include "annex/runtime/renderer.h"
#include "commands.h"
#include "hmd_option.h"
#include "label_points.h"

namespace annex::cli {
namespace {

constexpr std::string_view kName = "render";

int fail(std::string_view message, int code) { return cli::fail(kName, message, code); }

// The overlays of one matched virtual object: its mesh, or its haptic primitives
// as solid shapes when the mesh cannot be loaded.
Status add_object_overlays(Renderer& renderer, const std::filesystem::path& spec_dir,
                           const VirtualObject& object, const PropFit& fit, Rgba tint,
                           std::vector<Overlay>& out) {
  std::string why = "the object names no mesh";
  if (!object.mesh.empty()) {
    auto mesh = renderer.load_mesh(spec_dir / object.mesh);
    if (mesh) {
      out.push_back(
          {*mesh, fit.world_from_model * model_from_mesh(object), {1, 1, 1, 1}, OverlayStyle::solid});
      return Ok{};
    }
    why = mesh.error().format();
  }
  std::cerr << "annex-runtime render: note: " << object.name << ": " << why
            << "; drawing its haptic primitives instead\n";
  for (const Primitive& p : object.primitives) {
    std::vector<double> dims;
    for (const Dimension& d : p.dimensions) dims.push_back(d.value_m);
    auto id = renderer.add_mesh(primitive_mesh(p.kind, dims), object.name + "/" + p.name);
    if (!id) return id.error();
    out.push_back(
        {*id, fit.world_from_model * affine_from_pose(p.pose), tint, OverlayStyle::solid});
  }
  return Ok{};
}

Status add_wireframes(Renderer& renderer, const PhysicalScene& scene,
                      const std::vector<bool>& matched, std::vector<Overlay>& out) {
  for (std::size_t i = 0; i < scene.objects.size(); ++i)
    for (const PhysicalPrimitive& p : scene.objects[i].primitives) {
      auto id = renderer.add_mesh(primitive_mesh(p.kind, p.dimensions_m, 20), scene.objects[i].id);
      if (!id) return id.error();
      const Rgba colour = matched[i] ? Rgba{0.45f, 0.95f, 0.55f, 1} : Rgba{0.6f, 0.6f, 0.6f, 1};
      out.push_back({*id, world_from_physical(p), colour, OverlayStyle::wireframe});
    }
  return Ok{};
}

int run_render(const std::vector<std::string>& args) {
  const auto parsed = parse_args(kName, args,
                                 {{"stereo", "window", "points", "wireframes", "no-egl",
                                   "no-labels"},
                                  {"out", "cloud", "hmd", "repeat", "frames", "point-stride",
                                   "config"}});
  if (!parsed) return kExitBadInput;
  if (parsed->positional.size() != 2)
    return fail("expected SPEC.haptic and SCENE.scene or CLOUD.pcd (see --help)", kExitBadInput);
  const bool window = parsed->has("window");
  const auto out_path = parsed->get("out");
  if (!out_path && !window) return fail("expected --out OUT.png or --window", kExitBadInput);
  long repeat = 1, frames = 0;
  if (auto v = parsed->get("repeat")) {
    const auto n = parse_count(kName, "repeat", *v);
    if (!n) return kExitBadInput;
    repeat = std::max(1L, *n);
  }
  long point_stride = 1;
  if (auto v = parsed->get("point-stride")) {
    const auto n = parse_count(kName, "point-stride", *v);
    if (!n) return kExitBadInput;
    if (*n < 1 || *n > 64) return fail("--point-stride expects 1 to 64", kExitBadInput);
    point_stride = *n;
  }
  if (auto v = parsed->get("frames")) {
    const auto n = parse_count(kName, "frames", *v);
    if (!n) return kExitBadInput;
    frames = *n;
  }

  std::vector<Diagnostic> warnings;
  const std::filesystem::path spec_path = parsed->positional[0];
  const Result<HapticSpec> spec = read_haptic_file(spec_path, &warnings);
  // The scene: a .scene file, or a depth frame scanned first (as `match` takes it), whose
  // colour image is then the background unless --cloud names another.
  const std::string& scene_arg = parsed->positional[1];
  const bool scene_is_cloud = scene_arg.ends_with(".pcd");
  std::optional<Frame> scanned;
  int scene_failure = kExitBadInput;
  Result<PhysicalScene> scene = Error{"", {}};
  if (scene_is_cloud) {
    auto read = read_pcd(scene_arg);
    if (!read) {
      scene = read.error();
    } else {
      ScanParams scan_params;
      if (auto cfg_path = parsed->get("config")) {
        Result<ScanParams> cfg = read_scan_config_file(*cfg_path);
        if (!cfg) {
          std::cerr << cfg.error().format() << "\n";
          return kExitBadInput;
        }
        scan_params = *cfg;
      }
      Result<ScanResult> scan = scan_frame(*read, scan_params);
      if (scan) {
        scene = scene_with_surfaces(*scan);  // its flat surfaces carry virtual panels
      } else {
        Error e = scan.error();
        e.location.origin = scene_arg;
        scene = e;
        scene_failure = kExitFailure;
      }
      scanned = std::move(*read);
    }
  } else {
    scene = read_scene_file(scene_arg, &warnings);
  }
  std::optional<HmdConfig> hmd;
  if (!read_hmd_option(kName, *parsed, warnings, hmd)) return kExitBadInput;
  for (const Diagnostic& w : warnings) std::cerr << w.format() << "\n";
  if (!spec) std::cerr << spec.error().format() << "\n";
  if (!scene) std::cerr << scene.error().format() << "\n";
  if (!spec) return kExitBadInput;
  if (!scene) return scene_failure;

  std::optional<Frame> frame;
  if (scanned && !parsed->get("cloud")) frame = std::move(scanned);
  if (auto cloud = parsed->get("cloud")) {
    auto read = read_pcd(*cloud);
    if (!read) {
      std::cerr << read.error().format() << "\n";
      return kExitBadInput;
    }
    frame = std::move(*read);
  }

  // Kinect intrinsics, scaled to the recorded grid (e.g. a 320x240 recording).
  CameraIntrinsics camera;
  if (frame && frame->organized()) {
    const double sx = frame->width / 640.0, sy = frame->height / 480.0;
    camera = {frame->width,
              frame->height,
              525.0 * sx,
              525.0 * sy,
              (319.5 + 0.5) * sx - 0.5,
              (239.5 + 0.5) * sy - 0.5};
  }
  std::vector<Eye> eyes;
  if (hmd) {
    const auto pair = hmd_eyes(*hmd);
    eyes.assign(pair.begin(), pair.end());
  } else {
    eyes.push_back(sensor_eye(camera));
  }

  RendererParams params;
  params.target = window ? RenderTarget::window : RenderTarget::headless;
  // The window starts at the image's size, at most 1280 pixels wide.
  int total_width = 0, max_height = 0;
  for (const Eye& e : eyes) {
    total_width += e.intrinsics.width;
    max_height = std::max(max_height, e.intrinsics.height);
  }
  const double shrink = std::min(1.0, 1280.0 / total_width);
  params.window_width = static_cast<int>(total_width * shrink);
  params.window_height = static_cast<int>(max_height * shrink);
  params.window_title = "annex-runtime render";
  params.try_egl = !parsed->has("no-egl");
  auto renderer = Renderer::create(params);
  if (!renderer) return fail(renderer.error().message, kExitFailure);
  std::cerr << "annex-runtime render: " << renderer->backend() << "\n";

  const MatchResult match = match_objects(*spec, *scene);
  std::vector<Overlay> overlays;
  std::vector<bool> matched(scene->objects.size(), false);
  std::vector<OverlayLabel> labels;
  int colour = 0;
  for (const MatchEntry& m : match.matches) {
    const VirtualObject& v = spec->objects[m.virtual_index];
    if (!m.physical_index) {
      std::cout << "virtual-only " << v.name << "\n";
      continue;
    }
    const auto row = std::find(match.voters.begin(), match.voters.end(), m.virtual_index);
    const VoteExplanation& e = match.table[row - match.voters.begin()][*m.physical_index];
    const PhysicalObject& p = scene->objects[*m.physical_index];
    matched[*m.physical_index] = true;
    const PropFit fit =
        fit_to_prop(v.primitives[e.virtual_primitive], p.primitives[e.physical_primitive]);
    // Along the model's axes, as poses.txt has it (fit.scale is along the primitive's).
    const Vec3 s = decompose_model_transform(fit.world_from_model).scale;
    char scale[96];
    std::snprintf(scale, sizeof scale, "%.4f,%.4f,%.4f", s.x, s.y, s.z);
    std::cout << "render " << v.name << " on " << p.id << " scale=" << scale
              << (fit.clamped ? " clamped" : "") << "\n";
    char vote[32];
    std::snprintf(vote, sizeof vote, " %.2f", e.vote);
    OverlayLabel label{v.name + " on " + p.id + vote + (fit.clamped ? " clamped" : ""), {}, false};
    for (const Vec3& pt : object_label_points(spec_path.parent_path(), v))
      label.points.push_back(fit.world_from_model.apply(pt));
    labels.push_back(std::move(label));
    const Rgba tint = overlay_tint(colour++);
    if (auto st = add_object_overlays(*renderer, spec_path.parent_path(), v, fit, tint, overlays);
        !st)
      return fail(st.error().format(), kExitBadInput);
  }

  RenderScene rs;
  rs.camera = camera;
  if (frame) {
    rs.frame = &*frame;
    rs.background = frame->organized() && !parsed->has("points") ? Background::camera_image
                                                                 : Background::point_cloud;
    rs.point_stride = static_cast<int>(point_stride);
    rs.point_size_px = std::max(2.0f, static_cast<float>(point_stride));
  } else {
    rs.background = Background::clear;
  }
  if (!frame || parsed->has("wireframes")) {
    std::vector<Overlay> wires;
    if (auto st = add_wireframes(*renderer, *scene, matched, wires); !st)
      return fail(st.error().format(), kExitFailure);
    overlays.insert(overlays.begin(), wires.begin(), wires.end());
  }
  rs.overlays = std::move(overlays);

  RgbaImage image;
  std::vector<double> ms;
  for (long i = 0; i < repeat; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    if (auto st = renderer->render(rs, eyes, image); !st)
      return fail(st.error().format(), kExitFailure);
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  if (repeat > 1) {
    std::sort(ms.begin(), ms.end());
    char line[160];
    std::snprintf(line, sizeof line,
                  "render time: median %.2f ms, min %.2f ms, max %.2f ms over %ld frames (%dx%d)",
                  ms[ms.size() / 2], ms.front(), ms.back(), repeat, image.width, image.height);
    std::cout << line << "\n";
  }
  if (!parsed->has("no-labels")) draw_overlay_labels(image, eyes, labels);
  if (out_path) {
    create_parent_dirs(*out_path);
    if (auto st = write_rgba_png(*out_path, image); !st)
      return fail(st.error().format(), kExitFailure);
    std::cout << "wrote " << *out_path << " (" << image.width << "x" << image.height << ")\n";
  }
  if (window) {
    for (long i = 0; frames == 0 || i < frames; ++i) {
      auto open = renderer->present(rs, eyes);
      if (!open) return fail(open.error().format(), kExitFailure);
      if (!*open) break;
    }
  }
  return kExitOk;
}

}  // namespace

const Command kRenderCommand{
    "render", "render a spec's virtual objects fitted onto a scene's props",
    "usage: annex-runtime render SPEC.haptic (SCENE.scene | CLOUD.pcd)\n"
    "                            (--out OUT.png | --window) [--config SCAN.conf]\n"
    "                            [--cloud CLOUD.pcd] [--points] [--wireframes]\n"
    "                            [--stereo [--hmd HMD.conf]] [--repeat N] [--frames N]\n"
    "                            [--point-stride N] [--no-egl]\n"
    "\n"
    "Matches the spec to the scene (as 'match' does), fits each matched virtual object\n"
    "onto its prop (its matched primitive on the prop's, scaled per dimension within\n"
    "the developer's limits) and renders its mesh (the spec's 'mesh' path, relative to\n"
    "the spec file; without one, its haptic primitives as solid shapes). Prints\n"
    "  render <virtual-name> on <physical-id> scale=sx,sy,sz [clamped]\n"
    "  virtual-only <virtual-name>\n"
    "scale is along the model's x, y, z, as in run's poses.txt.\n"
    "With a depth frame (.pcd) the scanner runs first (see 'scan --help'; --config its\n"
    "parameters) and the frame's colour image is the background.\n"
    "\n"
    "  --out OUT.png   write the rendered image (RGBA PNG), each overlay labelled\n"
    "                  '<virtual> on <physical> <vote> [clamped]'\n"
    "  --no-labels     the image without the labels (the window has none)\n"
    "  --cloud C.pcd   draw over this frame: its colour image when organized, else its\n"
    "                  points; without it, a plain background with the scene's\n"
    "                  primitives as wireframes (matched ones green)\n"
    "  --points        draw the frame as points even when it is organized\n"
    "  --point-stride N  draw every N-th row and column of points (default 1)\n"
    "  --wireframes    draw the scene's primitives over a cloud too\n"
    "  --stereo        a side-by-side pair for a head-mounted display\n"
    "  --hmd FILE      HMD config (samples/config/hmd.conf); default: the HMD at the\n"
    "                  sensor, eyes 64 mm apart, 640x480 per eye, 60 degrees vertical\n"
    "  --window        show the image in a window until it is closed\n"
    "  --frames N      with --window, close after N frames\n"
    "  --repeat N      render N times and print the median render time\n"
    "  --no-egl        headless through a hidden GLFW window (needs DISPLAY), not EGL\n"
    "\n"
    "Headless rendering uses EGL without an X server, else a hidden GLFW window.\n"
    "Exit 0 on success, 1 when no OpenGL context can be created, 2 on bad input.\n",
    run_render};

}  // namespace annex::cli
