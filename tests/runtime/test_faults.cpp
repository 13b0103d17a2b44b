// Sensor faults (docs/reliability.md): the fault-injecting source and the health
// monitor; the session through stalls, drops, all-NaN frames, a resolution change and
// a disconnect (props held, lost, released, annexed again); `run` going on through
// them, saying per frame what happened, and leaving whole files.
#include "annex/runtime/fault_injection.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <thread>

#include "annex/runtime/annex_session.h"
#include "annex/runtime/synthetic_scene.h"
#include "cli_runner.h"
#include "temp_dir.h"
#include "session_fixture.h"

namespace annex {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// Frames from memory, as a recording.
class VectorGrabber final : public FrameGrabber {
 public:
  explicit VectorGrabber(std::vector<Frame> frames) : frames_(std::move(frames)) {}
  Result<std::optional<Frame>> next() override {
    if (next_ >= frames_.size()) return std::optional<Frame>{};
    return std::optional<Frame>(frames_[next_++]);
  }
  std::string describe() const override { return "frames in memory"; }
  std::optional<int> frame_count() const override { return static_cast<int>(frames_.size()); }

 private:
  std::vector<Frame> frames_;
  size_t next_ = 0;
};

Frame small_frame(int index, int w = 8, int h = 6) {
  Frame f;
  f.width = w;
  f.height = h;
  f.index = index;
  f.points.resize(static_cast<size_t>(w) * h);
  for (size_t i = 0; i < f.points.size(); ++i)
    f.points[i] = {float(i % w) * 0.01f, float(i / w) * 0.01f, 1.0f, 100, 100, 100};
  return f;
}

std::unique_ptr<FrameGrabber> small_source(int n) {
  std::vector<Frame> frames;
  for (int k = 0; k < n; ++k) frames.push_back(small_frame(k));
  return std::make_unique<VectorGrabber>(std::move(frames));
}

TEST(FaultPlan, ParsesEveryKindAndRefusesNonsense) {
  const auto plan = parse_fault_plan("stall@3:500,drop@5-6,nan@8-20,halfres@30-34,disconnect@40");
  ASSERT_TRUE(plan.ok()) << plan.error().format();
  ASSERT_EQ(plan->size(), 5u);
  EXPECT_EQ((*plan)[0].kind, FaultKind::stall);
  EXPECT_EQ((*plan)[0].first, 3);
  EXPECT_EQ((*plan)[0].stall_ms, 500);
  EXPECT_EQ((*plan)[1].kind, FaultKind::drop);
  EXPECT_EQ((*plan)[1].last, 6);
  EXPECT_EQ((*plan)[2].kind, FaultKind::invalid);
  EXPECT_EQ((*plan)[3].kind, FaultKind::half_resolution);
  EXPECT_EQ((*plan)[4].kind, FaultKind::disconnect);
  EXPECT_EQ((*plan)[4].first, 40);
  EXPECT_EQ((*plan)[4].last, 40);
  for (const char* bad :
       {"", "stall@3", "stall@3:99999", "drop@5-3", "melt@1", "nan@x", "nan@1,", "drop5"}) {
    const auto r = parse_fault_plan(bad);
    EXPECT_FALSE(r.ok()) << bad;
    if (!r.ok()) EXPECT_NE(r.error().message.find("fault plan"), std::string::npos);
  }
}

// Every second pixel of every second row: the camera's focal length and centre halve
// with the grid, so the pixels still back-project to where they were.
TEST(FaultInjection, HalfResolutionHalvesTheIntrinsics) {
  Frame f = small_frame(0, 640, 480);
  f.intrinsics = {640, 480, 580, 582, 320, 242};
  auto grabber = inject_faults(std::make_unique<VectorGrabber>(std::vector<Frame>{f}),
                               {Fault{FaultKind::half_resolution, 0, 0}});
  const auto half = grabber->next();
  ASSERT_TRUE(half.ok() && half->has_value());
  const CameraIntrinsics& k = (*half)->intrinsics;
  EXPECT_EQ(k.width, 320);
  EXPECT_EQ(k.height, 240);
  EXPECT_DOUBLE_EQ(k.fx, 290);
  EXPECT_DOUBLE_EQ(k.fy, 291);
  EXPECT_DOUBLE_EQ(k.cx, 160);
  EXPECT_DOUBLE_EQ(k.cy, 121);
}

TEST(FaultInjection, EachFaultAndWhatTheMonitorSays) {
  auto plan = parse_fault_plan("stall@1:300,drop@2,nan@3,halfres@4,disconnect@5-6");
  ASSERT_TRUE(plan.ok());
  auto grabber = inject_faults(small_source(10), *plan);
  EXPECT_FALSE(grabber->frame_count().has_value());  // a live device
  FrameHealthMonitor monitor;
  std::vector<std::vector<std::string>> notes;
  std::vector<int> indices;
  int errors = 0;
  for (int call = 0; call < 12; ++call) {
    const auto t0 = std::chrono::steady_clock::now();
    Result<std::optional<Frame>> r = grabber->next();
    const double read_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!r) {
      ++errors;
      EXPECT_NE(r.error().message.find("device disconnected"), std::string::npos);
      continue;
    }
    if (!*r) break;
    indices.push_back((*r)->index);
    notes.push_back(monitor.check(**r, read_s));
  }
  EXPECT_EQ(errors, 2);
  // Source frames 0, 1 (stalled), 3 (2 dropped), 4 (NaN), 5 (half), 6, 7, 8, 9 (the
  // disconnect reads nothing).
  EXPECT_EQ(indices, (std::vector<int>{0, 1, 3, 4, 5, 6, 7, 8, 9}));
  ASSERT_EQ(notes.size(), 9u);
  EXPECT_TRUE(notes[0].empty());
  ASSERT_EQ(notes[1].size(), 1u);
  EXPECT_NE(notes[1][0].find("the source took 0."), std::string::npos) << notes[1][0];
  EXPECT_EQ(notes[2], std::vector<std::string>{"1 frame missing (source frame 3 after 1)"});
  EXPECT_EQ(notes[3], std::vector<std::string>{"all 48 points invalid"});
  EXPECT_EQ(notes[4], std::vector<std::string>{"resolution 4x3, was 8x6"});
  EXPECT_EQ(notes[5], std::vector<std::string>{"resolution 8x6, was 4x3"});
  EXPECT_TRUE(notes[6].empty());
}

