#include "editor_app.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <numeric>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include "annex/formats/text_lexer.h"
#include "annex/authoring/fit.h"
#include "annex/formats/file_io.h"
#include "annex/formats/scene_format.h"
#include "panels.h"
#include "view.h"

namespace annex::authoring {

namespace fs = std::filesystem;

namespace {

constexpr double kAutosaveSeconds = 20.0;

const char* kUsage =
    "usage: annex-author [FILE.haptic] [--script FILE] [--size WIDTHxHEIGHT] [--samples N]\n"
    "\n"
    "The Annex haptic-model editor (docs/editor.md).\n"
    "  --script FILE   run editor commands from FILE with no person, then exit\n"
    "                  (exit 0: all lines ran; 1: a line failed)\n"
    "  --size WxH      window size in pixels (default 1600x900)\n"
    "  --samples N     multisample anti-aliasing samples, 0 for none (default 4)\n"
    "  --version       print the version\n";

fs::path recent_file() {
  return state_dir() / "recent.txt";
}

std::string find_samples_dir() {
  if (const char* env = std::getenv("ANNEX_SAMPLES_DIR"); env != nullptr && *env != '\0')
    return env;
  std::error_code ec;
  // The checkout the editor was started in comes before the source tree compiled in,
  // which may be another checkout (or gone): the dialogs open where the user works.
  if (fs::is_directory("samples/models", ec))
    return fs::absolute("samples", ec).lexically_normal().string();
#ifdef ANNEX_SAMPLES_DIR
  if (fs::is_directory(ANNEX_SAMPLES_DIR, ec)) return ANNEX_SAMPLES_DIR;
#endif
  return fs::absolute("samples", ec).string();
}

bool on_off(const std::string& word, bool& out) {
  if (word == "on" || word == "true" || word == "yes")
    out = true;
  else if (word == "off" || word == "false" || word == "no")
    out = false;
  else
    return false;
  return true;
}

// annex-runtime beside this executable (build tree: ../runtime/annex-runtime), or
// $ANNEX_RUNTIME, or on the PATH; kept only if it has the `run` command.
std::string find_runtime() {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("ANNEX_RUNTIME"); env != nullptr && *env != '\0')
    candidates.push_back(env);
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    candidates.push_back((self.parent_path().parent_path() / "runtime" / "annex-runtime").string());
    candidates.push_back((self.parent_path() / "annex-runtime").string());
  }
  candidates.push_back("annex-runtime");
  for (const std::string& c : candidates) {
    if (c.find('/') != std::string::npos && !fs::is_regular_file(c, ec)) continue;
    const std::string probe = "'" + c + "' run --help > /dev/null 2>&1";
    if (std::system(probe.c_str()) == 0) return c;
  }
  return {};
}

}  // namespace

std::optional<AppOptions> parse_options(int argc, char** argv, int& exit_code) {
  AppOptions o;
  exit_code = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      return std::nullopt;
    }
    if (a == "--version") {
#ifdef ANNEX_VERSION
      std::cout << "annex-author " << ANNEX_VERSION << "\n";
#endif
      return std::nullopt;
    }
    if (a == "--script" || a == "--size" || a == "--samples") {
      if (i + 1 >= argc) {
        std::cerr << "annex-author: error: " << a << " needs a value\n" << kUsage;
        exit_code = 2;
        return std::nullopt;
      }
      const std::string v = argv[++i];
      if (a == "--script") {
        o.script_path = v;
      } else if (a == "--samples") {
        double n = 0;
        if (!parse_double(v, n) || n < 0 || n > 16 || n != static_cast<int>(n)) {
          std::cerr << "annex-author: error: --samples wants a whole number from 0 to 16\n";
          exit_code = 2;
          return std::nullopt;
        }
        o.samples = static_cast<int>(n);
      } else {
        const auto x = v.find('x');
        const int w = x == std::string::npos ? 0 : std::atoi(v.substr(0, x).c_str());
        const int h = x == std::string::npos ? 0 : std::atoi(v.substr(x + 1).c_str());
        if (w < 320 || h < 240 || w > 8192 || h > 8192) {
          std::cerr << "annex-author: error: --size wants WIDTHxHEIGHT, at least 320x240\n";
          exit_code = 2;
          return std::nullopt;
        }
        o.width = w;
        o.height = h;
      }
    } else if (a.starts_with("-")) {
      std::cerr << "annex-author: error: unknown option '" << a << "'\n" << kUsage;
      exit_code = 2;
      return std::nullopt;
    } else if (o.open_path.empty()) {
      o.open_path = a;
    } else {
      std::cerr << "annex-author: error: one spec at a time\n" << kUsage;
      exit_code = 2;
      return std::nullopt;
    }
  }
  return o;
}

