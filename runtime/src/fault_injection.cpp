// Injected sensor faults and the per-frame health monitor (docs/reliability.md).
#include "annex/runtime/fault_injection.h"

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <thread>

namespace annex {
namespace {

Error plan_error(std::string_view event, std::string message) {
  return Error{"fault plan: '" + std::string(event) + "': " + std::move(message),
               Location{"--inject-faults"}};
}

bool to_int(std::string_view s, int& out) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return !s.empty() && ec == std::errc() && end == s.data() + s.size() && out >= 0;
}

// Every other pixel of every other row.
Frame half_resolution(const Frame& f) {
  if (!f.organized() || f.width < 2 || f.height < 2) return f;
  Frame out = f;
  out.width = f.width / 2;
  out.height = f.height / 2;
  // Every second pixel of every second row: pixel u is the source's 2u.
  const CameraIntrinsics k = grid_intrinsics(f);
  out.intrinsics = {out.width, out.height, k.fx / 2, k.fy / 2, k.cx / 2, k.cy / 2};
  out.points.resize(static_cast<size_t>(out.width) * out.height);
  for (int v = 0; v < out.height; ++v)
    for (int u = 0; u < out.width; ++u)
      out.points[static_cast<size_t>(v) * out.width + u] =
          f.points[static_cast<size_t>(2 * v) * f.width + 2 * u];
  return out;
}

class FaultInjectingGrabber final : public FrameGrabber {
 public:
  FaultInjectingGrabber(std::unique_ptr<FrameGrabber> source, std::vector<Fault> plan)
      : source_(std::move(source)), plan_(std::move(plan)) {}

  Result<std::optional<Frame>> next() override {
    const int call = calls_++;
    auto active = [&](FaultKind kind) -> const Fault* {
      for (const Fault& f : plan_)
        if (f.kind == kind && call >= f.first && call <= f.last) return &f;
      return nullptr;
    };
    if (active(FaultKind::disconnect))
      return Error{"device disconnected (injected fault)",
                   Location{"read " + std::to_string(call) + " (" + source_->describe() + ")"}};
    if (const Fault* stall = active(FaultKind::stall))
      std::this_thread::sleep_for(std::chrono::milliseconds(stall->stall_ms));
    if (active(FaultKind::drop)) {
      Result<std::optional<Frame>> lost = source_->next();
      if (!lost || !*lost) return lost;
    }
    Result<std::optional<Frame>> next = source_->next();
    if (!next || !*next) return next;
    Frame frame = std::move(**next);
    if (active(FaultKind::half_resolution)) frame = half_resolution(frame);
    if (active(FaultKind::invalid))
      for (PointXYZRGB& p : frame.points) p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
    return std::optional<Frame>(std::move(frame));
  }

  std::string describe() const override {
    return source_->describe() + " with " + std::to_string(plan_.size()) + " injected faults";
  }
  std::optional<int> frame_count() const override { return std::nullopt; }

 private:
  std::unique_ptr<FrameGrabber> source_;
  std::vector<Fault> plan_;
  int calls_ = 0;
};

}  // namespace

Result<std::vector<Fault>> parse_fault_plan(std::string_view text) {
  std::vector<Fault> plan;
  if (text.empty()) return plan_error(text, "empty; expected KIND@FIRST[-LAST],...");
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    const std::string_view event = text.substr(
        start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    const size_t at = event.find('@');
    if (at == std::string_view::npos)
      return plan_error(event,
                        "expected KIND@FIRST[-LAST] (kinds: stall, drop, nan, halfres, "
                        "disconnect)");
    const std::string_view kind = event.substr(0, at);
    std::string_view range = event.substr(at + 1);
    Fault f;
    if (kind == "stall") {
      f.kind = FaultKind::stall;
      const size_t colon = range.find(':');
      if (colon == std::string_view::npos || !to_int(range.substr(colon + 1), f.stall_ms) ||
          f.stall_ms > 60000)
        return plan_error(event,
                          "a stall needs its length in milliseconds, stall@FRAME:MS "
                          "(MS at most 60000)");
      range = range.substr(0, colon);
    } else if (kind == "drop") {
      f.kind = FaultKind::drop;
    } else if (kind == "nan") {
      f.kind = FaultKind::invalid;
    } else if (kind == "halfres") {
      f.kind = FaultKind::half_resolution;
    } else if (kind == "disconnect") {
      f.kind = FaultKind::disconnect;
    } else {
      return plan_error(event, "unknown fault '" + std::string(kind) +
                                   "' (kinds: stall, drop, nan, halfres, disconnect)");
    }
    const size_t dash = range.find('-');
    const bool ok =
        dash == std::string_view::npos
            ? to_int(range, f.first) && (f.last = f.first, true)
            : to_int(range.substr(0, dash), f.first) && to_int(range.substr(dash + 1), f.last);
    if (!ok || f.last < f.first)
      return plan_error(event, "expected FIRST or FIRST-LAST, whole numbers with FIRST <= LAST");
    plan.push_back(f);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return plan;
}

std::unique_ptr<FrameGrabber> inject_faults(std::unique_ptr<FrameGrabber> source,
                                            std::vector<Fault> plan) {
  return std::make_unique<FaultInjectingGrabber>(std::move(source), std::move(plan));
}

std::vector<std::string> FrameHealthMonitor::check(const Frame& frame, double read_s) {
  std::vector<std::string> notes;
  size_t valid = 0;
  for (const PointXYZRGB& p : frame.points) valid += std::isfinite(p.z) ? 1 : 0;
  if (valid == 0) notes.push_back("all " + std::to_string(frame.points.size()) + " points invalid");
  if (have_previous_) {
    if (frame.width != width_ || frame.height != height_)
      notes.push_back("resolution " + std::to_string(frame.width) + "x" +
                      std::to_string(frame.height) + ", was " + std::to_string(width_) + "x" +
                      std::to_string(height_));
    if (frame.index > index_ + 1) {
      const int missing = frame.index - index_ - 1;
      notes.push_back(std::to_string(missing) + (missing == 1 ? " frame" : " frames") +
                      " missing (source frame " + std::to_string(frame.index) + " after " +
                      std::to_string(index_) + ")");
    }
  }
  if (read_s >= params_.stall_s) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "the source took %.2f s to deliver it", read_s);
    notes.push_back(buf);
  }
  have_previous_ = true;
  width_ = frame.width;
  height_ = frame.height;
  index_ = frame.index;
  return notes;
}

}  // namespace annex
