#pragma once
// The runtime loop of the paper (Figure 4) without the Renderer: the ObjectFinder
// scans until props are found, votes and matches; it keeps scanning every
// `scan_every` frames, where only virtual objects without a prop vote, new props are
// picked up and a prop lost for `release_after_frames` is released so its virtual
// object votes again. Each matched object has its own PoseTracker; the trackers of one
// frame run concurrently on a small pool of threads. docs/tracking.md.

#include <optional>
#include <string>
#include <vector>

#include "annex/common/haptic_model.h"
#include "annex/common/object_finder.h"
#include "annex/common/prop_fit.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/pose_tracker.h"
#include "annex/runtime/scanner.h"

namespace annex {

struct SessionParams {
  ScanParams scan;
  MatchParams match;
  PoseTrackerParams tracker;
  int scan_every = 10;            // frames between scans once something is matched
  int release_after_frames = 45;  // lost this long: the prop is released
  int threads = 2;                // trackers running at once
  double same_prop_m = 0.06;      // a scanned object this close to a tracked one is that prop
  int model_points = 600;         // source model size per object
};

// A virtual object annexed to a prop and the state of its tracking.
struct AnnexedObject {
  int virtual_index = -1;  // into HapticSpec::objects
  std::string virtual_name;
  std::string physical_id;     // stable for the life of the match
  int virtual_primitive = -1;  // the matched primitive of the virtual object
  PhysicalPrimitive physical;  // the prop's primitive when it was matched
  double vote = 0;
  int matched_frame = 0;
  PropFit fit;  // scale per primitive axis (clamped)
  ObjectTrack track;
};

// The virtual model's transform in the sensor frame for the current pose: model
// coordinates to sensor coordinates, scaled along the primitive's axes.
Affine world_from_model(const HapticSpec& spec, const AnnexedObject& object);

// world_from_model as translation, rotation and per-axis scale of the model (the scale
// is the diagonal of the stretch in model axes; exact when the primitive's axes lie
// along the model's, as in every sample spec).
struct ModelPose {
  Vec3 translation;
  Quat rotation;
  Vec3 scale{1, 1, 1};
};
ModelPose decompose_model_transform(const Affine& world_from_model);

// `frame <i> <virtual-name> <physical-id> state=<s> t=x,y,z q=w,x,y,z scale=sx,sy,sz`
std::string format_pose_line(int frame_index, const HapticSpec& spec, const AnnexedObject& object);

struct FrameTimes {
  double scan_ms = 0;
  double track_ms = 0;  // all trackers, wall clock
  double total_ms = 0;
};

struct FrameReport {
  int frame_index = 0;
  bool scanned = false;
  std::optional<Error> scan_error;  // the scan of this frame failed (no plane...)
  std::optional<ScanResult> scan;   // when scanned and successful
  // When a match ran this frame (some virtual object voted): the scene it voted on
  // (tracked props renamed to their stable ids) and the result.
  std::optional<PhysicalScene> match_scene;
  std::optional<MatchResult> match;
  std::vector<std::string> released;   // virtual names whose props were released
  std::vector<AnnexedObject> objects;  // annexed objects after this frame, spec order
  FrameTimes times;
};

class AnnexSession {
 public:
  AnnexSession(HapticSpec spec, SessionParams params);

  FrameReport process(const Frame& frame);

  const HapticSpec& spec() const { return spec_; }
  const std::vector<AnnexedObject>& objects() const { return objects_; }

 private:
  HapticSpec spec_;
  SessionParams params_;
  std::vector<AnnexedObject> objects_;
  std::optional<CameraIntrinsics> camera_;
  std::vector<SupportSurface> supports_;  // of the last scan; each prop tracks on its own
  std::vector<PhysicalObject> last_scan_objects_;
  int frames_since_scan_ = 0;
  int next_prop_id_ = 1;
};

}  // namespace annex
