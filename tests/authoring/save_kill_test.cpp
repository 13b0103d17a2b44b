// The editor killed while it saves: annex-author runs a script that saves one spec over
// and over, alternating two versions, under a private Xvfb server, and is killed with
// SIGKILL at a random moment once its saves have begun, many times. After every kill the
// spec on disk must be, byte for byte, either the old or the new version, whole (and
// parse): EditorDocument::save writes a temporary file beside the spec, syncs it and
// renames it over the spec (write_file_atomically). A save that truncated the spec and
// wrote it in place would leave an empty or partial file at some of these kills.
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "annex/authoring/editor_document.h"
#include "annex/authoring/script.h"
#include "annex/formats/file_io.h"
#include "annex/formats/haptic_format.h"
#include "test_util.h"

namespace annex::authoring {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A private X server for the whole test: Xvfb picks a free display and writes its
// number to the pipe given by -displayfd.
class XServer {
 public:
  XServer() {
    int fds[2];
    if (::pipe(fds) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::close(fds[0]);
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, 1);
      ::dup2(null, 2);
      const std::string fd = std::to_string(fds[1]);
      ::execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "640x480x24",
               "-nolisten", "tcp", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(fds[1]);
    std::string number;
    char c = 0;
    while (::read(fds[0], &c, 1) == 1 && c != '\n') number += c;
    ::close(fds[0]);
    if (!number.empty()) display_ = ":" + number;
  }
  ~XServer() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  const std::string& display() const { return display_; }

