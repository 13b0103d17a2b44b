// The OSC stream of annexed objects (docs/streaming.md): liblo encodes the bundles and
// receives the game's answers; each target gets its own connected UDP socket so that
// "nothing listens there" comes back as ECONNREFUSED instead of vanishing.
#include "annex/runtime/osc_stream.h"

#include <lo/lo.h>
#include <lo/lo_lowlevel.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <optional>

namespace annex {
namespace {

constexpr std::string_view kScheme = "osc.udp://";

Error url_error(std::string_view url, std::string message) {
  return Error{std::move(message), Location{std::string(url), 0, 0}};
}

// Owns a liblo handle; liblo's free function as the deleter.
template <typename T, void (*Free)(T)>
struct LoHandle {
  T handle = nullptr;
  LoHandle() = default;
  explicit LoHandle(T h) : handle(h) {}
  LoHandle(const LoHandle&) = delete;
  LoHandle& operator=(const LoHandle&) = delete;
  ~LoHandle() {
    if (handle) Free(handle);
  }
};
using Bundle = LoHandle<lo_bundle, lo_bundle_free_recursive>;

lo_message to_lo(const OscMessage& m) {
  lo_message out = lo_message_new();
  for (const OscArg& a : m.args) {
    if (const auto* i = std::get_if<std::int32_t>(&a))
      lo_message_add_int32(out, *i);
    else if (const auto* f = std::get_if<float>(&a))
      lo_message_add_float(out, *f);
    else
      lo_message_add_string(out, std::get<std::string>(a).c_str());
  }
  return out;
}

// The bundle of one frame as bytes, ready for every target.
std::vector<char> encode(const std::vector<OscMessage>& messages) {
  Bundle bundle(lo_bundle_new(LO_TT_IMMEDIATE));
  for (const OscMessage& m : messages) {
    // The bundle takes the message (freed by lo_bundle_free_recursive).
    lo_bundle_add_message(bundle.handle, m.address.c_str(), to_lo(m));
  }
  size_t size = lo_bundle_length(bundle.handle);
  std::vector<char> bytes(size);
  lo_bundle_serialise(bundle.handle, bytes.data(), &size);
  bytes.resize(size);
  return bytes;
}

std::string errno_text(int e) {
  std::string s = std::strerror(e);
  if (e == ECONNREFUSED) s += " (nothing listens on that port)";
  return s;
}

}  // namespace

Result<OscUrl> parse_osc_url(std::string_view text, bool host_required) {
  if (!text.starts_with(kScheme))
    return url_error(text, "expected an OSC URL osc.udp://HOST:PORT (only UDP is supported)");
  std::string_view rest = text.substr(kScheme.size());
  if (!rest.empty() && rest.back() == '/') rest.remove_suffix(1);
  OscUrl url;
  url.text = std::string(text);
  std::string_view port;
  if (rest.starts_with('[')) {  // an IPv6 literal: [::1]:9000
    const size_t close = rest.find(']');
    if (close == std::string_view::npos || close + 1 >= rest.size() || rest[close + 1] != ':')
      return url_error(text, "expected [IPv6-ADDRESS]:PORT after osc.udp://");
    url.host = std::string(rest.substr(1, close - 1));
    port = rest.substr(close + 2);
  } else {
    const size_t colon = rest.rfind(':');
    if (colon == std::string_view::npos)
      return url_error(text, "expected HOST:PORT after osc.udp:// (no port given)");
    url.host = std::string(rest.substr(0, colon));
    port = rest.substr(colon + 1);
    if (url.host.find(':') != std::string::npos)
      return url_error(text, "an IPv6 address must be in brackets: osc.udp://[::1]:PORT");
  }
  if (host_required && url.host.empty())
    return url_error(text, "expected a host to send to: osc.udp://HOST:PORT");
  if (url.host.find('/') != std::string::npos)
    return url_error(text, "the host must not contain '/'");
  int n = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), n);
  // Listening on port 0 takes any free port (OscListener::port() tells which).
  const int lowest = host_required ? 1 : 0;
  if (port.empty() || ec != std::errc() || end != port.data() + port.size() || n < lowest ||
      n > 65535)
    return url_error(text, "the port must be a whole number from " + std::to_string(lowest) +
                               " to 65535, got '" + std::string(port) + "'");
  url.port = n;
  return url;
}

std::string OscMessage::types() const {
  std::string t;
  for (const OscArg& a : args)
    t += std::holds_alternative<std::int32_t>(a) ? 'i'
         : std::holds_alternative<float>(a)      ? 'f'
                                                 : 's';
  return t;
}