EditorApp::EditorApp(AppOptions options) : options_(std::move(options)) {
  ui_.samples_dir = find_samples_dir();
  ui_.layout.viewport =
      compute_layout(static_cast<float>(options_.width), static_cast<float>(options_.height), 19.f)
          .viewport;
  last_autosave_ = std::chrono::steady_clock::now();
  if (!scripted()) {
    ui_.recent = read_recent(recent_file());
    ui_.runtime_path = find_runtime();
  }
  if (scripted()) {
    auto text = read_text_file(options_.script_path);
    if (!text) {
      fail_script(text.error().format());
      return;
    }
    auto lines = parse_script(*text, options_.script_path);
    if (!lines) {
      fail_script(lines.error().format());
      return;
    }
    script_ = std::move(lines).value();
  }
  if (!options_.open_path.empty()) {
    if (!scripted() && has_recovery(options_.open_path)) {
      ui_.prompts.recover = options_.open_path;
      ui_.prompts.recover_open_requested = true;
    } else {
      queue_.request(AppAction::Kind::open, options_.open_path);
      queue_.actions.back().confirmed = true;
    }
  } else if (!scripted() && has_untitled_recovery()) {
    ui_.prompts.recover = "";
    ui_.prompts.recover_open_requested = true;
  }
  const std::string library = ui_.samples_dir + "/library/household.scene";
  if (fs::exists(library)) open_scene(library);
}

void EditorApp::fail_script(const std::string& message) {
  std::cerr << message << "\n";
  exit_code_ = 1;
  done_ = true;
}

void EditorApp::request_quit() {
  queue_.request(AppAction::Kind::quit);
}

void EditorApp::open_scene(const std::string& path) {
  ui_.scene_path = path;
  ui_.scene.reset();
  ui_.scene_error.clear();
  auto scene = read_scene_file(path);
  if (scene)
    ui_.scene = std::move(scene).value();
  else
    ui_.scene_error = scene.error().format();
  ui_.preview_dirty = true;
}

void EditorApp::add_recent(const std::string& path) {
  if (scripted()) return;  // scripts must not rewrite the user's list
  ui_.recent = authoring::add_recent(ui_.recent, path);
  if (Status s = write_recent(recent_file(), ui_.recent); !s) ui_.status = s.error().format();
}

void EditorApp::open_document(const std::string& path, bool recover, Renderer& renderer) {
  auto opened = path.empty() && recover ? EditorDocument::recover_untitled()
                                        : EditorDocument::open(path, recover);
  if (!opened) {
    // Nothing opens: the document stays as it was and a modal shows the whole error.
    ui_.status = "Not opened: " + opened.error().format();
    ui_.prompts.open_error = opened.error().format();
    ui_.prompts.open_error_requested = true;
    if (scripted()) fail_script(opened.error().format());
    return;
  }
  doc_ = std::move(opened).value();
  renderer.clear_meshes();
  ui_.box_points.clear();
  ui_.box_normals.clear();
  ui_.box_object = -1;
  ui_.preview_dirty = true;
  if (!path.empty()) add_recent(path);
  frame_all(doc_, ui_);
  ui_.status = recover ? "Recovered the autosave: save to keep it." : "Opened " + path;
  log_document_notes();
}

void EditorApp::log_document_notes() {
  for (const std::string& note : doc_.take_log()) {
    std::cerr << "annex-author: " << note << "\n";
    ui_.status += "; " + note;
  }
}

