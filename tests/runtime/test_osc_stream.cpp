// The OSC stream (docs/streaming.md) checked with a receiver no one here wrote:
// liblo-tools' oscdump listens while `run` streams the bundled recording, and oscsend
// plays the game answering /annex/exclude and /annex/rescan. Loopback only.
#include "annex/runtime/osc_stream.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <thread>

#include "cli_runner.h"
#include "temp_dir.h"

extern char** environ;

namespace annex {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// A loopback UDP port the OS picks, free when this returns (for a process that binds it
// next: OscDump retries when another took it in between).
int ephemeral_udp_port() {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  close(fd);
  return ntohs(a.sin_port);
}

// A loopback UDP port where nothing listens, held for the test so that no concurrent test
// binds it: the socket is bound to a port the OS picks and connected to itself, so the
// kernel hands it no datagram from another port and answers those with ICMP port
// unreachable, as for a closed port.
class RefusingUdpPort {
 public:
  RefusingUdpPort() : fd_(socket(AF_INET, SOCK_DGRAM, 0)) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    if (fd_ < 0 || bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
        getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len) != 0 ||
        connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0)
      ADD_FAILURE() << "cannot hold a loopback UDP port: " << std::strerror(errno);
    port_ = ntohs(a.sin_port);
  }
  ~RefusingUdpPort() {
    if (fd_ >= 0) close(fd_);
  }
  RefusingUdpPort(const RefusingUdpPort&) = delete;
  RefusingUdpPort& operator=(const RefusingUdpPort&) = delete;
  int port() const { return port_; }

 private:
  int fd_;
  int port_ = 0;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool oscsend(int port, const std::string& address, const std::string& types_and_values) {
  const std::string cmd = "oscsend 127.0.0.1 " + std::to_string(port) + " " + address + " " +
                          types_and_values + " >/dev/null 2>&1";
  return std::system(cmd.c_str()) == 0;
}

// oscdump listening on a loopback port the OS picked, its output in a file; killed on
// destruction. oscdump takes a port number, not 0: when another process binds the port
// first, oscdump fails (or never sees the probes) and a new port is tried.
class OscDump {
 public:
  explicit OscDump(fs::path out) : out_(std::move(out)) {
    for (int attempt = 0; attempt < 5 && !ready_; ++attempt) {
      stop();
      port_ = ephemeral_udp_port();
      if (!spawn()) return;  // not installed
      ready_ = wait_ready();
    }
  }
  ~OscDump() { stop(); }
  bool started() const { return pid_ > 0; }
  // oscdump answered a probe: it is listening on port().
  bool ready() const { return ready_; }
  int port() const { return port_; }
  // Waits until `count` lines containing `what` were dumped (or gives up).
  std::string wait_for(const std::string& what, int count) {
    std::string text;
    for (int i = 0; i < 2400; ++i) {  // up to a minute (a sanitizer build is slow)
      text = slurp(out_);
      int n = 0;
      for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
      if (n >= count) break;
      std::this_thread::sleep_for(25ms);
    }
    return text;
  }

 private:
  bool spawn() {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const std::string port_text = std::to_string(port_);
    char* argv[] = {const_cast<char*>("oscdump"), const_cast<char*>("-L"),
                    const_cast<char*>(port_text.c_str()), nullptr};
    if (posix_spawnp(&pid_, "oscdump", &actions, nullptr, argv, environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
    return pid_ > 0;
  }
  void stop() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
    pid_ = -1;
  }
  // Sends probes until one shows up in the dump; gives up when oscdump exited (it could
  // not bind the port).
  bool wait_ready() {
    for (int i = 0; i < 200; ++i) {
      oscsend(port_, "/probe", "i " + std::to_string(i));
      std::this_thread::sleep_for(25ms);
      if (slurp(out_).find("/probe") != std::string::npos) return true;
      if (waitpid(pid_, nullptr, WNOHANG) == pid_) {
        pid_ = -1;
        return false;
      }
    }
    return false;
  }

  int port_ = 0;
  fs::path out_;
  pid_t pid_ = -1;
  bool ready_ = false;
};

// One dumped message: "<timetag> /annex/object sssff... "lamp" "p2" ... 0.123".
struct Dumped {
  std::string address;
  std::string types;
  std::vector<std::string> args;  // strings without their quotes
};

std::vector<Dumped> parse_dump(const std::string& text) {
  std::vector<Dumped> out;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream tokens(line);
    std::string timetag;
    Dumped d;
    tokens >> timetag >> d.address >> d.types;
    if (d.address.rfind("/annex/", 0) != 0) continue;
    if (d.types.empty()) continue;
    std::string a;
    while (tokens >> a) {
      if (a.size() >= 2 && a.front() == '"' && a.back() == '"') a = a.substr(1, a.size() - 2);
      d.args.push_back(a);
    }
    out.push_back(std::move(d));
  }
  return out;
}