std::vector<OscMessage> frame_messages(const HapticSpec& spec, const FrameReport& report,
                                       double time_s) {
  std::vector<OscMessage> out;
  out.push_back(
      {"/annex/frame",
       {std::int32_t(report.frame_index), float(time_s), std::int32_t(report.objects.size())}});
  for (const std::string& id : report.excluded) out.push_back({"/annex/excluded", {id}});
  for (const std::string& name : report.released) out.push_back({"/annex/released", {name}});
  for (const AnnexedObject& o : report.objects) {
    const ModelPose p = decompose_model_transform(world_from_model(spec, o));
    out.push_back({"/annex/object",
                   {o.virtual_name, o.physical_id, std::string(tracking_state_name(o.track.state)),
                    float(o.track.confidence), float(p.translation.x), float(p.translation.y),
                    float(p.translation.z), float(p.rotation.w), float(p.rotation.x),
                    float(p.rotation.y), float(p.rotation.z), float(p.scale.x), float(p.scale.y),
                    float(p.scale.z), float(o.vote)}});
  }
  return out;
}

// ---- OscStream ------------------------------------------------------------------------

namespace {

struct Target {
  OscUrl url;
  int fd = -1;  // connected UDP socket; -1 when the host did not resolve
  std::string resolve_error;
  bool reported = false;
  OscTargetStats stats;
};

// A connected UDP socket to the first address the host resolves to.
int connect_udp(const OscUrl& url, std::string& error) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  const std::string port = std::to_string(url.port);
  if (const int rc = getaddrinfo(url.host.c_str(), port.c_str(), &hints, &found); rc != 0) {
    error = "cannot resolve '" + url.host + "': " + gai_strerror(rc);
    return -1;
  }
  int fd = -1;
  for (addrinfo* a = found; a && fd < 0; a = a->ai_next) {
    fd = socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) {
      error = errno_text(errno);
      continue;
    }
    if (connect(fd, a->ai_addr, a->ai_addrlen) != 0) {
      error = errno_text(errno);
      close(fd);
      fd = -1;
    }
  }
  freeaddrinfo(found);
  return fd;
}

}  // namespace

struct OscStream::Impl {
  std::vector<Target> targets;
  std::optional<double> first_time_s;
  ~Impl() {
    for (Target& t : targets)
      if (t.fd >= 0) close(t.fd);
  }
};