void EditorApp::run_action(const AppAction& a, Renderer& renderer) {
  using K = AppAction::Kind;
  const bool guarded = a.kind == K::new_document || a.kind == K::open || a.kind == K::quit;
  if (guarded && doc_.dirty() && !a.confirmed && !scripted()) {
    ui_.prompts.unsaved = a;
    ui_.prompts.unsaved_open_requested = true;
    return;
  }
  switch (a.kind) {
    case K::new_document:
      doc_.remove_autosave();
      doc_ = EditorDocument{};
      renderer.clear_meshes();
      ui_.preview_dirty = true;
      ui_.status = "New spec";
      break;
    case K::open:
      if (!scripted() && has_recovery(a.path)) {
        ui_.prompts.recover = a.path;
        ui_.prompts.recover_open_requested = true;
      } else {
        if (doc_.dirty()) doc_.remove_autosave();  // the user chose not to save
        open_document(a.path, false, renderer);
      }
      break;
    case K::recover:
      open_document(a.path, true, renderer);
      break;
    case K::discard_recovery:
      if (a.path.empty()) {
        std::error_code ec;
        fs::remove(state_dir() / "untitled.haptic.autosave", ec);
      } else {
        std::error_code ec;
        fs::remove(autosave_path_for(a.path), ec);
        open_document(a.path, false, renderer);
      }
      break;
    case K::save:
    case K::save_as: {
      const Status s = a.kind == K::save ? doc_.save() : doc_.save_as(a.path);
      ui_.status = s ? "Saved " + doc_.path().string() : "Not saved: " + s.error().format();
      log_document_notes();
      if (s) add_recent(doc_.path().string());
      break;
    }
    case K::import_mesh: {
      const Status s = doc_.apply(cmd::ImportMesh{doc_.mesh_reference(a.path), ""});
      doc_.apply(cmd::EndEdit{});
      ui_.status = s ? "Imported " + a.path : s.error().format();
      if (s) frame_all(doc_, ui_);
      break;
    }
    case K::open_scene:
      open_scene(a.path);
      break;
    case K::fit_view:
      frame_all(doc_, ui_);
      break;
    case K::choose_source:
      ui_.runtime_source = a.path;
      break;
    case K::run_preview:
      start_runtime_preview();
      break;
    case K::quit:
      // Quitting without saving discards the edits, autosave included.
      doc_.remove_autosave();
      done_ = true;
      break;
  }
}

int EditorApp::start_runtime_preview(int frames, bool wait) {
  if (ui_.runtime_path.empty() || doc_.path().empty() || doc_.dirty() || ui_.runtime_source.empty())
    return -1;
  if (runtime_pid_ > 0) {
    ui_.status = "annex-runtime run is already running (pid " + std::to_string(runtime_pid_) + ")";
    return -1;
  }
  // A child process with its own window: the editor stays responsive, and a crash of
  // the runtime cannot take the document with it.
  std::vector<std::string> args{ui_.runtime_path,   "run",     doc_.path().string(), "--source",
                                ui_.runtime_source, "--window"};
  if (frames > 0) {
    args.push_back("--frames");
    args.push_back(std::to_string(frames));
  }
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int err = posix_spawnp(&pid, args[0].c_str(), nullptr, nullptr, argv.data(), environ);
  if (err != 0) {
    ui_.status = "cannot start annex-runtime run: " + std::string(std::strerror(err));
    return -1;
  }
  if (wait) {
    int wstatus = 0;
    if (waitpid(pid, &wstatus, 0) != pid) return -1;
    return WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
  }
  runtime_pid_ = pid;
  ui_.status = "annex-runtime run started (pid " + std::to_string(pid) + ")";
  return 0;
}

void EditorApp::apply_queue(Renderer& renderer) {
  // Commands first (they were made against this frame's document), then actions.
  CommandQueue q;
  std::swap(q, queue_);
  for (const Command& c : q.commands)
    if (Status s = doc_.apply(c); !s) ui_.status = s.error().message;
  for (const AppAction& a : q.actions) run_action(a, renderer);
  if (clear_meshes_) {
    renderer.clear_meshes();
    clear_meshes_ = false;
  }
}

