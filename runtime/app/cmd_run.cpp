// annex-runtime run SPEC.haptic --source SRC: the runtime loop (docs/tracking.md):
// scan, vote and match, track each matched prop, write poses and overlays.
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <iostream>
#include <string>
#include <vector>

#include "annex/formats/haptic_format.h"
#include "annex/runtime/annex_session.h"
#include "annex/runtime/frame_grabber.h"
#include "annex/runtime/match_report.h"
#include "annex/runtime/renderer.h"
#include "annex/runtime/target_volume_segmenter.h"
#include "commands.h"
#include "hmd_option.h"

namespace annex::cli {
namespace {

constexpr std::string_view kName = "run";

int fail(std::string_view message, int code) { return cli::fail(kName, message, code); }

// A virtual object's drawables in model coordinates: its mesh, or its haptic
// primitives when the mesh cannot be loaded (uploaded once, on its first match).
struct Drawable {
  MeshId mesh;
  Affine model_from_part;
  Rgba tint;
};

std::vector<Drawable> object_drawables(Renderer& renderer, const std::filesystem::path& spec_dir,
                                       const VirtualObject& object, Rgba tint) {
  std::string why = "the object names no mesh";
  if (!object.mesh.empty()) {
    auto mesh = renderer.load_mesh(spec_dir / object.mesh);
    if (mesh) return {{*mesh, Affine{}, {1, 1, 1, 1}}};
    why = mesh.error().format();
  }
  std::cerr << "annex-runtime run: note: " << object.name << ": " << why
            << "; drawing its haptic primitives instead\n";
  std::vector<Drawable> out;
  for (const Primitive& p : object.primitives) {
    std::vector<double> dims;
    for (const Dimension& d : p.dimensions) dims.push_back(d.value_m);
    auto id = renderer.add_mesh(primitive_mesh(p.kind, dims), object.name + "/" + p.name);
    if (id) out.push_back({*id, affine_from_pose(p.pose), tint});
  }
  return out;
}

std::string frame_name(int i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "overlay_%05d.png", i);
  return buf;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int run_run(const std::vector<std::string>& args) {
  const auto parsed = parse_args(
      kName, args,
      {{"window", "stereo", "no-overlays", "points", "realtime"},
       {"source", "out", "frames", "scan-every", "release-after", "threads", "config", "hmd",
        "occlusion"}});
  if (!parsed) return kExitBadInput;
  if (parsed->positional.size() != 1)
    return fail("expected one SPEC.haptic (see --help)", kExitBadInput);
  const auto source = parsed->get("source");
  if (!source)
    return fail("expected --source SRC (a .pcd file, a directory, a .oni file or openni2)",
                kExitBadInput);
  SessionParams params;
  long max_frames = 0;
  auto count = [&](std::string_view name, long& out, long min) {
    if (auto v = parsed->get(name)) {
      const auto n = parse_count(kName, name, *v);
      if (!n) return false;
      if (*n < min) {
        std::cerr << "annex-runtime run: error: --" << name << " must be at least " << min << "\n";
        return false;
      }
      out = *n;
    }
    return true;
  };
  long scan_every = params.scan_every, release = params.release_after_frames,
       threads = params.threads;
  if (!count("frames", max_frames, 0) || !count("scan-every", scan_every, 1) ||
      !count("release-after", release, 1) || !count("threads", threads, 1))
    return kExitBadInput;
  double occlusion_m = -1;
  if (auto v = parsed->get("occlusion")) {
    char* end = nullptr;
    const std::string text(*v);
    occlusion_m = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !(occlusion_m >= 0) || occlusion_m > 1)
      return fail("--occlusion expects a margin in metres from 0 to 1, got '" + text + "'",
                  kExitBadInput);
  }
  params.scan_every = static_cast<int>(scan_every);
  params.release_after_frames = static_cast<int>(release);
  params.threads = static_cast<int>(threads);
  if (auto path = parsed->get("config")) {
    Result<ScanParams> cfg = read_scan_config_file(*path);
    if (!cfg) {
      std::cerr << cfg.error().format() << "\n";
      return kExitBadInput;
    }
    params.scan = *cfg;
  }

  std::vector<Diagnostic> warnings;
  const std::filesystem::path spec_path = parsed->positional[0];
  Result<HapticSpec> spec = read_haptic_file(spec_path, &warnings);
  std::optional<HmdConfig> hmd;
  if (!read_hmd_option(kName, *parsed, warnings, hmd)) return kExitBadInput;
  for (const Diagnostic& w : warnings) std::cerr << w.format() << "\n";
  if (!spec) {
    std::cerr << spec.error().format() << "\n";
    return kExitBadInput;
  }

  FrameSourceParams source_params;
  if (parsed->has("realtime")) source_params.pacing = Pacing::recorded_rate;
  auto grabber = open_frame_source(*source, source_params);
  if (!grabber) {
    std::cerr << grabber.error().format() << "\n";
    return kExitBadInput;
  }
  std::cerr << "annex-runtime run: " << (*grabber)->describe() << "\n";

