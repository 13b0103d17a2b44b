#pragma once
// The runtime loop of the paper (Figure 4) without the Renderer: the ObjectFinder
// scans until props are found, votes and matches; it keeps scanning every
// `scan_every` frames, where only virtual objects without a prop vote, new props are
// picked up and a prop lost for `release_after_frames` is released so its virtual
// object votes again. Each matched object has its own PoseTracker; the trackers of one
// frame run concurrently on the session's pool of threads, created once with the
// session. docs/tracking.md; docs/embedding.md for render loops.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "annex/common/haptic_model.h"
#include "annex/common/object_finder.h"
#include "annex/common/prop_fit.h"
#include "annex/runtime/camera_motion.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/pose_tracker.h"
#include "annex/runtime/scanner.h"

namespace annex {

// How a scan joins the frames. same_frame: the frame's scan runs on the calling thread
// while the trackers run, and what it finds shows in that frame's report (offline runs,
// tests). background: the scan runs on the session's scan worker on a copy of the frame
// and process() returns as soon as tracking is done; the result applies at the first
// frame after the scan finished, so a frame never waits for a scan (render loops).
enum class ScanMode { same_frame, background };
// The background scan worker's priority: SessionParams::scan_priority.
enum class ScanPriority { idle, nice };

struct SessionParams {
  ScanParams scan;
  MatchParams match;
  PoseTrackerParams tracker;
  int scan_every = 10;            // frames between scans once something is matched
  int release_after_frames = 45;  // lost this long: the prop is released
  int threads = 2;                // trackers running at once
  double same_prop_m = 0.06;      // a scanned object this close to a tracked one is that prop
  int model_points = 600;         // source model size per object
  ScanMode scan_mode = ScanMode::same_frame;
  // background: the scan worker's CPU priority (Linux). A scan is background work: the
  // render loop's threads come first, and on a busy machine the scan applies later.
  // idle: SCHED_IDLE, the scan runs only on a core nothing else wants (the idle time
  // between pushes) and any other thread preempts it at once; a scan not done scan_every
  // pushes after it started is promoted to niceness scan_nice until it ends, so a machine
  // with no idle core still gets scans (FrameReport::scan_promoted). Leaving SCHED_IDLE
  // needs CAP_SYS_NICE or RLIMIT_NICE >= 20 - scan_nice; without either the worker runs
  // at niceness scan_nice, as with nice: a smaller share of a busy core.
  ScanPriority scan_priority = ScanPriority::idle;
  int scan_nice = 10;
  // The depth camera's intrinsics when known; otherwise they are estimated from the
  // first organized frame (until then a tracker's target cube is cut by a full scan).
  std::optional<CameraIntrinsics> camera;
  // The head's motion from the static scene, so trackers predict in the room's frame.
  bool camera_motion = true;
  CameraMotionParams camera_motion_params;
  // A lost prop re-anchors on a scanned object of its shape this close to where it was.
  double reanchor_within_m = 0.6;
};

// What carries an annexed object's pose from frame to frame. track: its own PoseTracker
// (every prop; a box's face rides on a track of its box). prop: a box's face whose box
// is annexed as a prop too (another virtual object): the face rides on that prop's
// track, a copy of it each frame, so one physical box has one tracker. room: a support's
// free region, static in the room, moved only by the camera's motion (no tracker; state
// held while the camera's motion is unknown, lost when a scan finds the region taken).
enum class PoseCarrier { track, room, prop };

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
  // The tracking state; track.confidence in [0, 1] is how sure this frame's pose is
  // (docs/tracking.md), for a game to fade an unsure overlay.
  ObjectTrack track;
  PoseCarrier carrier = PoseCarrier::track;
  // The matched primitive's frame in track.pose's frame: identity for a prop, the face's
  // frame in its box's frame for a plane on a box (`<box>.top`, `<box>.face`).
  Pose primitive_in_track;
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

// `frame <i> <virtual-name> <physical-id> state=<s> t=x,y,z q=w,x,y,z scale=sx,sy,sz conf=c`
std::string format_pose_line(int frame_index, const HapticSpec& spec, const AnnexedObject& object);

struct FrameTimes {
  double scan_ms = 0;
  double track_ms = 0;  // all trackers, wall clock
  double total_ms = 0;
};

struct FrameReport {
  int frame_index = 0;
  bool scanned = false;  // a scan's result applied in this report (scan or scan_error)
  int scan_frame_index = -1;  // the frame that scan was taken from (background: an earlier one)
  std::optional<Error> scan_error;  // the scan of this frame failed (no plane...)
  std::optional<ScanResult> scan;   // when scanned and successful
  // background, ScanPriority::idle: the running scan was still not done scan_every pushes
  // after it started (the machine had no idle core for it), so it was promoted from
  // SCHED_IDLE to niceness scan_nice on this push.
  bool scan_promoted = false;
  // When a match ran this frame (some virtual object voted): the scene it voted on
  // (tracked props renamed to their stable ids) and the result.
  std::optional<PhysicalScene> match_scene;
  std::optional<MatchResult> match;
  std::vector<std::string> released;   // virtual names whose props were released
  std::vector<AnnexedObject> objects;  // annexed objects after this frame, spec order
  // The camera's motion since the previous frame (sensor_now_from_sensor_previous),
  // estimated from the static scene; identity when it could not be.
  Pose camera_motion;
  bool camera_motion_ok = false;
  std::vector<std::string> reanchored;  // virtual names whose lost props the scan found again
  FrameTimes times;
  double timestamp_s = 0;              // the frame's
  std::vector<std::string> excluded;   // physical ids whose exclusion took effect this frame
};

class AnnexSession {
 public:
  // Throws std::invalid_argument when validate_session_params fails; create() returns
  // that Error instead.
  AnnexSession(HapticSpec spec, SessionParams params);
  static Result<AnnexSession> create(HapticSpec spec, SessionParams params);
  AnnexSession(AnnexSession&&) noexcept;
  AnnexSession& operator=(AnnexSession&&) noexcept;
  ~AnnexSession();

