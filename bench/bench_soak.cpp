// annex-bench-soak: a long run through the session (docs/reliability.md, Soak). The
// bundled recording loops forwards and backwards through AnnexSession, each frame
// streamed over OSC to a listener in the same process. Every --blackout-every frames
// the last 60 are all-NaN (a covered sensor), so every prop is lost, released and
// annexed again: tracks are created and dropped all along. Every --every frames the
// process's resident memory (VmRSS, and its peak VmHWM), threads and open files are
// sampled. After the warm-up the peak may grow by at most --rss-tolerance (5 %) and
// the threads and files not at all; the exit status says whether they held.
//
//   annex-bench-soak [--frames 20000] [--warmup 1000] [--every 1000] [--rss-tolerance 0.05]
//                    [--blackout-every 1000] (0: none)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "annex/formats/haptic_format.h"
#include "annex/runtime/annex_session.h"
#include "annex/runtime/osc_stream.h"
#include "annex/runtime/pcd_io.h"

namespace {

struct Sample {
  long frame = 0;
  long rss_kb = 0, peak_kb = 0, threads = 0, fds = 0;
  int annexed = 0;
  double seconds = 0;
};

long status_field(const char* name) {
  std::ifstream in("/proc/self/status");
  std::string key;
  long value = -1;
  while (in >> key) {
    if (key == name) {
      in >> value;
      return value;
    }
    in.ignore(1 << 12, '\n');
  }
  return value;
}

long open_files() {
  long n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator("/proc/self/fd")) ++n;
  return n;
}

long arg(int argc, char** argv, const char* name, long fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == name) return std::strtol(argv[i + 1], nullptr, 10);
  return fallback;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace annex;
  const long total = arg(argc, argv, "--frames", 20000);
  const long warmup = arg(argc, argv, "--warmup", 1000);
  const long every = std::max(1L, arg(argc, argv, "--every", 1000));
  const long blackout_every = arg(argc, argv, "--blackout-every", 1000);
  constexpr long kBlackout = 60;  // > release_after_frames (45): every prop is released
  double tolerance = 0.05;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--rss-tolerance") tolerance = std::strtod(argv[i + 1], nullptr);

  const std::filesystem::path root = ANNEX_SOURCE_DIR;
  Result<HapticSpec> spec = read_haptic_file(root / "samples/specs/study.haptic");
  if (!spec) {
    std::fprintf(stderr, "%s\n", spec.error().format().c_str());
    return 2;
  }
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(root / "samples/recordings/tabletop"))
    if (e.path().extension() == ".pcd") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<Frame> recording;
  for (const auto& f : files) {
    Result<Frame> frame = read_pcd(f);
    if (!frame) {
      std::fprintf(stderr, "%s\n", frame.error().format().c_str());
      return 2;
    }
    recording.push_back(std::move(*frame));
  }
  const long n = static_cast<long>(recording.size());
  if (n < 2) return 2;

  Result<OscListener> listener = OscListener::open("osc.udp://:0");
  if (!listener) {
    std::fprintf(stderr, "%s\n", listener.error().format().c_str());
    return 2;
  }
  Result<OscStream> stream =
      OscStream::open({"osc.udp://127.0.0.1:" + std::to_string(listener->port())});
  if (!stream) return 2;

  AnnexSession session(*spec, SessionParams{});
  std::vector<Sample> samples;
  long releases = 0, matches = 0;
  std::vector<std::string> warnings;
  const auto t0 = std::chrono::steady_clock::now();
  std::printf("%8s %10s %10s %8s %6s %8s %8s\n", "frame", "rss_kb", "peak_kb", "threads", "fds",
              "annexed", "s");
  for (long k = 0; k < total; ++k) {
    const long cycle = k % (2 * n - 2);
    Frame frame = recording[static_cast<size_t>(cycle < n ? cycle : 2 * n - 2 - cycle)];
    frame.index = static_cast<int>(k);
    frame.timestamp_s = k / 30.0;
    if (blackout_every > kBlackout && k % blackout_every >= blackout_every - kBlackout)
      for (PointXYZRGB& p : frame.points) p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
    const FrameReport r = session.process(frame);
    releases += static_cast<long>(r.released.size());
    for (const AnnexedObject& o : r.objects) matches += o.matched_frame == frame.index;
    stream->send(*spec, r);
    listener->poll(&warnings);  // the stream's messages are not commands: warnings
    warnings.clear();
    if ((k + 1) % every == 0 || k + 1 == total) {
      Sample s;
      s.frame = k + 1;
      s.rss_kb = status_field("VmRSS:");
      s.peak_kb = status_field("VmHWM:");
      s.threads = status_field("Threads:");
      s.fds = open_files();
      s.annexed = static_cast<int>(r.objects.size());
      s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      samples.push_back(s);
      std::printf("%8ld %10ld %10ld %8ld %6ld %8d %8.1f\n", s.frame, s.rss_kb, s.peak_kb, s.threads,
                  s.fds, s.annexed, s.seconds);
      std::fflush(stdout);
    }
  }
  const Sample* base = nullptr;
  for (const Sample& s : samples)
    if (s.frame >= warmup) {
      base = &s;
      break;
    }
  if (!base) {
    std::printf("no sample after the warm-up of %ld frames\n", warmup);
    return 1;
  }
  const Sample& last = samples.back();
  const double growth = static_cast<double>(last.peak_kb - base->peak_kb) / base->peak_kb;
  const auto stats = stream->stats();
  std::printf(
      "after warm-up (frame %ld): peak RSS %ld -> %ld kB (%+.2f %%), threads %ld -> %ld, open "
      "files %ld -> %ld; %ld matches, %ld releases; %ld bundles streamed; %.2f ms per frame\n",
      base->frame, base->peak_kb, last.peak_kb, growth * 100, base->threads, last.threads,
      base->fds, last.fds, matches, releases, stats.empty() ? 0L : stats[0].bundles_sent,
      last.seconds * 1000 / static_cast<double>(total));
  const bool ok = growth <= tolerance && last.threads <= base->threads && last.fds <= base->fds;
  std::printf("%s\n", ok ? "soak: ok" : "soak: FAILED");
  return ok ? 0 : 1;
}