// poses.txt: "frame <i> <virtual> <physical> state=<s> t=x,y,z q=w,x,y,z scale=...".
struct PoseLine {
  int frame = -1;
  std::string name, id, state;
  std::vector<double> values;  // t, q, scale: 10 numbers
};

std::vector<PoseLine> read_poses(const fs::path& path) {
  std::vector<PoseLine> out;
  std::ifstream in(path);
  std::string line;
  const std::regex re(R"(frame (\d+) (\S+) (\S+) state=(\w+) t=(\S+) q=(\S+) scale=(\S+).*)");
  while (std::getline(in, line)) {
    std::smatch m;
    if (!std::regex_match(line, m, re)) {
      ADD_FAILURE() << "unexpected pose line: " << line;
      continue;
    }
    PoseLine p;
    p.frame = std::stoi(m[1]);
    p.name = m[2];
    p.id = m[3];
    p.state = m[4];
    for (int g = 5; g <= 7; ++g) {
      std::stringstream nums(m[g].str());
      std::string n;
      while (std::getline(nums, n, ',')) p.values.push_back(std::stod(n));
    }
    out.push_back(std::move(p));
  }
  return out;
}

int count_of(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

std::string study() {
  return test::source_path("samples/specs/study.haptic");
}
std::string recording() {
  return test::source_path("samples/recordings/tabletop");
}

// ---- The library ----------------------------------------------------------------------

TEST(OscUrl, ParsesTargetsAndListenPorts) {
  Result<OscUrl> u = parse_osc_url("osc.udp://127.0.0.1:9000", true);
  ASSERT_TRUE(u.ok()) << u.error().format();
  EXPECT_EQ(u->host, "127.0.0.1");
  EXPECT_EQ(u->port, 9000);
  u = parse_osc_url("osc.udp://[::1]:7000/", true);
  ASSERT_TRUE(u.ok()) << u.error().format();
  EXPECT_EQ(u->host, "::1");
  u = parse_osc_url("osc.udp://:9001", false);
  ASSERT_TRUE(u.ok());
  EXPECT_TRUE(u->host.empty());
  u = parse_osc_url("osc.udp://:0", false);  // listening: any free port
  ASSERT_TRUE(u.ok());
  EXPECT_EQ(u->port, 0);
  struct Bad {
    const char* url;
    bool host_required;
    const char* message;
  };
  for (const Bad& b : {Bad{"udp://127.0.0.1:9000", true, "only UDP"},
                       Bad{"osc.tcp://127.0.0.1:9000", true, "only UDP"},
                       Bad{"osc.udp://127.0.0.1", true, "no port given"},
                       Bad{"osc.udp://:9000", true, "expected a host"},
                       Bad{"osc.udp://127.0.0.1:0", true, "from 1 to 65535"},
                       Bad{"osc.udp://127.0.0.1:65536", true, "from 1 to 65535"},
                       Bad{"osc.udp://127.0.0.1:90x", true, "got '90x'"},
                       Bad{"osc.udp://::1:9000", true, "in brackets"},
                       Bad{"osc.udp://[::1:9000", true, "[IPv6-ADDRESS]:PORT"}}) {
    const Result<OscUrl> r = parse_osc_url(b.url, b.host_required);
    ASSERT_FALSE(r.ok()) << b.url;
    EXPECT_NE(r.error().message.find(b.message), std::string::npos) << r.error().format();
    EXPECT_EQ(r.error().location.origin, b.url);
  }
  const Result<OscListener> any = OscListener::open("osc.udp://:0");
  ASSERT_TRUE(any.ok()) << any.error().format();
  EXPECT_GT(any->port(), 0);
  const Result<OscListener> listen = OscListener::open("osc.udp://127.0.0.1:9000");
  ASSERT_FALSE(listen.ok());
  EXPECT_NE(listen.error().message.find("names only the port"), std::string::npos);
}

TEST(OscMessages, OneFrameInBundleOrder) {
  HapticSpec spec;
  VirtualObject v;
  v.name = "bottle";
  Primitive p = make_primitive(ShapeKind::cylinder, "body");
  v.primitives.push_back(p);
  spec.objects.push_back(v);
  FrameReport r;
  r.frame_index = 7;
  r.released = {"mug"};
  r.excluded = {"p4"};
  AnnexedObject o;
  o.virtual_index = 0;
  o.virtual_name = "bottle";
  o.physical_id = "p3";
  o.virtual_primitive = 0;
  o.vote = 61.5;
  o.fit.scale = {1.5, 1.5, 0.5};
  o.track.state = TrackingState::held;
  o.track.confidence = 0.25;
  o.track.pose = {{0.1, -0.2, 1.0}, {1, 0, 0, 0}};
  r.objects.push_back(o);
  const std::vector<OscMessage> m = frame_messages(spec, r, 0.5);
  ASSERT_EQ(m.size(), 4u);
  EXPECT_EQ(m[0].address, "/annex/frame");
  EXPECT_EQ(m[0].types(), "ifi");
  EXPECT_EQ(std::get<std::int32_t>(m[0].args[0]), 7);
  EXPECT_EQ(std::get<float>(m[0].args[1]), 0.5f);
  EXPECT_EQ(std::get<std::int32_t>(m[0].args[2]), 1);
  EXPECT_EQ(m[1].address, "/annex/excluded");
  EXPECT_EQ(std::get<std::string>(m[1].args[0]), "p4");
  EXPECT_EQ(m[2].address, "/annex/released");
  EXPECT_EQ(std::get<std::string>(m[2].args[0]), "mug");
  EXPECT_EQ(m[3].address, "/annex/object");
  EXPECT_EQ(m[3].types(),
            "sssfffffffffff"
            "f");
  EXPECT_EQ(std::get<std::string>(m[3].args[0]), "bottle");
  EXPECT_EQ(std::get<std::string>(m[3].args[1]), "p3");
  EXPECT_EQ(std::get<std::string>(m[3].args[2]), "held");
  const float expected[] = {0.25f, 0.1f, -0.2f, 1.0f, 1, 0, 0, 0, 1.5f, 1.5f, 0.5f, 61.5f};
  for (size_t i = 0; i < 12; ++i)
    EXPECT_NEAR(std::get<float>(m[3].args[3 + i]), expected[i], 1e-6) << "argument " << 3 + i;
}

TEST(OscListener, ReceivesExcludeAndRescanFromOscsend) {
  // Port 0: the OS picks a free one, read back from the listener.
  Result<OscListener> listener = OscListener::open("osc.udp://:0");
  ASSERT_TRUE(listener.ok()) << listener.error().format();
  const int port = listener->port();
  ASSERT_GT(port, 0);
  ASSERT_TRUE(oscsend(port, "/annex/exclude", "s p3"));
  ASSERT_TRUE(oscsend(port, "/annex/rescan", ""));
  ASSERT_TRUE(oscsend(port, "/annex/exclude", "i 3"));
  ASSERT_TRUE(oscsend(port, "/annex/teleport", "s p1"));
  {  // Not OSC at all.
    const int fd = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    const char junk[] = "not an OSC packet";
    sendto(fd, junk, sizeof junk, 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
    close(fd);
  }
  std::vector<OscCommand> commands;
  std::vector<std::string> warnings;
  for (int i = 0; i < 200 && commands.size() + warnings.size() < 5; ++i) {
    for (OscCommand& c : listener->poll(&warnings)) commands.push_back(std::move(c));
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_EQ(commands.size(), 2u);
  EXPECT_EQ(commands[0].kind, OscCommand::Kind::exclude);
  EXPECT_EQ(commands[0].physical_id, "p3");
  EXPECT_EQ(commands[1].kind, OscCommand::Kind::rescan);
  ASSERT_EQ(warnings.size(), 3u);
  EXPECT_NE(warnings[0].find("/annex/exclude ,i 3 (expects one string argument"), std::string::npos)
      << warnings[0];
  EXPECT_NE(warnings[1].find("/annex/teleport"), std::string::npos) << warnings[1];
  EXPECT_NE(warnings[2].find("ignored a malformed OSC packet"), std::string::npos) << warnings[2];
  // The port is taken now: a second listener says so.
  const Result<OscListener> again = OscListener::open("osc.udp://:" + std::to_string(port));
  ASSERT_FALSE(again.ok());
  EXPECT_NE(again.error().message.find("cannot listen on UDP port"), std::string::npos);
}

TEST(OscStream, ATargetWhereNothingListensIsReportedOnce) {
  const RefusingUdpPort closed;
  Result<OscStream> stream =
      OscStream::open({"osc.udp://127.0.0.1:" + std::to_string(closed.port())});
  ASSERT_TRUE(stream.ok()) << stream.error().format();
  HapticSpec spec;
  std::vector<std::string> problems;
  for (int k = 0; k < 10; ++k) {
    FrameReport r;
    r.frame_index = k;
    for (std::string& p : stream->send(spec, r)) problems.push_back(std::move(p));
    std::this_thread::sleep_for(10ms);  // room for the ICMP answer
  }
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("Connection refused (nothing listens on that port)"),
            std::string::npos)
      << problems[0];
  const std::vector<OscTargetStats> stats = stream->stats();
  ASSERT_EQ(stats.size(), 1u);
  EXPECT_GT(stats[0].bundles_failed, 0);
  EXPECT_EQ(stats[0].bundles_sent + stats[0].bundles_failed, 10);
  EXPECT_FALSE(OscStream::open({"osc.udp://127.0.0.1"}).ok());
}

// ---- The run command with oscdump and oscsend ----------------------------------------

// The README's recording streamed to oscdump: one /annex/object per annexed object per
// frame, names, ids, states and poses equal to poses.txt; a second target where
// nothing listens is reported once and the run goes on.
TEST(RunStream, OscdumpSeesTheRecordingFrameByFrame) {
  const test::TempDir dir("test_stream");
  OscDump dump(dir / "dump.txt");
  ASSERT_TRUE(dump.started()) << "oscdump (liblo-tools) is not installed";
  ASSERT_TRUE(dump.ready());
  const RefusingUdpPort closed;
  const std::string listening = "osc.udp://127.0.0.1:" + std::to_string(dump.port());
  const std::string nobody = "osc.udp://127.0.0.1:" + std::to_string(closed.port());
  const test::CliRun run = test::run_cli("run " + study() + " --source " + recording() + " --out " +
                                         (dir / "out").string() + " --no-overlays --stream " +
                                         listening + " --stream " + nobody);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(count_of(run.output, nobody + ": cannot deliver"), 1) << run.output;
  EXPECT_NE(run.output.find(listening + ": 4 bundles sent\n"), std::string::npos) << run.output;

  const std::vector<PoseLine> poses = read_poses(dir / "out" / "poses.txt");
  ASSERT_EQ(poses.size(), 8u);
  const std::vector<Dumped> msgs = parse_dump(dump.wait_for("/annex/object", 8));
  // Group by frame: each /annex/frame opens one.
  std::map<int, std::vector<Dumped>> frames;
  std::map<int, int> announced;
  int current = -1;
  for (const Dumped& d : msgs) {
    if (d.address == "/annex/frame") {
      ASSERT_EQ(d.types, "ifi");
      current = std::stoi(d.args[0]);
      announced[current] = std::stoi(d.args[2]);
      EXPECT_EQ(frames.count(current), 0u) << "frame " << current << " streamed twice";
      frames[current];
    } else if (d.address == "/annex/object") {
      ASSERT_GE(current, 0);
      ASSERT_EQ(d.types,
                "sssfffffffffff"
                "f");
      frames[current].push_back(d);
    }
  }
  ASSERT_EQ(frames.size(), 4u);
  std::map<std::string, std::string> votes;  // from the "frame 0 match" lines
  const std::regex match_line(R"(frame 0 match (\S+) (\S+) ([0-9.]+))");
  for (std::sregex_iterator it(run.output.begin(), run.output.end(), match_line), end; it != end;
       ++it)
    votes[(*it)[1]] = (*it)[3];
  ASSERT_EQ(votes.size(), 2u) << run.output;
  for (const auto& [k, objects] : frames) {
    std::vector<const PoseLine*> expected;
    for (const PoseLine& p : poses)
      if (p.frame == k) expected.push_back(&p);
    ASSERT_EQ(objects.size(), expected.size()) << "frame " << k;
    EXPECT_EQ(announced[k], static_cast<int>(objects.size()));
    for (size_t i = 0; i < objects.size(); ++i) {
      const Dumped& d = objects[i];
      const PoseLine& p = *expected[i];
      EXPECT_EQ(d.args[0], p.name) << "frame " << k;
      EXPECT_EQ(d.args[1], p.id) << "frame " << k;
      EXPECT_EQ(d.args[2], p.state) << "frame " << k;
      const double confidence = std::stod(d.args[3]);
      EXPECT_GE(confidence, 0.0);
      EXPECT_LE(confidence, 1.0);
      // t (4 decimals in poses.txt), q (5), scale (4); float32 on the wire.
      for (size_t v = 0; v < 10; ++v) {
        const double tolerance = v >= 3 && v < 7 ? 2e-5 : 2e-4;
        EXPECT_NEAR(std::stod(d.args[4 + v]), p.values[v], tolerance)
            << "frame " << k << " " << p.name << " value " << v;
      }
      EXPECT_NEAR(std::stod(d.args[14]), std::stod(votes[p.name]), 0.006) << p.name;
    }
  }
}

// The ids the first scan of the recording gives each virtual object's prop.
std::map<std::string, std::string> first_matches() {
  const test::CliRun run =
      test::run_cli("run " + study() + " --source " + recording() + " --frames 1");
  std::map<std::string, std::string> ids;
  const std::regex match_line(R"(frame 0 match (\S+) (\S+) )");
  for (std::sregex_iterator it(run.output.begin(), run.output.end(), match_line), end; it != end;
       ++it)
    ids[(*it)[1]] = (*it)[2];
  return ids;
}

TEST(RunStream, ExcludeOnTheCommandLine) {
  const std::map<std::string, std::string> ids = first_matches();
  ASSERT_EQ(ids.count("lamp"), 1u);
  const test::TempDir out("test_exclude_cli");
  const test::CliRun run =
      test::run_cli("run " + study() + " --source " + recording() + " --out " + out.string() +
                    " --no-overlays --exclude " + ids.at("lamp") + ",p99");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("frame 0 exclude " + ids.at("lamp") + "\n"), std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find("match lamp"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("frame 0 match champagne_bottle " + ids.at("champagne_bottle")),
            std::string::npos);
  const std::string poses = slurp(out / "poses.txt");
  EXPECT_EQ(poses.find(" lamp "), std::string::npos);
  EXPECT_EQ(count_of(poses, " champagne_bottle "), 4);

  const test::CliRun bad =
      test::run_cli("run " + study() + " --source " + recording() + " --exclude p1,,p2");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("--exclude expects physical ids separated by commas"),
            std::string::npos)
      << bad.output;
  const test::CliRun bad_url = test::run_cli("run " + study() + " --source " + recording() +
                                             " --stream osc.udp://127.0.0.1:0");
  EXPECT_EQ(bad_url.exit_code, 2);
  EXPECT_NE(bad_url.output.find("osc.udp://127.0.0.1:0: error: the port must be"),
            std::string::npos)
      << bad_url.output;
}

// The game answers with oscsend while `run` streams: the annexed lamp's prop is
// excluded, released, and never annexed again; a rescan is asked for; a malformed
// message is reported.
TEST(RunStream, OscsendExcludesAPropMidRun) {
  const std::map<std::string, std::string> ids = first_matches();
  ASSERT_EQ(ids.count("lamp"), 1u);
  const std::string lamp_prop = ids.at("lamp");
  const test::TempDir dir("test_stream_listen");
  fs::create_directories(dir / "frames");
  // 3 s of frames at 30 Hz: the recording forwards, backwards, forwards... (links).
  const std::vector<fs::path> files = [] {
    std::vector<fs::path> f;
    for (const auto& e : fs::directory_iterator(recording()))
      if (e.path().extension() == ".pcd") f.push_back(e.path());
    std::sort(f.begin(), f.end());
    return f;
  }();
  ASSERT_EQ(files.size(), 4u);
  const int n = static_cast<int>(files.size());
  for (int k = 0; k < 90; ++k) {
    const int cycle = k % (2 * n - 2);
    const int i = cycle < n ? cycle : 2 * n - 2 - cycle;
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.pcd", k);
    fs::create_symlink(files[static_cast<size_t>(i)], dir / "frames" / name);
  }
  OscDump dump(dir / "dump.txt");
  ASSERT_TRUE(dump.started());
  ASSERT_TRUE(dump.ready());
  const std::string cmd = test::shell_quote(ANNEX_RUNTIME_EXE) + " run " + study() + " --source " +
                          (dir / "frames").string() + " --realtime --out " +
                          (dir / "out").string() +
                          " --no-overlays --stream osc.udp://127.0.0.1:" +
                          std::to_string(dump.port()) + " --listen osc.udp://:0 > " +
                          (dir / "run.txt").string() + " 2>&1";
  std::thread runner([&] { std::system(cmd.c_str()); });
  // run listens on a port the OS picked and names it first thing.
  int listen = 0;
  const std::regex listening(R"(listening for /annex/exclude and /annex/rescan on UDP port (\d+))");
  for (int i = 0; i < 2400 && listen == 0; ++i) {  // up to a minute
    std::smatch m;
    const std::string so_far = slurp(dir / "run.txt");
    if (std::regex_search(so_far, m, listening)) listen = std::stoi(m[1]);
    else std::this_thread::sleep_for(25ms);
  }
  if (listen == 0) runner.join();
  ASSERT_GT(listen, 0) << slurp(dir / "run.txt");
  // Once the lamp is streamed on its prop, the game excludes it.
  const std::string first = dump.wait_for("\"" + lamp_prop + "\"", 1);
  EXPECT_NE(first.find("\"lamp\" \"" + lamp_prop + "\""), std::string::npos) << first;
  ASSERT_TRUE(oscsend(listen, "/annex/exclude", "i 3"));
  ASSERT_TRUE(oscsend(listen, "/annex/exclude", "s " + lamp_prop));
  ASSERT_TRUE(oscsend(listen, "/annex/rescan", ""));
  runner.join();
  const std::string output = slurp(dir / "run.txt");
  EXPECT_NE(output.find("OSC asks to exclude " + lamp_prop), std::string::npos) << output;
  EXPECT_NE(output.find("OSC asks for a rescan"), std::string::npos) << output;
  EXPECT_NE(output.find("warning: ignored OSC message /annex/exclude ,i 3"), std::string::npos)
      << output;
  const std::regex released(R"(frame (\d+) release lamp)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(output, m, released)) << output;
  const int k = std::stoi(m[1]);
  EXPECT_GE(k, 1);
  EXPECT_NE(output.find("frame " + std::to_string(k) + " exclude " + lamp_prop), std::string::npos)
      << output;
  EXPECT_EQ(count_of(output, "match lamp"), 1) << output;  // frame 0 only
  for (const PoseLine& p : read_poses(dir / "out" / "poses.txt"))
    if (p.frame >= k) {
      EXPECT_NE(p.name, "lamp") << "frame " << p.frame;
      EXPECT_NE(p.id, lamp_prop) << "frame " << p.frame;
    }
  // The stream says so, and the lamp is not streamed after.
  const std::vector<Dumped> msgs = parse_dump(dump.wait_for("/annex/frame", 90));
  bool after = false, saw_released = false, saw_excluded = false;
  int frames = 0;
  for (const Dumped& d : msgs) {
    if (d.address == "/annex/frame") {
      ++frames;
      after = after || std::stoi(d.args[0]) > k;
    }
    if (d.address == "/annex/released" && d.args[0] == "lamp") saw_released = true;
    if (d.address == "/annex/excluded" && d.args[0] == lamp_prop) saw_excluded = true;
    if (after && d.address == "/annex/object") {
      EXPECT_NE(d.args[0], "lamp");
      EXPECT_NE(d.args[1], lamp_prop);
    }
  }
  EXPECT_EQ(frames, 90);
  EXPECT_TRUE(saw_released);
  EXPECT_TRUE(saw_excluded);
}

}  // namespace
}  // namespace annex
