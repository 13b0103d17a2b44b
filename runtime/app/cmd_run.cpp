// annex-runtime run SPEC.haptic --source SRC: the runtime loop (docs/tracking.md):
// scan, vote and match, track each matched prop, write poses and overlays.
#include <algorithm>
#include <chrono>
#include <cmath>
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
#include "annex/runtime/fault_injection.h"
#include "annex/runtime/frame_grabber.h"
#include "annex/runtime/match_report.h"
#include "annex/runtime/osc_stream.h"
#include "annex/runtime/overlay_labels.h"
#include "annex/runtime/renderer.h"
#include "commands.h"
#include "depth_options.h"
#include "hmd_option.h"
#include "label_points.h"
#include "scan_options.h"

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
    if (mesh) return {{*mesh, model_from_mesh(object), {1, 1, 1, 1}}};
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

// Deletes DIR/overlay_NNNNN.png (this command's names only); returns how many.
int remove_old_overlays(const std::filesystem::path& dir) {
  int removed = 0;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const bool ours = name.size() == 17 && name.starts_with("overlay_") &&
                      name.ends_with(".png") &&
                      std::all_of(name.begin() + 8, name.begin() + 13,
                                  [](char c) { return c >= '0' && c <= '9'; });
    std::error_code rm;
    if (ours && it->is_regular_file(rm) && std::filesystem::remove(it->path(), rm)) ++removed;
  }
  return removed;
}

// Why annexable objects got no prop, one line each, from the last match that ran
// (`annexed` marks the objects that have one; empty: none has).
void explain_no_match(const HapticSpec& spec, const std::optional<PhysicalScene>& scene,
                      const std::optional<MatchResult>& match, const MatchParams& params,
                      const std::vector<bool>& annexed = {}) {
  int annexable = 0;
  for (const VirtualObject& o : spec.objects) annexable += o.annexable ? 1 : 0;
  if (annexable == 0) {
    std::cerr << "  the spec has no annexable object ('annexable yes')\n";
    return;
  }
  if (!match || !scene) {
    std::cerr << "  no scan found a support plane and objects to vote on\n";
    return;
  }
  if (scene->objects.empty()) {
    std::cerr << "  the scans found no physical object on the support plane\n";
    return;
  }
  for (size_t r = 0; r < match->voters.size(); ++r) {
    const auto vi = static_cast<size_t>(match->voters[r]);
    if (vi < annexed.size() && annexed[vi]) continue;
    const VirtualObject& v = spec.objects[vi];
    // Its candidates by vote, each with why it did not get it (at most three).
    std::vector<size_t> order;
    for (size_t j = 0; j < match->table[r].size(); ++j)
      if (match->table[r][j].vote > 0) order.push_back(j);
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return match->table[r][a].vote > match->table[r][b].vote;
    });
    std::string line;
    for (size_t k = 0; k < order.size() && k < 3; ++k) {
      const size_t j = order[k];
      std::string why = pair_rejection(v, match->table[r][j], params);
      if (why.empty()) {
        char vote[32];
        std::snprintf(vote, sizeof vote, "%.2f", match->table[r][j].vote);
        why = std::string("votes ") + vote + ", went to another object";
        for (const MatchEntry& m : match->matches)
          if (m.physical_index && static_cast<size_t>(*m.physical_index) == j)
            why = std::string("votes ") + vote + ", went to " +
                  spec.objects[static_cast<size_t>(m.virtual_index)].name;
      }
      line += (k ? "; " : "") + scene->objects[j].id + " " + why;
    }
    if (line.empty()) line = "no physical object shares one of its shapes";
    std::cerr << "  " << v.name << ": " << line << "\n";
  }
}