  // Outputs.
  const auto out_dir = parsed->get("out");
  std::ofstream poses, matches;
  if (out_dir) {
    std::error_code ec;
    std::filesystem::create_directories(*out_dir, ec);
    if (ec) return fail("cannot create '" + *out_dir + "': " + ec.message(), kExitBadInput);
    poses.open(std::filesystem::path(*out_dir) / "poses.txt");
    matches.open(std::filesystem::path(*out_dir) / "matches.txt");
    if (!poses || !matches) return fail("cannot write into '" + *out_dir + "'", kExitBadInput);
  }
  const bool window = parsed->has("window");
  const bool overlays = window || (out_dir && !parsed->has("no-overlays"));
  std::optional<Renderer> renderer;
  if (overlays) {
    RendererParams rp;
    rp.target = window ? RenderTarget::window : RenderTarget::headless;
    auto created = Renderer::create(rp);
    if (!created) {
      if (window) return fail(created.error().message, kExitFailure);
      std::cerr << "annex-runtime run: warning: no overlay images: " << created.error().message
                << "\n";
    } else {
      std::cerr << "annex-runtime run: " << created->backend() << "\n";
      renderer.emplace(std::move(*created));
    }
  }

  AnnexSession session(*spec, params);
  std::vector<std::vector<Drawable>> drawables(spec->objects.size());
  std::vector<bool> uploaded(spec->objects.size(), false);
  std::optional<CameraIntrinsics> camera;
  RgbaImage image;
  // Encoding and writing a 640x480 PNG takes longer than tracking a frame: it runs
  // beside the next frame's work, one image in flight.
  std::future<Status> png_write;
  auto finish_png = [&]() -> Status { return png_write.valid() ? png_write.get() : Status{Ok{}}; };
  std::vector<double> frame_ms, track_ms, scan_ms;
  int frames = 0, errors = 0, matches_made = 0;
  std::optional<Error> last_scan_error;
  const auto t_start = std::chrono::steady_clock::now();
  while (max_frames == 0 || frames < max_frames) {
    Result<std::optional<Frame>> next = (*grabber)->next();
    if (!next) {
      std::cerr << next.error().format() << "\n";
      // A live sensor that fails is gone; a bad recorded frame is skipped.
      if (!(*grabber)->frame_count()) return kExitFailure;
      ++errors;
      continue;
    }
    if (!*next) break;
    const Frame& frame = **next;
    const int i = frames++;
    const FrameReport r = session.process(frame);
    frame_ms.push_back(r.times.total_ms);
    track_ms.push_back(r.times.track_ms);
    if (r.scanned) scan_ms.push_back(r.times.scan_ms);
    if (r.scan_error) last_scan_error = r.scan_error;

    for (const std::string& name : r.released)
      std::cout << "frame " << i << " release " << name << "\n";
    if (r.match) {
      if (matches.is_open())
        matches << "frame " << i << "\n"
                << format_vote_table(*spec, *r.match_scene, *r.match) << "\n";
      for (const AnnexedObject& o : r.objects) {
        if (o.matched_frame != frame.index) continue;
        ++matches_made;
        char vote[32];
        std::snprintf(vote, sizeof vote, "%.2f", o.vote);
        std::cout << "frame " << i << " match " << o.virtual_name << " " << o.physical_id << " "
                  << vote << "\n";
        if (matches.is_open())
          matches << "match " << o.virtual_name << " " << o.physical_id << " " << vote << "\n";
      }
      if (matches.is_open()) matches << "\n";
    }
    if (poses.is_open())
      for (const AnnexedObject& o : r.objects) poses << format_pose_line(i, *spec, o) << "\n";

    if (!renderer) continue;
    if (!camera) {
      if (auto k = estimate_intrinsics(frame))
        camera = *k;
      else
        camera = CameraIntrinsics{};
    }
    RenderScene rs;
    rs.frame = &frame;
    rs.camera = *camera;
    rs.background = frame.organized() && !parsed->has("points") ? Background::camera_image
                                                                : Background::point_cloud;
    rs.occlusion_margin_m = occlusion_m;
    for (const AnnexedObject& o : r.objects) {
      if (o.track.state == TrackingState::lost) continue;
      const auto v = static_cast<size_t>(o.virtual_index);
      if (!uploaded[v]) {
        uploaded[v] = true;
        drawables[v] = object_drawables(*renderer, spec_path.parent_path(), spec->objects[v],
                                        overlay_tint(v));
      }
      const Affine world = world_from_model(*spec, o);
      for (const Drawable& d : drawables[v]) {
        Rgba tint = d.tint;
        if (o.track.state == TrackingState::held) tint.a = 0.5f;  // the pose is a guess
        rs.overlays.push_back({d.mesh, world * d.model_from_part, tint, OverlayStyle::solid});
      }
    }
    std::vector<Eye> eyes;
    if (hmd) {
      const auto pair = hmd_eyes(*hmd);
      eyes.assign(pair.begin(), pair.end());
    } else {
      eyes.push_back(sensor_eye(rs.camera));
    }
    if (window) {
      auto open = renderer->present(rs, eyes);
      if (!open) return fail(open.error().format(), kExitFailure);
      if (!*open) break;
    }
    if (out_dir && !parsed->has("no-overlays")) {
      if (auto st = renderer->render(rs, eyes, image); !st)
        return fail(st.error().format(), kExitFailure);
      if (auto st = finish_png(); !st) return fail(st.error().format(), kExitFailure);
      png_write = std::async(std::launch::async,
                             [img = std::move(image),
                              path = std::filesystem::path(*out_dir) / frame_name(i)] {
                               return write_rgba_png(path, img);
                             });
    }
  }
  if (auto st = finish_png(); !st) return fail(st.error().format(), kExitFailure);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  char line[256];
  std::snprintf(line, sizeof line,
                "annex-runtime run: %d frames in %.2f s (%.1f fps); median per frame %.2f ms "
                "(tracking %.2f ms, scan %.2f ms over %zu scans)",
                frames, seconds, seconds > 0 ? frames / seconds : 0.0, median(frame_ms),
                median(track_ms), median(scan_ms), scan_ms.size());
  std::cerr << line << "\n";
  if (matches_made == 0 && frames > 0) {
    std::cerr << "annex-runtime run: no prop was annexed";
    if (last_scan_error) std::cerr << " (last scan: " << last_scan_error->message << ")";
    std::cerr << "\n";
  }
  for (const AnnexedObject& o : session.objects())
    std::cout << "annexed " << o.virtual_name << " " << o.physical_id
              << " state=" << tracking_state_name(o.track.state) << "\n";
  if (frames == 0) return fail("the source delivered no frame", kExitFailure);
  return errors > 0 && errors == frames ? kExitFailure : kExitOk;
}

}  // namespace