 private:
  pid_t pid_ = -1;
  std::string display_;
};

// Starts annex-author on a script, its output to `log`, its state folder in dir/state.
pid_t start_editor(const std::string& display, const fs::path& dir, const fs::path& script,
                   const fs::path& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out, 1);
    ::dup2(out, 2);
    ::setenv("DISPLAY", display.c_str(), 1);
    ::setenv("ANNEX_AUTHOR_STATE_DIR", (dir / "state").c_str(), 1);
    ::setenv("LSAN_OPTIONS", "detect_leaks=0", 1);  // Mesa's leaks, as in app_test.cpp
    ::execl(ANNEX_AUTHOR_EXE, ANNEX_AUTHOR_EXE, "--script", script.c_str(), "--size", "320x240",
            "--samples", "0", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

// Runs annex-author on a script to its end; returns the wait status.
int run_editor(const std::string& display, const fs::path& dir, const fs::path& script,
               const fs::path& log) {
  fs::create_directories(log.parent_path());
  const pid_t pid = start_editor(display, dir, script, log);
  int status = -1;
  if (pid > 0) ::waitpid(pid, &status, 0);
  return status;
}

std::vector<fs::path> temporaries_of(const fs::path& dir, const fs::path& spec) {
  std::vector<fs::path> out;
  for (const auto& entry : fs::directory_iterator(dir))
    if (is_temporary_of(entry.path(), spec)) out.push_back(entry.path());
  return out;
}

// Runs document commands in-process; fails the test on the first error.
void run(EditorDocument& doc, const std::string& text) {
  auto lines = parse_script(text, "setup.script");
  ASSERT_TRUE(lines) << lines.error().format();
  for (const ScriptLine& l : *lines) {
    auto r = run_document_command(doc, l, "setup.script");
    ASSERT_TRUE(r) << r.error().format();
  }
}

TEST(AuthorSave, KilledWhileSavingLeavesTheOldOrTheNewSpecWhole) {
  if (std::system("command -v Xvfb > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "needs Xvfb (package xvfb)";
  const fs::path dir = testing::fresh_dir("kill");
  const fs::path spec = dir / "room.haptic";

  // The old version: 120 objects of two primitives each (about 40 kB of text, so a
  // save is many write calls). The new one differs in one radius.
  std::string build;
  for (int i = 0; i < 120; ++i)
    build += "add_object prop" + std::to_string(i) + "\nadd cylinder body\nset radius 0.04\n" +
             "set height 0.12\nadd box grip\nset size_x 0.05\n";
  EditorDocument doc;
  run(doc, build + "select prop0 body\n");
  ASSERT_TRUE(doc.save_as(spec)) << "cannot write " << spec;
  const std::string old_text = slurp(spec);
  run(doc, "set radius 0.05\n");
  ASSERT_TRUE(doc.save_as(dir / "new.haptic"));
  const std::string new_text = slurp(dir / "new.haptic");
  fs::remove(dir / "new.haptic");
  ASSERT_NE(old_text, new_text);
  ASSERT_GT(old_text.size(), 20000u);

  // The editor's script: open the spec, then save the new and the old version in turn.
  std::string script = "open " + spec.string() + "\nselect prop0 body\n";
  for (int i = 0; i < 4000; ++i) script += "set radius 0.05\nsave\nset radius 0.04\nsave\n";
  testing::write_text(dir / "save_loop.script", script);

  XServer x;
  ASSERT_FALSE(x.display().empty()) << "Xvfb did not start";

  std::mt19937 rng(20161207);
  std::uniform_int_distribution<int> delay_us(0, 40000);
  const int kills = 40;
  int saw_old = 0, saw_new = 0, interrupted_saves = 0, finished = 0, display_retries = 0;
  for (int k = 0; k < kills; ++k) {
    // Each run starts from the old version.
    { std::ofstream(spec, std::ios::binary | std::ios::trunc) << old_text; }
    struct stat before {};
    ASSERT_EQ(::stat(spec.c_str(), &before), 0);
    // The editor's output, outside the spec's folder (which must hold nothing else).
    const fs::path run_log = dir.parent_path() / (dir.filename().string() + "_editor.log");
    const pid_t pid = start_editor(x.display(), dir, dir / "save_loop.script", run_log);
    ASSERT_GE(pid, 0);
    // Wait until the saves have begun (the spec's inode changes with the first rename),
    // then kill at a random moment within the next 40 ms.
    bool exited = false;
    int status = 0;
    const auto deadline = Clock::now() + std::chrono::seconds(60);
    for (;;) {
      if (::waitpid(pid, &status, WNOHANG) == pid) {
        exited = true;
        break;
      }
      struct stat now {};
      if (::stat(spec.c_str(), &now) == 0 && now.st_ino != before.st_ino) break;
      if (Clock::now() > deadline) break;
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    if (!exited) {
      std::this_thread::sleep_for(std::chrono::microseconds(delay_us(rng)));
      ::kill(pid, SIGKILL);
      ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    }
    ASSERT_FALSE(exited && WIFEXITED(status) && WEXITSTATUS(status) == 127)
        << "cannot run " << ANNEX_AUTHOR_EXE;
    // X servers of several suites come and go on this machine: an editor that could
    // not open its display never ran its script, so that run is made again.
    if (!WIFSIGNALED(status) &&
        slurp(run_log).find("Failed to open display") != std::string::npos &&
        display_retries < 10) {
      ++display_retries;
      --k;
      continue;
    }
    if (!WIFSIGNALED(status)) {
      ++finished;
      ADD_FAILURE() << "run " << k << " ended by itself (wait status " << status
                    << ") before it was killed; its output:\n"
                    << slurp(run_log);
    }

    const std::string text = slurp(spec);
    ASSERT_TRUE(text == old_text || text == new_text)
        << "kill " << k << ": the spec on disk is neither version (" << text.size()
        << " bytes; old " << old_text.size() << ", new " << new_text.size() << ")";
    auto parsed = read_haptic_file(spec);
    ASSERT_TRUE(parsed) << parsed.error().format();
    EXPECT_EQ(parsed->objects.size(), 120u);
    (text == old_text ? saw_old : saw_new)++;
    // A temporary file left beside the spec is a save the kill interrupted; the spec
    // itself was untouched by it. Nothing else may appear in the folder. The next
    // editor removes them when it opens the spec (below they accumulate until the
    // last run: every kill's editor opened the spec before the first kill).
    int temporaries = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind(".room.haptic.tmp-", 0) == 0) {
        ++temporaries;
      } else {
        EXPECT_TRUE(name == "room.haptic" || name == "save_loop.script" || name == "state" ||
                    name == "room.haptic.autosave")
            << "unexpected file after kill " << k << ": " << name;
      }
    }
    // Each editor removed the temporaries the earlier kills left when it opened the
    // spec, so at most the one of its own interrupted save remains.
    EXPECT_LE(temporaries, 1) << "after kill " << k;
    interrupted_saves += temporaries;
  }
  // Every run must have been killed while saving, not have finished or failed first.
  EXPECT_EQ(finished, 0) << "the editor ended before it was killed";
  EXPECT_GT(interrupted_saves, 0) << "no kill landed inside a save";

  // One normal open and save leaves no temporary file and says what it removed.
  const std::vector<fs::path> left = temporaries_of(dir, spec);
  testing::write_text(dir / "open_save.script", "open " + spec.string() + "\nsave\n");
  const fs::path log = dir / "state" / "open_save.log";
  int status = run_editor(x.display(), dir, dir / "open_save.script", log);
  for (int retry = 0; retry < 3 && slurp(log).find("Failed to open display") != std::string::npos;
       ++retry)
    status = run_editor(x.display(), dir, dir / "open_save.script", log);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp(log);
  EXPECT_TRUE(temporaries_of(dir, spec).empty());
  const std::string said = slurp(log);
  for (const fs::path& t : left)
    EXPECT_NE(said.find("removed '" + t.string() + "', the temporary file of an interrupted save"),
              std::string::npos)
        << said;
  const std::string text = slurp(spec);
  EXPECT_TRUE(text == old_text || text == new_text);
  std::printf("%d kills: %d left the old spec, %d the new one, %d interrupted a save "
              "(its temporary file left beside the spec); %d runs made again (no display)\n",
              kills, saw_old, saw_new, interrupted_saves, display_retries);
}

}  // namespace
}  // namespace annex::authoring
