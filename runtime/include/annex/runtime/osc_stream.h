#pragma once
// The annexed objects streamed to a game on another device (a headset, a phone) as
// OSC 1.0, one bundle per frame, and the game's answers (exclude a prop, rescan).
// Address space, units and frames in docs/streaming.md. The CLI (`run --stream`) and
// any embedding send the same messages: both hand the session's FrameReport to
// OscStream::send. liblo stays inside osc_stream.cpp.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "annex/common/haptic_model.h"
#include "annex/common/result.h"
#include "annex/runtime/annex_session.h"

namespace annex {

// A UDP endpoint written as an OSC URL: `osc.udp://HOST:PORT` to send to (HOST a
// name, an IPv4 address or [an IPv6 address]), `osc.udp://:PORT` to listen on.
struct OscUrl {
  std::string text;  // as given, for messages
  std::string host;  // empty: every local interface (listening only)
  int port = 0;      // 1 to 65535 (listening: 0 takes any free port)
};

// Errors name the URL and what is wrong with it (scheme, host, port).
Result<OscUrl> parse_osc_url(std::string_view text, bool host_required);

// One OSC argument: the stream uses only int32 ('i'), float32 ('f') and string ('s'),
// the types every OSC library (Unity's OscJack and extOSC included) reads.
using OscArg = std::variant<std::int32_t, float, std::string>;

struct OscMessage {
  std::string address;  // "/annex/object"
  std::vector<OscArg> args;
  std::string types() const;  // "ssf..." in argument order
};

// The messages of one frame, in bundle order: /annex/frame, one /annex/excluded per
// prop excluded this frame, one /annex/released per released virtual object, then one
// /annex/object per annexed object (spec order). `time_s`: seconds since the stream's
// first frame.
std::vector<OscMessage> frame_messages(const HapticSpec& spec, const FrameReport& report,
                                       double time_s);

// What became of one target so far.
struct OscTargetStats {
  std::string url;
  long bundles_sent = 0;
  long bundles_failed = 0;  // refused, unreachable or dropped by a full socket buffer
  std::string first_error;  // empty while every bundle went out
};

// Sends every frame's bundle to one or more targets over connected UDP sockets, so a
// target where nothing listens (the OS answers "port unreachable") is noticed rather
// than sent to in silence. A target that cannot be resolved or reached is reported
// once; the others, and the run, go on.
class OscStream {
 public:
  // Resolves each target (numeric addresses or names); fails only on a malformed URL.
  // Targets that do not resolve are kept, reported by the first send and skipped.
  static Result<OscStream> open(const std::vector<std::string>& urls);

  OscStream(OscStream&&) noexcept;
  OscStream& operator=(OscStream&&) noexcept;
  ~OscStream();

  // Encodes the frame once (liblo) and sends it to every target. Returns one line per
  // target that failed for the first time ("osc.udp://h:p: cannot deliver: ...").
  std::vector<std::string> send(const HapticSpec& spec, const FrameReport& report);

  std::vector<OscTargetStats> stats() const;

 private:
  struct Impl;
  explicit OscStream(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// What the game asked for.
struct OscCommand {
  enum class Kind { exclude, rescan };
  Kind kind = Kind::rescan;
  std::string physical_id;  // for exclude
};

// Listens on a UDP port for /annex/exclude s:physical_id and /annex/rescan. Polled by
// the run loop between frames (no thread of its own: commands reach the session in
// frame order, on the session's thread).
class OscListener {
 public:
  static Result<OscListener> open(std::string_view url);

  OscListener(OscListener&&) noexcept;
  OscListener& operator=(OscListener&&) noexcept;
  ~OscListener();

  int port() const;

  // Every command received since the last poll, in arrival order, without waiting.
  // Messages the address space does not know, or with the wrong argument types, are
  // skipped with a line in `warnings`.
  std::vector<OscCommand> poll(std::vector<std::string>* warnings = nullptr);

 private:
  struct Impl;
  explicit OscListener(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace annex