  FrameReport process(const Frame& frame);
  // The same, numbering the frame `frame_index` in the report and the objects instead of
  // frame.index (for callers that count their pushes).
  FrameReport process(const Frame& frame, int frame_index);

  // background: blocks until the scan in flight (if any) has finished, so the next
  // process() applies it. Offline tools call it for results that do not depend on timing.
  void wait_for_scan();
  // background: whether a scan is running or waiting to be applied.
  bool scan_in_flight() const;

  const HapticSpec& spec() const { return spec_; }
  const std::vector<AnnexedObject>& objects() const { return objects_; }

  // The user forbids a prop (a hot mug, a fragile glass, someone's phone). From the
  // next frame it is released if annexed and never voted on again while it is in view:
  // it is still tracked under its id, so the scans recognise it, until it is lost for
  // release_after_frames. An id not given to any prop yet excludes the next scanned
  // prop given that id (ids of the first scan are those `scan` prints for the view).
  void exclude(std::string physical_id);
  // Scan on the next frame instead of waiting for scan_every.
  void rescan() { rescan_ = true; }
  // Excluded ids still in view, then those waiting for a scan to give them.
  std::vector<std::string> excluded_ids() const;

 private:
  struct Workers;  // the tracker pool and the scan worker (annex_session.cpp)
  std::unique_ptr<Workers> workers_;
  HapticSpec spec_;
  SessionParams params_;
  std::vector<AnnexedObject> objects_;
  std::optional<CameraIntrinsics> camera_;
  std::vector<SupportSurface> supports_;  // of the last scan; each prop tracks on its own
  std::vector<PhysicalObject> last_scan_objects_;  // in the current sensor frame
  std::shared_ptr<const TrackingModel> static_scene_;  // the previous frame's
  Pose camera_motion_;  // the last estimate: the next one's prediction
  Pose since_scan_frame_;  // the camera's motion since the background scan's frame
  int frames_since_scan_ = 0;
  int next_prop_id_ = 1;
  // Props the user excluded, tracked so that scans recognise them (exclude()).
  struct ExcludedProp {
    std::string physical_id;
    ObjectTrack track;
  };
  std::vector<ExcludedProp> excluded_;
  std::vector<std::string> exclude_requests_;  // applied at the next process()
  std::vector<std::string> exclude_waiting_;   // ids no prop has had yet
  std::vector<std::string> excluded_surfaces_;  // surface ids (`s1.free`, `p3.top`)
  bool rescan_ = false;
  bool spec_has_plane_ = false;  // some virtual object has a plane: scans match surfaces
  void apply_exclude_requests(FrameReport& report);
  void ride_faces_on_props();
  std::optional<AnnexedObject> annex_surface(int virtual_index, const Primitive& vp,
                                             int virtual_primitive, double vote,
                                             const PhysicalScene& scene, size_t j,
                                             size_t object_count, const ScanResult& scan,
                                             const Pose& scan_to_now, int frame_index) const;
};

}  // namespace annex