OscStream::OscStream(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
OscStream::OscStream(OscStream&&) noexcept = default;
OscStream& OscStream::operator=(OscStream&&) noexcept = default;
OscStream::~OscStream() = default;

Result<OscStream> OscStream::open(const std::vector<std::string>& urls) {
  auto impl = std::make_unique<Impl>();
  for (const std::string& text : urls) {
    Result<OscUrl> url = parse_osc_url(text, true);
    if (!url) return url.error();
    Target t;
    t.url = *url;
    t.stats.url = url->text;
    t.fd = connect_udp(t.url, t.resolve_error);
    impl->targets.push_back(std::move(t));
  }
  return OscStream(std::move(impl));
}

std::vector<std::string> OscStream::send(const HapticSpec& spec, const FrameReport& report) {
  if (!impl_->first_time_s) impl_->first_time_s = report.timestamp_s;
  const std::vector<char> bytes =
      encode(frame_messages(spec, report, report.timestamp_s - *impl_->first_time_s));
  std::vector<std::string> problems;
  for (Target& t : impl_->targets) {
    std::string error = t.resolve_error;
    if (t.fd >= 0) {
      const ssize_t n = ::send(t.fd, bytes.data(), bytes.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
      if (n == static_cast<ssize_t>(bytes.size())) {
        ++t.stats.bundles_sent;
        continue;
      }
      error = n < 0 ? errno_text(errno) : "short write";
    }
    ++t.stats.bundles_failed;
    if (t.stats.first_error.empty()) t.stats.first_error = error;
    if (!t.reported) {
      t.reported = true;
      problems.push_back(t.url.text + ": cannot deliver frame " +
                         std::to_string(report.frame_index) + ": " + error +
                         "; this target is reported once, the stream goes on");
    }
  }
  return problems;
}

std::vector<OscTargetStats> OscStream::stats() const {
  std::vector<OscTargetStats> out;
  for (const Target& t : impl_->targets) out.push_back(t.stats);
  return out;
}

// ---- OscListener ----------------------------------------------------------------------

namespace {

// liblo reports server errors through a callback without user data; the message of
// the latest failure on this thread is kept for open() to return.
thread_local std::string g_lo_error;
void remember_lo_error(int num, const char* msg, const char* where) {
  g_lo_error = std::string(msg ? msg : "error") + (where ? std::string(" (") + where + ")" : "") +
               " [" + std::to_string(num) + "]";
}

using Server = LoHandle<lo_server, lo_server_free>;

// What liblo's handlers collect between two polls.
struct Inbox {
  std::vector<OscCommand> pending;
  std::vector<std::string> warnings;
};

std::string describe_args(const char* types, lo_arg** argv, int argc) {
  std::string out = std::string(" ,") + (types ? types : "");
  for (int i = 0; i < argc && types && types[i]; ++i) {
    out += ' ';
    switch (types[i]) {
      case 'i':
        out += std::to_string(argv[i]->i);
        break;
      case 'f':
        out += std::to_string(argv[i]->f);
        break;
      case 's':
        out += std::string("\"") + &argv[i]->s + "\"";
        break;
      default:
        out += '?';
    }
  }
  return out;
}

int on_exclude(const char*, const char*, lo_arg** argv, int, lo_message, void* data) {
  auto* impl = static_cast<Inbox*>(data);
  const std::string id = &argv[0]->s;
  if (id.empty())
    impl->warnings.push_back("ignored /annex/exclude with an empty physical id");
  else
    impl->pending.push_back({OscCommand::Kind::exclude, id});
  return 0;
}

int on_rescan(const char*, const char*, lo_arg**, int, lo_message, void* data) {
  static_cast<Inbox*>(data)->pending.push_back({OscCommand::Kind::rescan, {}});
  return 0;
}

int on_other(const char* path, const char* types, lo_arg** argv, int argc, lo_message, void* data) {
  auto* impl = static_cast<Inbox*>(data);
  const std::string p = path ? path : "";
  std::string why = " (not in the address space: /annex/exclude s, /annex/rescan)";
  if (p == "/annex/exclude") why = " (expects one string argument, the physical id)";
  impl->warnings.push_back("ignored OSC message " + p + describe_args(types, argv, argc) + why);
  return 0;
}

}  // namespace

struct OscListener::Impl {
  Server server;
  Inbox inbox;
};

OscListener::OscListener(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
OscListener::OscListener(OscListener&&) noexcept = default;
OscListener& OscListener::operator=(OscListener&&) noexcept = default;
OscListener::~OscListener() = default;

Result<OscListener> OscListener::open(std::string_view text) {
  Result<OscUrl> url = parse_osc_url(text, false);
  if (!url) return url.error();
  auto impl = std::make_unique<Impl>();
  g_lo_error.clear();
  const std::string port = std::to_string(url->port);
  if (!url->host.empty())
    return url_error(text,
                     "a listening URL names only the port, osc.udp://:PORT (it listens on "
                     "every interface)");
  // liblo picks a free port when given none.
  lo_server s =
      lo_server_new_with_proto(url->port == 0 ? nullptr : port.c_str(), LO_UDP, remember_lo_error);
  if (!s)
    return url_error(text, "cannot listen on UDP port " + port + ": " +
                               (g_lo_error.empty() ? "unknown liblo error" : g_lo_error));
  impl->server.handle = s;
  lo_server_add_method(s, "/annex/exclude", "s", on_exclude, &impl->inbox);
  lo_server_add_method(s, "/annex/rescan", nullptr, on_rescan, &impl->inbox);
  lo_server_add_method(s, nullptr, nullptr, on_other, &impl->inbox);
  return OscListener(std::move(impl));
}

int OscListener::port() const {
  return lo_server_get_port(impl_->server.handle);
}

std::vector<OscCommand> OscListener::poll(std::vector<std::string>* warnings) {
  // The datagrams already queued, without blocking (at most kMaxPerPoll, so a flood
  // cannot hold up the frame loop).
  constexpr int kMaxPerPoll = 1000;
  Inbox& inbox = impl_->inbox;
  g_lo_error.clear();
  for (int n = 0; n < kMaxPerPoll && lo_server_recv_noblock(impl_->server.handle, 0) > 0; ++n) {
    if (!g_lo_error.empty()) {  // liblo's handler saw a malformed packet
      inbox.warnings.push_back("ignored a malformed OSC packet: " + g_lo_error);
      g_lo_error.clear();
    }
  }
  if (!g_lo_error.empty())
    inbox.warnings.push_back("ignored a malformed OSC packet: " + g_lo_error);
  std::vector<OscCommand> out = std::move(inbox.pending);
  inbox.pending.clear();
  if (warnings)
    for (std::string& w : inbox.warnings) warnings->push_back(std::move(w));
  inbox.warnings.clear();
  return out;
}

}  // namespace annex