// "note: mug on p2 needs major_radius x2.26 (limits 0.50..1.50), ...: drawn clamped at its
// limits", per dimension of the matched primitive (boxes largest with largest, as the
// Voter compares them).
std::string clamp_note(const HapticSpec& spec, const AnnexedObject& o) {
  const Primitive& p = spec.objects[static_cast<size_t>(o.virtual_index)]
                           .primitives[static_cast<size_t>(o.virtual_primitive)];
  std::vector<int> vi(p.dimensions.size()), pi(o.physical.dimensions_m.size());
  for (size_t i = 0; i < vi.size(); ++i) vi[i] = static_cast<int>(i);
  for (size_t i = 0; i < pi.size(); ++i) pi[i] = static_cast<int>(i);
  if (p.kind == ShapeKind::box) {
    std::sort(vi.begin(), vi.end(),
              [&](int a, int b) { return p.dimensions[a].value_m > p.dimensions[b].value_m; });
    std::sort(pi.begin(), pi.end(), [&](int a, int b) {
      return o.physical.dimensions_m[a] > o.physical.dimensions_m[b];
    });
  }
  const auto names = dimension_names(p.kind);
  std::string out = "annex-runtime run: note: " + o.virtual_name + " on " + o.physical_id + " needs";
  for (size_t k = 0; k < vi.size() && k < pi.size(); ++k) {
    const Dimension& d = p.dimensions[static_cast<size_t>(vi[k])];
    const double want = o.physical.dimensions_m[static_cast<size_t>(pi[k])] / d.value_m;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s %s x%.2f (limits %.2f..%.2f)", k ? "," : "",
                  std::string(names[static_cast<size_t>(vi[k])]).c_str(), want, d.min_scale,
                  d.max_scale);
    out += buf;
  }
  return out + ": drawn clamped at its limits\n";
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
      {{"window", "stereo", "no-overlays", "no-labels", "points", "realtime", "within-limits"},
       {"source", "out", "frames", "scan-every", "release-after", "threads", "config", "hmd",
        "occlusion", "depth-scale", "intrinsics", "stream", "listen", "exclude", "inject-faults",
        "source-retries", "min-vote", "depth-noise"}});
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
       threads = params.threads, source_retries = 30;
  if (!count("frames", max_frames, 0) || !count("scan-every", scan_every, 1) ||
      !count("release-after", release, 1) || !count("threads", threads, 1) ||
      !count("source-retries", source_retries, 0))
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
  if (auto v = parsed->get("min-vote")) {
    char* end = nullptr;
    const std::string text(*v);
    params.match.min_vote = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !(params.match.min_vote >= 0) ||
        !std::isfinite(params.match.min_vote))
      return fail("--min-vote expects a finite number >= 0, got '" + text + "'", kExitBadInput);
  }
  params.match.within_limits = parsed->has("within-limits");
  params.scan_every = static_cast<int>(scan_every);
  params.release_after_frames = static_cast<int>(release);
  params.threads = static_cast<int>(threads);
  const std::optional<ScanParams> scan_params = read_scan_options(kName, *parsed);
  if (!scan_params) return kExitBadInput;
  params.scan = *scan_params;

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
  if (!read_depth_options(kName, *parsed, source_params)) return kExitBadInput;
  auto grabber = open_frame_source(*source, source_params);
  if (!grabber) {
    std::cerr << grabber.error().format() << "\n";
    return kExitBadInput;
  }
  if (auto plan_text = parsed->get("inject-faults")) {
    auto plan = parse_fault_plan(*plan_text);
    if (!plan) {
      std::cerr << plan.error().format() << "\n";
      return kExitBadInput;
    }
    *grabber = inject_faults(std::move(*grabber), std::move(*plan));
  }
  std::cerr << "annex-runtime run: " << (*grabber)->describe() << "\n";

  // Outputs.
  const auto out_dir = parsed->get("out");
  if (!out_dir && !parsed->has("window") && !parsed->has("stream") && !parsed->has("listen"))
    std::cerr << "annex-runtime run: warning: no --out DIR and no --window: nothing is saved or "
                 "shown, only the match and annexed lines are printed\n";
  if (out_dir) {
    // Overlays of an earlier, longer run would sit beside this run's as if they were its own.
    const int stale = remove_old_overlays(*out_dir);
    if (stale > 0)
      std::cerr << "annex-runtime run: note: removed " << plural(stale, "overlay PNG")
                << " of an earlier run from " << *out_dir << "\n";
  }
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
  // The OSC stream and the game's answers (docs/streaming.md).
  std::vector<std::string> stream_urls;
  for (const auto& [name, value] : parsed->options)
    if (name == "stream") stream_urls.push_back(value);
  std::optional<OscStream> stream;
  if (!stream_urls.empty()) {
    auto opened = OscStream::open(stream_urls);
    if (!opened) return fail(opened.error().format(), kExitBadInput);
    stream.emplace(std::move(*opened));
  }
  std::optional<OscListener> listener;
  if (auto url = parsed->get("listen")) {
    auto opened = OscListener::open(*url);
    if (!opened) return fail(opened.error().format(), kExitBadInput);
    listener.emplace(std::move(*opened));
    std::cerr << "annex-runtime run: listening for /annex/exclude and /annex/rescan on UDP port "
              << listener->port() << "\n";
  }
  if (auto ids = parsed->get("exclude")) {
    size_t start = 0;
    for (;;) {
      const size_t comma = ids->find(',', start);
      const std::string id = ids->substr(start, comma == std::string::npos ? comma : comma - start);
      if (id.empty() || id.find_first_of(" \t") != std::string::npos)
        return fail("--exclude expects physical ids separated by commas (p1,p3), got '" + *ids +
                        "'",
                    kExitBadInput);
      session.exclude(id);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  std::vector<std::vector<Drawable>> drawables(spec->objects.size());
  std::vector<bool> uploaded(spec->objects.size(), false);
  std::vector<std::vector<Vec3>> label_model_points(spec->objects.size());
  const bool labels = !parsed->has("no-labels");
  std::optional<CameraIntrinsics> camera;
  RgbaImage image;
  // Encoding and writing a 640x480 PNG takes longer than tracking a frame: it runs
  // beside the next frame's work, one image in flight.
  std::future<Status> png_write;
  auto finish_png = [&]() -> Status { return png_write.valid() ? png_write.get() : Status{Ok{}}; };
  std::vector<double> frame_ms, track_ms, scan_ms;
  int frames = 0, errors = 0, matches_made = 0, failed_reads = 0;
  std::optional<Error> last_scan_error;
  FrameHealthMonitor health;
  std::vector<std::string> last_state(spec->objects.size());  // per virtual object
  std::optional<MatchResult> last_match;
  std::optional<PhysicalScene> last_match_scene;
  const auto t_start = std::chrono::steady_clock::now();
  while (max_frames == 0 || frames < max_frames) {
    const auto t_read = std::chrono::steady_clock::now();
    Result<std::optional<Frame>> next = (*grabber)->next();
    const double read_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_read).count();
    if (!next) {
      std::cerr << next.error().format() << "\n";
      // A bad recorded frame is skipped; a live sensor that fails is waited for (it may
      // come back: a loose cable) until it failed --source-retries reads in a row.
      if ((*grabber)->frame_count()) {
        ++errors;
        continue;
      }
      if (++failed_reads > source_retries) {
        if (auto st = png_write.valid() ? png_write.get() : Status{Ok{}}; !st)
          std::cerr << st.error().format() << "\n";
        return fail("the source failed " + std::to_string(failed_reads) +
                        " reads in a row; giving up",
                    kExitFailure);
      }
      continue;
    }
    if (failed_reads > 0)
      std::cerr << "annex-runtime run: the source delivers again after " << failed_reads
                << (failed_reads == 1 ? " failed read\n" : " failed reads\n");
    failed_reads = 0;
    if (!*next) break;
    const Frame& frame = **next;
    const int i = frames++;
    for (const std::string& note : health.check(frame, read_s))
      std::cerr << "annex-runtime run: frame " << i << ": " << note << "\n";
    if (listener) {
      std::vector<std::string> ignored;
      for (const OscCommand& c : listener->poll(&ignored)) {
        if (c.kind == OscCommand::Kind::exclude) {
          std::cerr << "annex-runtime run: frame " << i << ": OSC asks to exclude "
                    << c.physical_id << "\n";
          session.exclude(c.physical_id);
        } else {
          std::cerr << "annex-runtime run: frame " << i << ": OSC asks for a rescan\n";
          session.rescan();
        }
      }
      for (const std::string& w : ignored) std::cerr << "annex-runtime run: warning: " << w << "\n";
    }
    const FrameReport r = session.process(frame);
    if (stream)
      for (const std::string& problem : stream->send(*spec, r))
        std::cerr << "annex-runtime run: warning: " << problem << "\n";
    for (const std::string& id : r.excluded) std::cout << "frame " << i << " exclude " << id << "\n";
    frame_ms.push_back(r.times.total_ms);
    track_ms.push_back(r.times.track_ms);
    if (r.scanned) scan_ms.push_back(r.times.scan_ms);
    if (r.scan_error) last_scan_error = r.scan_error;

    for (const std::string& name : r.released)
      std::cout << "frame " << i << " release " << name << "\n";
    // Tracking state changes of props already annexed (held, lost, back to tracking).
    for (const AnnexedObject& o : r.objects) {
      std::string& last = last_state[static_cast<size_t>(o.virtual_index)];
      const std::string state(tracking_state_name(o.track.state));
      if (o.matched_frame != frame.index && !last.empty() && state != last)
        std::cout << "frame " << i << " state " << o.virtual_name << " " << o.physical_id << " "
                  << state << "\n";
      last = state;
    }
    for (const std::string& name : r.released)
      for (size_t v = 0; v < spec->objects.size(); ++v)
        if (spec->objects[v].name == name &&
            std::none_of(r.objects.begin(), r.objects.end(),
                         [&](const AnnexedObject& o) { return o.virtual_name == name; }))
          last_state[v].clear();
    // Each frame's lines go to poses.txt and matches.txt in one write, so a run that is
    // killed leaves whole lines.
    std::string match_block;
    if (r.match) {
      last_match = r.match;
      last_match_scene = r.match_scene;
      match_block = "frame " + std::to_string(i) + "\n" +
                    format_vote_table(*spec, *r.match_scene, *r.match) + "\n";
      for (const AnnexedObject& o : r.objects) {
        if (o.matched_frame != frame.index) continue;
        ++matches_made;
        char vote[32];
        std::snprintf(vote, sizeof vote, "%.2f", o.vote);
        const char* clamped = o.fit.clamped ? " clamped" : "";
        std::cout << "frame " << i << " match " << o.virtual_name << " " << o.physical_id << " "
                  << vote << clamped << "\n";
        if (o.fit.clamped) std::cerr << clamp_note(*spec, o);
        match_block += "match " + o.virtual_name + " " + o.physical_id + " " + vote + clamped + "\n";
      }
      match_block += "\n";
    }
    if (matches.is_open() && !match_block.empty()) matches << match_block << std::flush;
    if (poses.is_open()) {
      std::string pose_block;
      for (const AnnexedObject& o : r.objects)
        pose_block += format_pose_line(i, *spec, o) + (o.fit.clamped ? " clamped" : "") + "\n";
      poses << pose_block << std::flush;
    }

    if (!renderer) continue;
    // Again when the resolution changes (the sensor switched modes).
    // The frame's own camera (as its source gave or recovered it; the Kinect's scaled to
    // the grid otherwise).
    if (!camera || camera->width != frame.width || camera->height != frame.height)
      camera = grid_intrinsics(frame);
    RenderScene rs;
    rs.frame = &frame;
    rs.camera = *camera;
    rs.background = frame.organized() && !parsed->has("points") ? Background::camera_image
                                                                : Background::point_cloud;
    rs.occlusion_margin_m = occlusion_m;
    std::vector<OverlayLabel> overlay_labels;
    for (const AnnexedObject& o : r.objects) {
      if (o.track.state == TrackingState::lost) continue;
      const auto v = static_cast<size_t>(o.virtual_index);
      if (!uploaded[v]) {
        uploaded[v] = true;
        drawables[v] = object_drawables(*renderer, spec_path.parent_path(), spec->objects[v],
                                        overlay_tint(v));
        if (labels) label_model_points[v] = object_label_points(spec_path.parent_path(), spec->objects[v]);
      }
      const Affine world = world_from_model(*spec, o);
      if (labels) {
        OverlayLabel label{overlay_label_text(o), {}, o.track.state == TrackingState::held};
        for (const Vec3& p : label_model_points[v]) label.points.push_back(world.apply(p));
        overlay_labels.push_back(std::move(label));
      }
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
      draw_overlay_labels(image, eyes, overlay_labels);
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
                "(tracking %.2f ms, scan %.2f ms over %zu scan%s)",
                frames, seconds, seconds > 0 ? frames / seconds : 0.0, median(frame_ms),
                median(track_ms), median(scan_ms), scan_ms.size(), scan_ms.size() == 1 ? "" : "s");
  std::cerr << line << "\n";
  if (matches_made == 0 && frames > 0) {
    std::cerr << "annex-runtime run: no prop was annexed";
    if (last_scan_error) std::cerr << " (last scan: " << last_scan_error->message << ")";
    std::cerr << ":\n";
    explain_no_match(*spec, last_match_scene, last_match, params.match);
  } else if (last_match) {
    std::vector<bool> annexed(spec->objects.size(), false);
    for (const AnnexedObject& o : session.objects())
      annexed[static_cast<size_t>(o.virtual_index)] = true;
    bool any = false;
    for (size_t i = 0; i < spec->objects.size(); ++i)
      any |= spec->objects[i].annexable && !annexed[i];
    if (any) {
      std::cerr << "annex-runtime run: not annexed:\n";
      explain_no_match(*spec, last_match_scene, last_match, params.match, annexed);
    }
  }
  if (stream)
    for (const OscTargetStats& t : stream->stats())
      std::cerr << "annex-runtime run: " << t.url << ": " << t.bundles_sent << " bundles sent"
                << (t.bundles_failed ? ", " + std::to_string(t.bundles_failed) +
                                           " not delivered (" + t.first_error + ")"
                                     : std::string())
                << "\n";
  for (const AnnexedObject& o : session.objects())
    std::cout << "annexed " << o.virtual_name << " " << o.physical_id
              << " state=" << tracking_state_name(o.track.state)
              << (o.fit.clamped ? " clamped" : "") << "\n";
  if (frames == 0) return fail("the source delivered no frame", kExitFailure);
  return errors > 0 && errors == frames ? kExitFailure : kExitOk;
}

}  // namespace

