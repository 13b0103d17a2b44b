#pragma once
// The app around the panels: applies the command queue after each frame, carries
// out file actions, autosaves, and runs --script files frame by frame.

#include <chrono>
#include <ctime>
#include <optional>
#include <string>
#include <vector>

#include "annex/authoring/editor_document.h"
#include "annex/authoring/script.h"
#include "renderer.h"
#include "ui_state.h"

namespace annex::authoring {

struct AppOptions {
  std::string open_path;    // .haptic to open at start
  std::string script_path;  // --script FILE
  int width = 1600;
  int height = 900;
  int samples = 4;  // multisample anti-aliasing; 0 turns it off (faster on llvmpipe)
};

// Parses argv; prints usage or an error and returns nullopt when the app should exit
// with `exit_code`.
std::optional<AppOptions> parse_options(int argc, char** argv, int& exit_code);

class EditorApp {
 public:
  explicit EditorApp(AppOptions options);

  // Before ImGui's frame: script lines, autosave.
  void before_frame(Renderer& renderer);
  // After the scene and ImGui are drawn, before the swap: screenshots, bench timing.
  void after_render(int fb_width, int fb_height);
  // Commands and actions the frame's widgets asked for.
  void apply_queue(Renderer& renderer);
  // The window's close button.
  void request_quit();

  bool done() const { return done_; }
  int exit_code() const { return exit_code_; }
  bool scripted() const { return !options_.script_path.empty(); }
  const EditorDocument& doc() const { return doc_; }
  UiState& ui() { return ui_; }
  CommandQueue& queue() { return queue_; }

 private:
  void run_action(const AppAction& action, Renderer& renderer);
  void open_document(const std::string& path, bool recover, Renderer& renderer);
  // The document's log lines (stale temporaries removed) to stderr and the status line.
  void log_document_notes();
  void open_scene(const std::string& path);
  void add_recent(const std::string& path);
  void fail_script(const std::string& message);
  // Starts annex-runtime run on the saved spec; `frames` > 0 adds --frames, `wait`
  // blocks until it ends (scripts). Returns the exit code when waited, else 0; -1 if
  // it could not start.
  int start_runtime_preview(int frames = 0, bool wait = false);
  // Runs one app-level script line; returns false when the verb is not an app verb.
  bool run_view_command(const ScriptLine& line);

  AppOptions options_;
  EditorDocument doc_;
  UiState ui_;
  CommandQueue queue_;
  bool done_ = false;
  int exit_code_ = 0;
  bool clear_meshes_ = false;  // the document was replaced: GPU meshes are stale

  // Autosave.
  std::chrono::steady_clock::time_point last_autosave_;
  std::uint64_t autosaved_revision_ = 0;

  // The annex-runtime run child, reaped when it ends.
  int runtime_pid_ = -1;

  // Script state.
  std::vector<ScriptLine> script_;
  std::size_t next_line_ = 0;
  int pending_frames_ = 0;
  std::string capture_path_;
  bool benching_ = false;
  std::vector<double> bench_ms_;
  std::clock_t bench_cpu_start_ = 0;
  std::chrono::steady_clock::time_point frame_start_;
  bool first_frame_ = true;
};

}  // namespace annex::authoring