// ---- The session ----------------------------------------------------------------------

using test::spec_for;
using test::three_props;

TEST(FaultSession, PropsAreHeldLostReleasedAndAnnexedAgain) {
  const SyntheticScene scene = three_props(51);
  std::vector<Frame> frames;
  for (int k = 0; k < 40; ++k) frames.push_back(render_scene(scene, {}, k).frame);
  auto plan = parse_fault_plan("drop@3,nan@5-14,halfres@22-24,disconnect@27-29");
  ASSERT_TRUE(plan.ok());
  auto grabber = inject_faults(std::make_unique<VectorGrabber>(frames), *plan);
  SessionParams params;
  params.scan_every = 3;
  params.release_after_frames = 3;
  AnnexSession session(spec_for(scene), params);
  std::map<std::string, std::vector<std::string>> history;  // virtual -> state per frame
  std::map<std::string, int> released_at, annexed_again_at;
  int errors = 0, processed = 0;
  for (int call = 0; call < 60; ++call) {
    Result<std::optional<Frame>> next = grabber->next();
    if (!next) {
      ++errors;
      continue;
    }
    if (!*next) break;
    const FrameReport r = session.process(**next);
    ++processed;
    for (const std::string& name : r.released)
      if (!released_at.count(name)) released_at[name] = call;
    for (const AnnexedObject& o : r.objects) {
      history[o.virtual_name].push_back(std::string(tracking_state_name(o.track.state)));
      if (released_at.count(o.virtual_name) && !annexed_again_at.count(o.virtual_name))
        annexed_again_at[o.virtual_name] = call;
    }
  }
  EXPECT_EQ(errors, 3);
  EXPECT_EQ(processed, 39 - 3 + 3);  // 40 frames, one dropped; 3 failed reads
  for (const char* name : {"v0", "v1", "v2"}) {
    const std::vector<std::string>& h = history[name];
    ASSERT_FALSE(h.empty()) << name;
    // Tracking, then held on the NaN frames, then lost...
    const auto held = std::find(h.begin(), h.end(), "held");
    ASSERT_NE(held, h.end()) << name;
    EXPECT_NE(std::find(held, h.end(), "lost"), h.end()) << name;
    // ... released during the NaN frames and annexed again once frames return.
    ASSERT_TRUE(released_at.count(name)) << name;
    EXPECT_GE(released_at[name], 5);
    EXPECT_LE(released_at[name], 15);
    ASSERT_TRUE(annexed_again_at.count(name)) << name;
    EXPECT_GE(annexed_again_at[name], 15);
    EXPECT_EQ(h.back(), "tracking") << name;
  }
  EXPECT_EQ(session.objects().size(), 3u);
}

// ---- The run command ------------------------------------------------------------------

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// 60 frames of the bundled recording, forwards and backwards (symbolic links).
fs::path long_recording(const fs::path& dir, int count) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(test::source_path("samples/recordings/tabletop")))
    if (e.path().extension() == ".pcd") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  const int n = static_cast<int>(files.size());
  fs::create_directories(dir);
  for (int k = 0; k < count; ++k) {
    const int cycle = k % (2 * n - 2);
    const int i = cycle < n ? cycle : 2 * n - 2 - cycle;
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.pcd", k);
    fs::create_symlink(files[static_cast<size_t>(i)], dir / name);
  }
  return dir;
}

// A folder of this process (the suites of several builds or worktrees run at once).
fs::path run_dir(const std::string& name) {
  return test::process_temp_dir() / name;
}

