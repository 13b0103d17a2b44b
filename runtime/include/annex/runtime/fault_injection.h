#pragma once
// Faults real depth sensors show, injected into another source's frames, to test a run
// loop (and a game downstream) without unplugging anything: a stall, dropped frames,
// all-invalid frames, a resolution change, a disconnect and reconnect. And a monitor
// that says, per frame, what looks wrong with the stream. docs/reliability.md.

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "annex/common/result.h"
#include "annex/runtime/frame_grabber.h"

namespace annex {

enum class FaultKind {
  stall,            // the frame arrives `stall_ms` late
  drop,             // the source's frame is lost; the next one is delivered instead
  invalid,          // every point NaN (lens covered, sensor saturated)
  half_resolution,  // delivered at half the width and height (the mode changed)
  disconnect,       // next() fails: "device disconnected"; the source is not read
};

// Applies to the calls of next() numbered first..last (0-based), whatever they deliver.
struct Fault {
  FaultKind kind = FaultKind::stall;
  int first = 0;
  int last = 0;
  int stall_ms = 0;
};

// "stall@3:500,drop@5-6,nan@8-20,halfres@30-34,disconnect@40-45": KIND@FIRST[-LAST],
// stall with :MILLISECONDS (at most 60000). Errors name the event and what is wrong.
Result<std::vector<Fault>> parse_fault_plan(std::string_view text);

// Wraps `source`. The wrapper presents itself as a live device (no frame count), as
// the sensors that fail like this are; frames keep the source's index, so a drop shows
// as a gap.
std::unique_ptr<FrameGrabber> inject_faults(std::unique_ptr<FrameGrabber> source,
                                            std::vector<Fault> plan);

struct FrameHealthParams {
  double stall_s = 0.25;  // a source this slow to deliver one frame has stalled
};

// Compares each frame with the previous one and says what happened, in words for logs:
// "all 76800 points invalid", "resolution 160x120, was 320x240", "2 frames missing
// (source frame 7 after 4)", "the source took 0.51 s to deliver it". Empty when all is well.
class FrameHealthMonitor {
 public:
  explicit FrameHealthMonitor(FrameHealthParams params = {}) : params_(params) {}
  // `read_s`: how long the source's next() took for this frame.
  std::vector<std::string> check(const Frame& frame, double read_s);

 private:
  FrameHealthParams params_;
  bool have_previous_ = false;
  int width_ = 0, height_ = 0, index_ = 0;
};

}  // namespace annex