bool EditorApp::run_view_command(const ScriptLine& line) {
  const auto& w = line.words;
  const std::string& verb = w[0];
  auto fail = [&](const std::string& message) {
    fail_script(options_.script_path + ":" + std::to_string(line.line) + ": error: " + message);
  };
  auto count = [&](std::size_t i, int& out) {
    double v = 0;
    if (i >= w.size() || !parse_double(w[i], v) || v < 1 || v > 100000 ||
        v != static_cast<int>(v)) {
      fail("'" + verb + "' needs a whole number of frames");
      return false;
    }
    out = static_cast<int>(v);
    return true;
  };
  if (verb == "screenshot") {
    if (w.size() != 2) return fail("usage: screenshot FILE.png"), true;
    capture_path_ = w[1];
    pending_frames_ = 3;  // auto-sized ImGui windows settle within two frames
  } else if (verb == "frames") {
    int n = 0;
    if (count(1, n)) pending_frames_ = n;
  } else if (verb == "bench") {
    int n = 0;
    if (count(1, n)) {
      pending_frames_ = n;
      benching_ = true;
      bench_ms_.clear();
      bench_cpu_start_ = std::clock();
    }
  } else if (verb == "scene") {
    if (w.size() != 2) return fail("usage: scene FILE.scene"), true;
    open_scene(w[1]);
    if (!ui_.scene) fail(ui_.scene_error);
  } else if (verb == "camera") {
    double yaw = 0, pitch = 0, dist = 0;
    if (w.size() != 4 || !parse_double(w[1], yaw) || !parse_double(w[2], pitch) ||
        !parse_double(w[3], dist) || dist <= 0)
      return fail("usage: camera YAW_DEG PITCH_DEG DISTANCE_M"), true;
    ui_.camera.yaw_deg = static_cast<float>(yaw);
    ui_.camera.pitch_deg = static_cast<float>(std::clamp(pitch, -89.0, 89.0));
    ui_.camera.distance_m = static_cast<float>(dist);
  } else if (verb == "frame_all") {
    frame_all(doc_, ui_);
  } else if (verb == "frame_selected") {
    frame_selected(doc_, ui_);
  } else if (verb == "limits_preview" || verb == "rank_mode" || verb == "wireframes" ||
             verb == "grid") {
    bool* flag = verb == "limits_preview" ? &ui_.limits_preview
                 : verb == "rank_mode"    ? &ui_.rank_mode
                 : verb == "wireframes"   ? &ui_.show_wireframes
                                          : &ui_.show_grid;
    if (w.size() != 2 || !on_off(w[1], *flag)) fail("usage: " + verb + " on|off");
  } else if (verb == "gizmo") {
    if (w.size() == 2 && w[1] == "move")
      ui_.gizmo = GizmoMode::move;
    else if (w.size() == 2 && w[1] == "rotate")
      ui_.gizmo = GizmoMode::rotate;
    else if (w.size() == 2 && w[1] == "size")
      ui_.gizmo = GizmoMode::size;
    else
      fail("usage: gizmo move|rotate|size");
  } else if (verb == "box_select") {
    double v[4];
    const bool through = w.size() == 6 && w[5] == "through";
    for (int k = 0; k < 4; ++k)
      if ((w.size() != 5 && !through) || !parse_double(w[1 + k], v[k]))
        return fail("usage: box_select X0 Y0 X1 Y1 [through] (window pixels)"), true;
    select_box(doc_, ui_, ImVec2(static_cast<float>(v[0]), static_cast<float>(v[1])),
               ImVec2(static_cast<float>(v[2]), static_cast<float>(v[3])), through);
    std::cout << ui_.status << "\n";
  } else if (verb == "fit_selection") {
    const Selection s = doc_.selection();
    if (s.object < 0 || s.primitive < 0)
      return fail("fit_selection needs a selected primitive"), true;
    if (ui_.box_object != s.object || ui_.box_points.empty())
      return fail("fit_selection needs a box selection on this object (box_select)"), true;
    Primitive prim = doc_.spec().objects[s.object].primitives[s.primitive];
    // fit_selection [KIND] [snap up|principal]
    std::size_t next = 1;
    if (w.size() > next && w[next] != "snap") {
      const auto k = shape_from_name(w[next]);
      if (!k) return fail("unknown shape '" + w[next] + "'"), true;
      if (*k != prim.kind) {
        Primitive q = make_primitive(*k, prim.name);
        q.weight = prim.weight;
        prim = q;
      }
      ++next;
    }
    AxisSnap snap = AxisSnap::none;
    if (w.size() > next) {
      if (w[next] != "snap" || w.size() != next + 2 || (w[next + 1] != "up" && w[next + 1] != "principal"))
        return fail("fit_selection takes [KIND] [snap up|principal]"), true;
      snap = w[next + 1] == "up" ? AxisSnap::object_up : AxisSnap::mesh_principal;
    }
    FitOptions options;
    if (const MeshData* mesh = doc_.mesh_for(s.object)) options.axis = snap_axis(snap, *mesh);
    options.normals = ui_.box_normals;
    auto fit = fit_primitive(ui_.box_points, prim.kind, options);
    if (!fit) return fail(fit.error().message), true;
    if (Status st = doc_.apply(cmd::ReplacePrimitive{s.object, s.primitive, with_fit(prim, *fit)});
        !st)
      return fail(st.error().message), true;
    doc_.apply(cmd::EndEdit{});
  } else if (verb == "print_match" || verb == "expect_match") {
    if (!ui_.scene) return fail("no scene loaded for the match preview (scene FILE)"), true;
    const MatchPreview mp = preview_match(doc_.spec(), *ui_.scene);
    if (verb == "print_match") {
      for (const ObjectPreview& o : mp.objects) {
        char vote[32];
        std::snprintf(vote, sizeof vote, "%.2f", o.assigned_vote);  // as annex-runtime prints
        std::cout << "match " << o.name << " -> " << (o.assigned ? o.assigned_id : "virtual-only")
                  << " vote " << vote << "\n";
      }
    } else {
      if (w.size() != 3) return fail("usage: expect_match OBJECT PROP|none"), true;
      for (const ObjectPreview& o : mp.objects) {
        if (o.name != w[1]) continue;
        const std::string got = o.assigned ? o.assigned_id : "none";
        if (got != w[2])
          fail("expected " + w[1] + " to match " + w[2] + ", the preview says " + got);
        return true;
      }
      fail("no object named '" + w[1] + "'");
    }
  } else if (verb == "runtime_preview") {
    int frames = 0;
    if (w.size() != 3 || !count(2, frames))
      return fail("usage: runtime_preview SOURCE FRAMES"), true;
    if (ui_.runtime_path.empty()) ui_.runtime_path = find_runtime();
    if (ui_.runtime_path.empty()) return fail("needs annex-runtime run (runtime issue)"), true;
    if (doc_.path().empty() || doc_.dirty())
      return fail("runtime_preview needs the spec saved first"), true;
    ui_.runtime_source = w[1];
    const int code = start_runtime_preview(frames, /*wait=*/true);
    if (code < 0) return fail("cannot start " + ui_.runtime_path + " run"), true;
    std::cout << "runtime_preview: annex-runtime run exited " << code << "\n";
  } else if (verb == "quit") {
    next_line_ = script_.size();
  } else {
    return false;
  }
  return true;
}