extern const Command kRunCommand = {
    "run", "annex a scene live or from a recording: match, track, overlay",
    "usage: annex-runtime run SPEC.haptic --source SRC [--out DIR] [--window]\n"
    "                         [--stereo [--hmd HMD.conf]] [--frames N] [--scan-every K]\n"
    "                         [--release-after N] [--threads N] [--config SCAN.conf]\n"
    "                         [--no-overlays] [--points] [--occlusion M] [--realtime]\n"
    "\n"
    "SRC is a .pcd file, a directory of .pcd frames (name order), an .oni recording,\n"
    "'openni2' (the first device) or 'openni2:URI'. Scans frames until props are found,\n"
    "votes and matches (as 'match' does), then tracks each matched prop (ICP in a cube\n"
    "around its last pose; re-initialised after 5 failed frames) and keeps scanning\n"
    "every K frames: virtual objects without a prop vote again, new props are picked\n"
    "up, and a prop lost for N frames is released. Prints\n"
    "  frame <i> match <virtual-name> <physical-id> <vote>\n"
    "  frame <i> release <virtual-name>\n"
    "  annexed <virtual-name> <physical-id> state=<state>      (at the end)\n"
    "\n"
    "  --out DIR         write DIR/poses.txt (one line per frame per annexed object:\n"
    "                    frame <i> <virtual> <physical> state=<tracking|held|reinit|lost>\n"
    "                    t=x,y,z q=w,x,y,z scale=sx,sy,sz conf=c, the model's transform\n"
    "                    in the sensor frame and the tracking confidence in [0, 1]),\n"
    "                    DIR/matches.txt (the vote table of every match)\n"
    "                    and DIR/overlay_NNNNN.png (each virtual model on its prop)\n"
    "  --window          show the overlays live in a window\n"
    "  --stereo          render side-by-side pairs for a head-mounted display\n"
    "  --hmd FILE        HMD config (samples/config/hmd.conf) for --stereo\n"
    "  --frames N        stop after N frames (0: until the source ends)\n"
    "  --scan-every K    frames between scans once something is matched (default 10)\n"
    "  --release-after N lost frames before a prop is released (default 45)\n"
    "  --threads N       trackers running at once (default 2)\n"
    "  --config FILE     scan parameters (samples/config/scan.conf)\n"
    "  --no-overlays     with --out, write only poses.txt and matches.txt\n"
    "  --points          draw the frame as points rather than as the colour image\n"
    "  --occlusion M     over the colour image, real surfaces more than M metres in\n"
    "                    front of a virtual model hide it (a hand; its prop, within M,\n"
    "                    does not); without it the models are drawn over everything\n"
    "  --realtime        deliver recorded frames at their recorded rate\n"
    "\n"
    "Exit 0 on success, 1 when the source fails (a lost sensor, no frame) or no OpenGL\n"
    "context exists for --window, 2 on bad arguments or input.\n",
    run_run};

}  // namespace annex::cli