const std::regex kPoseLine(
    R"(frame \d+ \S+ p\d+ state=(tracking|held|reinit|lost) t=(-?[0-9]+\.[0-9]+,){2}-?[0-9]+\.[0-9]+ )"
    R"(q=(-?[0-9]+\.[0-9]+,){3}-?[0-9]+\.[0-9]+ scale=([0-9]+\.[0-9]+,){2}[0-9]+\.[0-9]+.*)");

TEST(FaultRun, TheLoopGoesOnAndSaysWhatHappened) {
  const fs::path dir = run_dir("annex_test_fault_run");
  fs::remove_all(dir);
  const fs::path frames = long_recording(dir / "frames", 60);
  const test::CliRun run =
      test::run_cli("run " + test::source_path("samples/specs/study.haptic") + " --source " +
                    frames.string() + " --out " + (dir / "out").string() +
                    " --release-after 4 --scan-every 3"
                    " --inject-faults stall@2:300,drop@4,nan@8-22,halfres@32-35,disconnect@40-44");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string& out = run.output;
  EXPECT_NE(out.find("frame 2: the source took 0."), std::string::npos) << out;
  EXPECT_NE(out.find(": 1 frame missing (source frame 5 after 3)"), std::string::npos) << out;
  EXPECT_NE(out.find(": all 307200 points invalid"), std::string::npos) << out;
  EXPECT_NE(out.find(": resolution 320x240, was 640x480"), std::string::npos) << out;
  EXPECT_NE(out.find(": resolution 640x480, was 320x240"), std::string::npos) << out;
  int disconnects = 0;
  for (size_t at = out.find("device disconnected (injected fault)"); at != std::string::npos;
       at = out.find("device disconnected (injected fault)", at + 1))
    ++disconnects;
  EXPECT_EQ(disconnects, 5) << out;
  EXPECT_NE(out.find("the source delivers again after 5 failed reads"), std::string::npos) << out;
  // Each prop: held, lost, released; its virtual object annexed again when frames return.
  for (const char* name : {"champagne_bottle", "lamp"}) {
    const std::regex held(std::string("frame (\\d+) state ") + name + " p\\d+ held");
    const std::regex released(std::string("frame (\\d+) release ") + name);
    const std::regex again(std::string("frame (\\d+) match ") + name + " p\\d+");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(out, m, held)) << name << "\n" << out;
    const int held_at = std::stoi(m[1]);
    EXPECT_NE(out.find(std::string(" state ") + name), std::string::npos);
    ASSERT_TRUE(std::regex_search(out, m, released)) << name;
    const int released_at = std::stoi(m[1]);
    EXPECT_GT(released_at, held_at);
    int last_match = -1;
    for (std::sregex_iterator it(out.begin(), out.end(), again), end; it != end; ++it)
      last_match = std::stoi((*it)[1]);
    EXPECT_GT(last_match, released_at) << name << "\n" << out;
  }
  // Whole files: every pose line complete, one PNG per frame, no temporary left.
  std::ifstream poses(dir / "out" / "poses.txt");
  std::string line;
  int lines = 0;
  while (std::getline(poses, line)) {
    ++lines;
    EXPECT_TRUE(std::regex_match(line, kPoseLine)) << line;
  }
  EXPECT_GT(lines, 60);
  int pngs = 0;
  for (const auto& e : fs::directory_iterator(dir / "out")) {
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
    pngs += e.path().extension() == ".png";
  }
  if (out.find("no overlay images") == std::string::npos) EXPECT_EQ(pngs, 59);
  fs::remove_all(dir);
}

TEST(FaultRun, ALiveSourceThatStaysGoneEndsTheRun) {
  const test::CliRun run =
      test::run_cli("run " + test::source_path("samples/specs/study.haptic") + " --source " +
                    test::source_path("samples/recordings/tabletop") +
                    " --inject-faults disconnect@3-100 --source-retries 5");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("error: the source failed 6 reads in a row; giving up"),
            std::string::npos)
      << run.output;
  const test::CliRun bad =
      test::run_cli("run " + test::source_path("samples/specs/study.haptic") + " --source " +
                    test::source_path("samples/recordings/tabletop") + " --inject-faults melt@3");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("unknown fault 'melt'"), std::string::npos) << bad.output;
}

// A run killed while it writes leaves poses.txt with whole lines only.
TEST(FaultRun, AKilledRunLeavesWholeLines) {
  const fs::path dir = run_dir("annex_test_fault_kill");
  fs::remove_all(dir);
  const fs::path frames = long_recording(dir / "frames", 90);
  const fs::path poses = dir / "out" / "poses.txt";
  const std::string cmd = "exec " + test::shell_quote(ANNEX_RUNTIME_EXE) + " run " +
                          test::source_path("samples/specs/study.haptic") + " --source " +
                          frames.string() + " --realtime --no-overlays --out " +
                          (dir / "out").string() + " > /dev/null 2>&1";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Kill it once it has written a few frames.
  for (int i = 0; i < 1000 && slurp(poses).size() < 2000; ++i) std::this_thread::sleep_for(5ms);
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status));
  const std::string text = slurp(poses);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) EXPECT_TRUE(std::regex_match(line, kPoseLine)) << line;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace annex