void EditorApp::before_frame(Renderer& renderer) {
  frame_start_ = std::chrono::steady_clock::now();
  if (runtime_pid_ > 0) {
    int wstatus = 0;
    if (waitpid(runtime_pid_, &wstatus, WNOHANG) == runtime_pid_) {
      ui_.status = "annex-runtime run ended (exit " +
                   std::to_string(WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1) + ")";
      runtime_pid_ = -1;
    }
  }
  if (!scripted()) {
    const double since = std::chrono::duration<double>(frame_start_ - last_autosave_).count();
    if (since >= kAutosaveSeconds) {
      last_autosave_ = frame_start_;
      if (doc_.dirty() && doc_.revision() != autosaved_revision_) {
        // An invalid spec cannot be read back, so only valid states are autosaved.
        if (doc_.validate()) {
          if (Status s = doc_.write_autosave(); !s)
            ui_.status = s.error().format();
          else
            autosaved_revision_ = doc_.revision();
        }
      }
    }
    return;
  }
  if (done_ || pending_frames_ > 0 || first_frame_) {
    if (pending_frames_ > 0) --pending_frames_;
    first_frame_ = false;
    return;
  }
  while (!done_ && pending_frames_ == 0 && next_line_ < script_.size()) {
    const ScriptLine& line = script_[next_line_++];
    if (run_view_command(line)) continue;
    const std::size_t objects_before = doc_.spec().objects.size();
    const std::string verb = line.words[0];
    auto r = run_document_command(doc_, line, options_.script_path);
    if (!r) {
      fail_script(r.error().format());
      break;
    }
    if (!r->handled) {
      // The spec reader's did-you-mean, over every command a script may use.
      static constexpr std::string_view kCommands[] = {
          "new", "open", "recover", "import", "add_object", "select", "add", "remove",
          "duplicate", "set", "rank", "fit", "undo", "redo", "save", "autosave", "validate",
          "print", "screenshot", "frames", "bench", "scene", "print_match", "expect_match",
          "camera", "frame_all", "frame_selected", "limits_preview", "rank_mode",
          "wireframes", "grid", "gizmo", "box_select", "fit_selection", "runtime_preview",
          "quit"};
      std::string hint = detail::suggestion(verb, kCommands);
      if (!hint.starts_with("; did you mean")) hint = " (docs/editor.md lists them)";
      fail_script(options_.script_path + ":" + std::to_string(line.line) +
                  ": error: unknown command '" + verb + "'" + hint);
      break;
    }
    std::cout << r->output;
    if (verb == "open" || verb == "new" || verb == "recover") {
      clear_meshes_ = true;
      ui_.preview_dirty = true;  // a new document restarts its revision count
    }
    if (verb == "open" || verb == "recover" || doc_.spec().objects.size() != objects_before)
      frame_all(doc_, ui_);
  }
  if (clear_meshes_) {
    renderer.clear_meshes();
    clear_meshes_ = false;
  }
  if (pending_frames_ > 0)
    --pending_frames_;
  else if (next_line_ >= script_.size())
    done_ = true;
}