extern const Command kRunCommand = {
    "run", "annex a scene live or from a recording: match, track, overlay",
    "usage: annex-runtime run SPEC.haptic --source SRC [--out DIR] [--window]\n"
    "                         [--stereo [--hmd HMD.conf]] [--frames N] [--scan-every K]\n"
    "                         [--release-after N] [--threads N] [--config SCAN.conf]\n"
    "                         [--depth-noise NAME]\n"
    "                         [--no-overlays] [--no-labels] [--points] [--occlusion M]\n"
    "                         [--realtime]\n"
    "                         [--depth-scale S] [--intrinsics fx,fy,cx,cy]\n"
    "                         [--stream osc.udp://HOST:PORT]... [--listen osc.udp://:PORT]\n"
    "                         [--exclude ID[,ID...]] [--inject-faults PLAN]\n"
    "                         [--source-retries N]\n"
    "                         [--min-vote X] [--within-limits]\n"
    "\n"
    "SRC is a .pcd file, a directory of .pcd frames (name order), a TUM RGB-D sequence\n"
    "(a directory with depth.txt and rgb.txt), a directory of 16-bit depth PNGs or one,\n"
    "an .oni recording, 'openni2' (the first device) or 'openni2:URI'. Scans frames until props "
    "are found,\n"
    "votes and matches (as 'match' does), then tracks each matched prop (ICP in a cube\n"
    "around its last pose; re-initialised after 5 failed frames) and keeps scanning\n"
    "every K frames: virtual objects without a prop vote again, new props are picked\n"
    "up, and a prop lost for N frames is released. Prints\n"
    "  frame <i> match <virtual-name> <physical-id> <vote> [clamped]\n"
    "  frame <i> release <virtual-name>\n"
    "  frame <i> exclude <physical-id>                      (an exclusion takes effect)\n"
    "  frame <i> state <virtual-name> <physical-id> <state> (a track's state changed)\n"
    "  annexed <virtual-name> <physical-id> state=<state>      [clamped]  (at the end)\n"
    "'clamped': the prop needs the model scaled beyond its scaling limits; it is drawn\n"
    "at the limits (a note on stderr gives the scales). When nothing is annexed, stderr\n"
    "says why for each annexable object.\n"
    "\n"
    "  --out DIR         write DIR/poses.txt (one line per frame per annexed object:\n"
    "                    frame <i> <virtual> <physical> state=<tracking|held|reinit|lost>\n"
    "                    t=x,y,z q=w,x,y,z scale=sx,sy,sz conf=c [clamped], the model's transform\n"
    "                    in the sensor frame and the tracking confidence in [0, 1]),\n"
    "                    DIR/matches.txt (the vote table of every match)\n"
    "                    and DIR/overlay_NNNNN.png (each virtual model on its prop,\n"
    "                    labelled '<virtual> on <physical> <vote> [clamped] <state>')\n"
    "  --window          show the overlays live in a window\n"
    "  --stereo          render side-by-side pairs for a head-mounted display\n"
    "  --hmd FILE        HMD config (samples/config/hmd.conf) for --stereo\n"
    "  --frames N        stop after N frames (0: until the source ends)\n"
    "  --scan-every K    frames between scans once something is matched (default 10)\n"
    "  --release-after N lost frames before a prop is released (default 45)\n"
    "  --threads N       trackers running at once (default 2)\n"
    "  --config FILE     scan parameters (samples/config/scan.conf)\n"
    "  --depth-noise NAME the depth camera's noise: kinect (the default), stereo\n"
    "                    (RealSense D400) or tof (Kinect v2, Azure Kinect); the scan,\n"
    "                    the trackers and the camera's motion count in it\n"
    "  --no-overlays     with --out, write only poses.txt and matches.txt\n"
    "  --no-labels       overlay PNGs without the labels (the window has none)\n"
    "  --points          draw the frame as points rather than as the colour image\n"
    "  --occlusion M     over the colour image, real surfaces more than M metres in\n"
    "                    front of a virtual model hide it (a hand; its prop, within M,\n"
    "                    does not); without it the models are drawn over everything\n"
    "  --realtime        deliver recorded frames at their recorded rate\n"
    "  --depth-scale S   depth PNG value per metre (default 1000; a TUM sequence 5000)\n"
    "  --intrinsics LIST depth PNG camera fx,fy,cx,cy (default the Kinect's)\n"
    "  --stream URL      send every frame as one OSC bundle to URL, osc.udp://HOST:PORT\n"
    "                    (repeatable; docs/streaming.md): /annex/frame, /annex/object per\n"
    "                    annexed object, /annex/released, /annex/excluded. A target that\n"
    "                    cannot be reached is reported once; the run goes on\n"
    "  --listen URL      receive /annex/exclude <physical-id> and /annex/rescan on\n"
    "                    osc.udp://:PORT\n"
    "  --exclude IDS     props never to annex (p1,p3: ids as the first scan gives them);\n"
    "                    an excluded prop is released if annexed and never voted on\n"
    "                    again while it stays in view\n"
    "  --inject-faults PLAN  test the loop against sensor faults, e.g.\n"
    "                    stall@3:500,drop@5-6,nan@8-20,halfres@30-34,disconnect@40-45\n"
    "                    (numbers count reads of the source; docs/reliability.md)\n"
    "  --source-retries N  failed reads in a row of a live source before giving up\n"
    "                    (default 30)\n"
    "  --min-vote X      never match a pair voting X or less (default 0; a spec's\n"
    "                    per-object 'min_vote' also applies)\n"
    "  --within-limits   never match a prop that needs a dimension scaled beyond its\n"
    "                    scaling limits (default: match it and draw the model clamped)\n"
    "\n"
    "Exit 0 on success, 1 when the source fails (a live sensor that failed --source-retries\n"
    "reads in a row, no frame) or no OpenGL context exists for --window, 2 on bad\n"
    "arguments or input.\n",
    run_run};

}  // namespace annex::cli