void EditorApp::after_render(int fb_width, int fb_height) {
  if (benching_) glFinish();  // time the whole frame, GPU included
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frame_start_)
          .count();
  ui_.frame_ms = ui_.frame_ms == 0 ? static_cast<float>(ms)
                                   : 0.9f * ui_.frame_ms + 0.1f * static_cast<float>(ms);
  if (benching_) {
    bench_ms_.push_back(ms);
    if (pending_frames_ == 0) {
      benching_ = false;
      std::vector<double> sorted = bench_ms_;
      std::sort(sorted.begin(), sorted.end());
      const double mean =
          std::accumulate(sorted.begin(), sorted.end(), 0.0) / static_cast<double>(sorted.size());
      std::size_t tris = 0;
      for (int o = 0; o < static_cast<int>(doc_.spec().objects.size()); ++o)
        if (const MeshData* m = doc_.mesh_for(o)) tris += m->triangle_count();
      // CPU time of the process (llvmpipe's threads included) is steadier than wall
      // time on a shared machine.
      const double cpu_ms = 1000.0 * static_cast<double>(std::clock() - bench_cpu_start_) /
                            CLOCKS_PER_SEC / static_cast<double>(sorted.size());
      std::cout << "bench: " << sorted.size() << " frames, " << tris << " triangles, " << fb_width
                << "x" << fb_height << ", " << options_.samples << "x MSAA: wall mean " << mean
                << " ms, median " << sorted[sorted.size() / 2] << " ms, min " << sorted.front()
                << " ms, max " << sorted.back() << " ms; CPU " << cpu_ms << " ms/frame\n";
    }
  }
  if (!capture_path_.empty() && pending_frames_ == 0) {
    if (Status s = write_screenshot(capture_path_, fb_width, fb_height); !s)
      fail_script(s.error().format());
    else
      std::cout << "screenshot " << capture_path_ << " " << fb_width << "x" << fb_height << "\n";
    capture_path_.clear();
  }
}

}  // namespace annex::authoring
