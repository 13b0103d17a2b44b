// The runtime loop: ObjectFinder (scan, vote, match) and one PoseTracker per match.
#include "annex/runtime/annex_session.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <thread>
#include <utility>
#include <stdexcept>

#include "annex/runtime/params_validation.h"
#include "annex/runtime/scan_workers.h"
#include "session_workers.h"

#include "annex/runtime/rigid_motion.h"

namespace annex {
namespace {

using Clock = std::chrono::steady_clock;

// The support a prop at `p` stands on: the nearest plane below it (a cup on a shelf
// tracks on the shelf, not on the floor).
std::optional<Plane> support_below(const std::vector<SupportSurface>& supports, Vec3 p) {
  std::optional<Plane> best;
  double best_h = 0;
  for (const SupportSurface& s : supports) {
    const double h = dot(s.plane.normal, p) + s.plane.d;
    if (h > -0.02 && (!best || h < best_h)) best = s.plane, best_h = h;
  }
  return best;
}

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Which physical dimension each virtual dimension of a box takes: sizes by rank, as
// fit_to_prop pairs them.
std::vector<size_t> box_partners(const Primitive& v, const PhysicalPrimitive& p) {
  const size_t n = std::min(v.dimensions.size(), p.dimensions_m.size());
  std::vector<size_t> vi(n), pi(n), partner(n);
  std::iota(vi.begin(), vi.end(), 0);
  std::iota(pi.begin(), pi.end(), 0);
  std::stable_sort(vi.begin(), vi.end(), [&](size_t a, size_t b) {
    return v.dimensions[a].value_m > v.dimensions[b].value_m;
  });
  std::stable_sort(pi.begin(), pi.end(),
                   [&](size_t a, size_t b) { return p.dimensions_m[a] > p.dimensions_m[b]; });
  for (size_t r = 0; r < n; ++r) partner[vi[r]] = pi[r];
  return partner;
}

// The object frame a new track starts in: the frame fit_to_prop places the virtual
// primitive in (its centre, +Z its axis); for a box, its axes ordered so that the
// virtual primitive's local x, y, z fall on the physical sides they were scaled to.
Pose object_frame(const Primitive& v, const PhysicalPrimitive& p, Vec3 x_axis) {
  if (p.kind != ShapeKind::box || v.kind != ShapeKind::box || p.dimensions_m.size() < 3)
    return {p.center, rotation_from_z(p.axis)};
  const Vec3 z = normalized(p.axis);
  Vec3 x = x_axis - z * dot(x_axis, z);
  if (norm(x) < 1e-6) x = rotate(rotation_from_z(z), {1, 0, 0});
  x = normalized(x);
  const Vec3 axes[3] = {x, cross(z, x), z};
  const std::vector<size_t> partner = box_partners(v, p);
  Vec3 c[3] = {axes[partner[0]], axes[partner[1]], axes[partner[2]]};
  // An odd permutation is a reflection; a box looks the same flipped along a side.
  if (dot(cross(c[0], c[1]), c[2]) < 0) c[0] = c[0] * -1.0;
  return {p.center, quat_from_axes(c[0], c[1], c[2])};
}

// Distance from a track to a scanned object: to the nearest of its primitives' centres
// (the track follows one primitive, which may not be the salient one).
double distance_to(const PhysicalObject& o, Vec3 p) {
  double best = 1e9;
  for (const PhysicalPrimitive& q : o.primitives) best = std::min(best, norm(q.center - p));
  return best;
}

bool has_plane(const HapticSpec& spec) {
  for (const VirtualObject& v : spec.objects)
    for (const Primitive& p : v.primitives)
      if (v.annexable && p.kind == ShapeKind::plane) return true;
  return false;
}

bool is_surface(const AnnexedObject& o) { return o.physical.kind == ShapeKind::plane; }

// `p3.top` -> {"p3", ".top"}; a support's `s1.free` -> {"s1", ".free"}.
std::pair<std::string, std::string> split_surface_id(const std::string& id) {
  const size_t dot_at = id.rfind('.');
  if (dot_at == std::string::npos) return {id, ""};
  return {id.substr(0, dot_at), id.substr(dot_at)};
}

// A box's face that runs a tracker of its box (no prop of that box is annexed): it
// associates with and re-anchors on its box like a prop.
bool tracks_its_box(const AnnexedObject& o) {
  return is_surface(o) && o.carrier == PoseCarrier::track;
}

// The number of a session id `p<n>`, 0 for any other (a support's `s1`).
int prop_number(const std::string& id) {
  if (id.size() < 2 || id[0] != 'p' ||
      id.find_first_not_of("0123456789", 1) != std::string::npos)
    return 0;
  return std::stoi(id.substr(1));
}

// Where an annexed surface lies now: its centre and normal in the sensor frame.
Pose surface_pose(const AnnexedObject& o) { return compose(o.track.pose, o.primitive_in_track); }

// A scanned surface is the annexed one seen again: the same kind (a free region, a top,
// a face), on its plane (normals within 15 degrees, the centre within `band_m` of it)
// and, for a free region, still holding the panel's centre (nothing was put there); a
// box's face within same_prop_m of where its box carried it.
bool same_surface(const AnnexedObject& o, const PhysicalObject& s, double band_m,
                  double same_prop_m) {
  if (s.primitives.empty() || split_surface_id(s.id).second != split_surface_id(o.physical_id).second)
    return false;
  const PhysicalPrimitive& q = s.primitives.front();
  const Pose at = surface_pose(o);
  const Vec3 normal = rotate(at.rotation, {0, 0, 1});
  if (dot(normalized(q.axis), normal) < std::cos(15 * 3.14159265358979323846 / 180)) return false;
  const Vec3 r = at.position - q.center;
  if (o.carrier != PoseCarrier::room) return norm(r) <= same_prop_m;
  if (std::abs(dot(r, normalized(q.axis))) > band_m) return false;
  const Vec3 x = normalized(q.x_axis), y = cross(normalized(q.axis), x);
  return q.dimensions_m.size() >= 2 && std::abs(dot(r, x)) <= q.dimensions_m[0] / 2 &&
         std::abs(dot(r, y)) <= q.dimensions_m[1] / 2;
}

std::string num(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  std::string s = buf;
  // Never print "-0.000000".
  if (s.find_first_not_of("-0.") == std::string::npos && s[0] == '-') s.erase(0, 1);
  return s;
}

}  // namespace

Affine world_from_model(const HapticSpec& spec, const AnnexedObject& object) {
  const VirtualObject& v = spec.objects.at(static_cast<size_t>(object.virtual_index));
  const Primitive& prim = v.primitives.at(static_cast<size_t>(object.virtual_primitive));
  Affine scale;
  scale.m[0] = object.fit.scale.x;
  scale.m[5] = object.fit.scale.y;
  scale.m[10] = object.fit.scale.z;
  return affine_from_pose(compose(object.track.pose, object.primitive_in_track)) * scale *
         inverse_rigid(prim.pose);
}

ModelPose decompose_model_transform(const Affine& a) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = a.m[i * 4 + j];
  // Polar decomposition m = R S: R the closest rotation, S symmetric (the stretch).
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d r = svd.matrixU() * svd.matrixV().transpose();
  if (r.determinant() < 0) {
    Eigen::Matrix3d u = svd.matrixU();
    u.col(2) *= -1;
    r = u * svd.matrixV().transpose();
  }
  const Eigen::Matrix3d s = r.transpose() * m;
  Eigen::Quaterniond q(r);
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1;
  ModelPose out;
  out.translation = {a.m[3], a.m[7], a.m[11]};
  out.rotation = {q.w(), q.x(), q.y(), q.z()};
  out.scale = {s(0, 0), s(1, 1), s(2, 2)};
  return out;
}

std::string format_pose_line(int frame_index, const HapticSpec& spec, const AnnexedObject& o) {
  const ModelPose p = decompose_model_transform(world_from_model(spec, o));
  std::string line = "frame " + std::to_string(frame_index) + " " + o.virtual_name + " " +
                     o.physical_id + " state=" + std::string(tracking_state_name(o.track.state));
  line += " t=" + num(p.translation.x, 4) + "," + num(p.translation.y, 4) + "," +
          num(p.translation.z, 4);
  line += " q=" + num(p.rotation.w, 5) + "," + num(p.rotation.x, 5) + "," + num(p.rotation.y, 5) +
          "," + num(p.rotation.z, 5);
  line += " scale=" + num(p.scale.x, 4) + "," + num(p.scale.y, 4) + "," + num(p.scale.z, 4);
  line += " conf=" + num(o.track.confidence, 2);
  return line;
}

struct AnnexSession::Workers {
  WorkerPool trackers;
  std::unique_ptr<ScanWorker> scanner;  // ScanMode::background only
  ScanWorkers scan_threads;              // the scans on the pushing thread (scan_frame's pool)
  explicit Workers(const SessionParams& p)
      : trackers(p.threads),
        scanner(p.scan_mode == ScanMode::background
                    ? std::make_unique<ScanWorker>(p.scan, p.scan_priority, p.scan_nice,
                                                   p.scan_every)
                    : nullptr) {}
};

AnnexSession::AnnexSession(HapticSpec spec, SessionParams params)
    : spec_(std::move(spec)), params_(std::move(params)) {
  if (Status s = validate_session_params(params_); !s)
    throw std::invalid_argument(s.error().message);
  // Surfaces are looked for only when some virtual object can be laid on one.
  spec_has_plane_ = has_plane(spec_);
  if (!spec_has_plane_) params_.scan.plane_candidates = false;
  // One camera: the trackers and the camera's motion count in the scan's depth noise.
  params_.tracker.volume.depth_noise = params_.camera_motion_params.depth_noise =
      params_.scan.depth_noise;
  workers_ = std::make_unique<Workers>(params_);
}

Result<AnnexSession> AnnexSession::create(HapticSpec spec, SessionParams params) {
  if (Status s = validate_session_params(params); !s) return s.error();
  return AnnexSession(std::move(spec), std::move(params));
}

AnnexSession::AnnexSession(AnnexSession&&) noexcept = default;
AnnexSession& AnnexSession::operator=(AnnexSession&&) noexcept = default;
AnnexSession::~AnnexSession() = default;

void AnnexSession::exclude(std::string physical_id) {
  exclude_requests_.push_back(std::move(physical_id));
}

std::vector<std::string> AnnexSession::excluded_ids() const {
  std::vector<std::string> ids;
  for (const ExcludedProp& e : excluded_) ids.push_back(e.physical_id);
  ids.insert(ids.end(), excluded_surfaces_.begin(), excluded_surfaces_.end());
  ids.insert(ids.end(), exclude_waiting_.begin(), exclude_waiting_.end());
  return ids;
}

// An annexed prop the user excluded is released and keeps its track as an excluded
// prop; an id no prop has yet waits for the scan that gives it.
void AnnexSession::apply_exclude_requests(FrameReport& report) {
  for (std::string& id : exclude_requests_) {
    const auto annexed = std::find_if(objects_.begin(), objects_.end(),
                                      [&](const AnnexedObject& o) { return o.physical_id == id; });
    // A surface (a free region, a box's face) is excluded by its id until a scan no
    // longer shows it.
    if (id.find('.') != std::string::npos) {
      if (annexed != objects_.end()) {
        report.released.push_back(annexed->virtual_name);
        objects_.erase(annexed);
      }
      report.excluded.push_back(id);
      if (std::find(excluded_surfaces_.begin(), excluded_surfaces_.end(), id) ==
          excluded_surfaces_.end())
        excluded_surfaces_.push_back(std::move(id));
      continue;
    }
    // The panels on a prop's faces go with it: a user who forbids a box forbids
    // touching it.
    auto released_faces = [&] {
      std::erase_if(objects_, [&](const AnnexedObject& o) {
        if (!is_surface(o) || split_surface_id(o.physical_id).first != id) return false;
        report.released.push_back(o.virtual_name);
        return true;
      });
    };
    if (annexed != objects_.end()) {
      report.released.push_back(annexed->virtual_name);
      report.excluded.push_back(id);
      excluded_.push_back({id, std::move(annexed->track)});
      objects_.erase(annexed);
      released_faces();
      continue;
    }
    released_faces();
    const bool known =
        std::any_of(excluded_.begin(), excluded_.end(),
                    [&](const ExcludedProp& e) { return e.physical_id == id; }) ||
        std::find(exclude_waiting_.begin(), exclude_waiting_.end(), id) != exclude_waiting_.end();
    if (!known) exclude_waiting_.push_back(std::move(id));
  }
  exclude_requests_.clear();
}

void AnnexSession::wait_for_scan() {
  if (workers_->scanner) workers_->scanner->wait();
}

bool AnnexSession::scan_in_flight() const {
  return workers_->scanner && workers_->scanner->busy();
}

// A box's face whose box is annexed as a prop (by another virtual object) rides on the
// prop's track: the face's frame is re-expressed in the prop's object frame once, when
// the two meet, and the prop's track is copied each frame, so the box is tracked once.
// A face whose prop is gone (released at the same frame, as its state is the prop's)
// keeps the copy and tracks its box itself from then on.
void AnnexSession::ride_faces_on_props() {
  for (AnnexedObject& face : objects_) {
    if (!is_surface(face) || face.carrier == PoseCarrier::room) continue;
    const std::string owner = split_surface_id(face.physical_id).first;
    const auto prop = std::find_if(objects_.begin(), objects_.end(), [&](const AnnexedObject& o) {
      return !is_surface(o) && o.physical_id == owner;
    });
    if (prop == objects_.end()) {
      face.carrier = PoseCarrier::track;
      continue;
    }
    if (face.carrier == PoseCarrier::track) {
      face.primitive_in_track = compose(inverse(prop->track.pose), surface_pose(face));
      face.carrier = PoseCarrier::prop;
    }
    face.track = prop->track;
  }
}

// A virtual panel on a scanned surface (in this frame's sensor coordinates; the scan's
// objects in its own frame's, `scan_to_now` away): a support's free region stays where
// it is in the room; a box's face rides on a track of its box (the box's cluster as the
// model), the face's frame fixed in the box's.
std::optional<AnnexedObject> AnnexSession::annex_surface(int virtual_index, const Primitive& vp,
                                                         int virtual_primitive, double vote,
                                                         const PhysicalScene& scene, size_t j,
                                                         size_t object_count,
                                                         const ScanResult& scan,
                                                         const Pose& scan_to_now,
                                                         int frame_index) const {
  const PhysicalObject& s = scene.objects[j];
  if (s.primitives.empty() || s.primitives.front().kind != ShapeKind::plane) return std::nullopt;
  AnnexedObject a;
  a.virtual_index = virtual_index;
  a.virtual_name = spec_.objects[static_cast<size_t>(virtual_index)].name;
  a.physical_id = s.id;
  a.virtual_primitive = virtual_primitive;
  a.physical = s.primitives.front();
  a.vote = vote;
  a.matched_frame = frame_index;
  a.fit = fit_to_prop(vp, a.physical);
  const Pose plane{a.physical.center, plane_frame(a.physical, box_partners(vp, a.physical)[0] == 1)};
  const auto [owner, kind] = split_surface_id(s.id);
  if (kind == ".free") {
    a.carrier = PoseCarrier::room;
    a.track.pose = plane;
    a.track.confidence = s.fit;
    return a;
  }
  // The box the face belongs to.
  for (size_t k = 0; k < object_count && k < scan.clusters.size(); ++k) {
    const PhysicalObject& box = scene.objects[k];
    if (box.id != owner || box.primitives.empty() || scan.clusters[k].shape.primitives.empty())
      continue;
    const PhysicalPrimitive& bp = box.primitives.front();
    const Vec3 z = normalized(bp.axis);
    Vec3 x = scan.clusters[k].shape.primitives.front().x_axis;
    x = x - z * dot(x, z);
    if (norm(x) < 1e-6) x = rotate(rotation_from_z(z), {1, 0, 0});
    x = normalized(x);
    const Pose box_pose{bp.center, quat_from_axes(x, cross(z, x), z)};
    // The box's model from the scan's frame; its pose, like the face's, in this one.
    a.track = start_track(bp.kind, scan.clusters[k].points, box_pose, params_.model_points);
    a.track.pose = compose(scan_to_now, box_pose);
    a.track.confidence = s.fit;
    a.primitive_in_track = compose(inverse(a.track.pose), plane);
    return a;
  }
  return std::nullopt;
}

FrameReport AnnexSession::process(const Frame& frame) { return process(frame, frame.index); }

FrameReport AnnexSession::process(const Frame& frame, int frame_index) {
  const auto t_frame = Clock::now();
  FrameReport report;
  report.frame_index = frame_index;
  // The parameters' camera, else the frame's own (as its source gave or recovered it);
  // an unorganized cloud has no pixels to project cubes into, so it is cut by a full scan.
  if (params_.camera && params_.camera->width == frame.width &&
      params_.camera->height == frame.height) {
    camera_ = params_.camera;
  } else if (!camera_ || camera_->width != frame.width || camera_->height != frame.height) {
    camera_.reset();
    if (frame.organized()) camera_ = grid_intrinsics(frame);
  }

  report.timestamp_s = frame.timestamp_s;
  apply_exclude_requests(report);

  // The head's motion since the last frame: what is remembered in sensor coordinates
  // (the support, the last scan's objects) moves with it.
  // (Only while something is tracked, or a background scan runs: the head's motion
  // until it applies moves what it finds into the frame it applies at.)
  const bool scan_running = workers_->scanner && workers_->scanner->busy();
  if (params_.camera_motion && camera_ && static_scene_ && (!objects_.empty() || scan_running)) {
    const CameraMotionResult m =
        estimate_camera_motion(*static_scene_, frame, *camera_, camera_motion_,
                               params_.camera_motion_params);
    report.camera_motion_ok = m.ok;
    report.camera_motion = m.motion;
    camera_motion_ = m.motion;
    since_scan_frame_ = compose(m.motion, since_scan_frame_);
    for (SupportSurface& sp : supports_) sp.plane = transform_plane(sp.plane, m.motion);
    // A support's free region stays in the room: the camera's motion carries it.
    for (AnnexedObject& o : objects_)
      if (o.carrier == PoseCarrier::room) o.track.pose = compose(m.motion, o.track.pose);
    for (PhysicalObject& o : last_scan_objects_)
      for (PhysicalPrimitive& p : o.primitives) {
        p.center = transform_point(m.motion, p.center);
        p.axis = rotate(m.motion.rotation, p.axis);
      }
  }

  // Scan until something is annexed, then every scan_every frames (or when asked); in
  // background mode the scan runs beside the trackers and applies a frame later.
  const bool scan_due =
      std::exchange(rescan_, false) || objects_.empty() || ++frames_since_scan_ >= params_.scan_every;
  const bool scan_now = scan_due && params_.scan_mode == ScanMode::same_frame;

  // Trackers run on the pool while this thread scans: the annexed props, then the
  // excluded ones.
  std::vector<ObjectTrack*> tracks;
  for (AnnexedObject& o : objects_)
    if (o.carrier == PoseCarrier::track) tracks.push_back(&o.track);
  // Room-carried surfaces have no tracker: held while the camera's motion is unknown,
  // lost (from a scan that found them taken) until released.
  for (AnnexedObject& o : objects_) {
    if (o.carrier != PoseCarrier::room) continue;
    if (o.track.state == TrackingState::lost) {
      ++o.track.lost_frames;
    } else {
      const bool moved_ok = !params_.camera_motion || report.camera_motion_ok;
      o.track.state = moved_ok ? TrackingState::tracking : TrackingState::held;
    }
  }
  for (ExcludedProp& e : excluded_) tracks.push_back(&e.track);
  TrackingInput input;
  input.frame = &frame;
  input.camera = camera_;
  input.support = supports_.empty() ? std::nullopt : std::optional<Plane>(supports_.front().plane);
  input.camera_motion = report.camera_motion;
  std::vector<ObjectTrack> tracked(tracks.size());
  std::vector<TrackingInput> inputs(tracks.size(), input);
  for (size_t i = 0; i < tracks.size(); ++i)
    if (auto s = support_below(supports_, tracks[i]->pose.position)) inputs[i].support = s;
  // Re-initialisation candidates: the last scan's primitives of the track's shape, except
  // on an object another prop holds (within same_prop_m of its centre, as when
  // associating): a hidden sphere's model fits a neighbouring cylinder's side at 0.7.
  auto held_by_other = [&](const PhysicalObject& o, size_t i) {
    for (size_t j = 0; j < tracks.size(); ++j)
      if (j != i && tracks[j]->state != TrackingState::lost &&
          distance_to(o, tracks[j]->pose.position) <= params_.same_prop_m)
        return true;
    return false;
  };
  for (size_t i = 0; i < tracks.size(); ++i)
    for (const PhysicalObject& o : last_scan_objects_)
      if (!held_by_other(o, i))
        for (const PhysicalPrimitive& p : o.primitives)
          if (p.kind == tracks[i]->model->kind) inputs[i].candidates.push_back(p.center);
  const auto t_track = Clock::now();
  if (!tracks.empty())
    workers_->trackers.start(static_cast<int>(tracks.size()), [&](int i) {
      tracked[i] = track_step(*tracks[i], inputs[i], params_.tracker);
    });
  ScanWorker* background = workers_->scanner.get();
  if (background) report.scan_promoted = background->tick();
  const bool start_background = scan_due && background && !background->busy();
  if (start_background) {
    background->stage(frame, frame_index);
    frames_since_scan_ = 0;
    since_scan_frame_ = {};
  }
  if (scan_now) {
    const auto t0 = Clock::now();
    Result<ScanResult> scan = scan_frame(frame, params_.scan, workers_->scan_threads);
    report.times.scan_ms = ms_since(t0);
    report.scanned = true;
    report.scan_frame_index = frame_index;
    frames_since_scan_ = 0;
    if (scan) {
      report.scan = std::move(scan.value());
    } else {
      report.scan_error = scan.error();
    }
  }
  if (!tracks.empty()) workers_->trackers.wait();
  report.times.track_ms = ms_since(t_track);
  // A background scan that has finished applies now, a frame or more after its frame.
  Pose scan_to_now;  // the camera's motion since the frame of the scan applied now
  if (background && !start_background && background->ready()) {
    ScanWorker::Done done = background->take();
    scan_to_now = since_scan_frame_;
    report.scanned = true;
    report.scan_frame_index = done.frame_index;
    report.times.scan_ms = done.ms;
    if (done.result) {
      report.scan = std::move(done.result.value());
    } else {
      report.scan_error = done.result.error();
    }
  }
  // This frame's static scene, for the next frame's camera motion (before the tracks
  // move out of `tracked`).
  if (params_.camera_motion && camera_)
    static_scene_ = std::make_shared<const TrackingModel>(static_scene_model(
        frame, *camera_, moving_props(tracked, params_.camera_motion_params),
        params_.camera_motion_params));
  for (size_t i = 0; i < tracks.size(); ++i) *tracks[i] = std::move(tracked[i]);
  ride_faces_on_props();
  // An excluded prop lost this long has left the view: its exclusion ends.
  std::erase_if(excluded_, [&](const ExcludedProp& e) {
    return e.track.state == TrackingState::lost &&
           e.track.lost_frames >= params_.release_after_frames;
  });

  // Release props lost for too long: their virtual objects vote again.
  std::erase_if(objects_, [&](const AnnexedObject& o) {
    if (o.track.state != TrackingState::lost || o.track.lost_frames < params_.release_after_frames)
      return false;
    report.released.push_back(o.virtual_name);
    return true;
  });

  if (report.scan) {
    ScanResult& scan = *report.scan;
    supports_ = scan.scene.supports;
    last_scan_objects_ = scan.scene.objects;
    // Which scanned objects are props already annexed or excluded (nearest first, one
    // each; excluded props after the annexed ones in `tracks`).
    PhysicalScene scene = scan.scene;
    std::vector<bool> taken(scene.objects.size(), false);
    // Named by a face's track of its box: the box keeps its id but stays free to vote
    // for (a prop annexed on it then carries the face).
    std::vector<bool> named(scene.objects.size(), false);
    std::vector<std::tuple<double, size_t, size_t>> pairs;
    auto id_of = [&](size_t a) -> const std::string& {
      return a < objects_.size() ? objects_[a].physical_id
                                 : excluded_[a - objects_.size()].physical_id;
    };
    const size_t known_props = objects_.size() + excluded_.size();
    for (size_t a = 0; a < known_props; ++a) {
      // Surfaces are matched on the scan's surfaces; a face tracking its box names it.
      if (a < objects_.size() && is_surface(objects_[a]) && !tracks_its_box(objects_[a])) continue;
      const Vec3 at = a < objects_.size() ? objects_[a].track.pose.position
                                          : excluded_[a - objects_.size()].track.pose.position;
      for (size_t j = 0; j < scene.objects.size(); ++j) {
        const double d = distance_to(scene.objects[j], at);
        if (d <= params_.same_prop_m) pairs.emplace_back(d, a, j);
      }
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<bool> object_done(known_props, false);
    for (const auto& [d, a, j] : pairs) {
      if (object_done[a] || taken[j] || named[j]) continue;
      object_done[a] = true;
      const bool face = a < objects_.size() && is_surface(objects_[a]);
      (face ? named : taken)[j] = true;
      scene.objects[j].id = face ? split_surface_id(id_of(a)).first : id_of(a);
    }
    // A lost prop seen again elsewhere: re-anchored on the nearest free scanned object of
    // its shape (the InitialAligner decides), keeping its physical id. So is a lost box's
    // face on its box (the box then keeps the face's owner id, free to vote for).
    TrackingInput here = input;
    here.support = scan.plane;
    here.camera_motion = {};
    for (size_t a = 0; a < objects_.size(); ++a) {
      ObjectTrack& t = objects_[a].track;
      const bool face = tracks_its_box(objects_[a]);
      if (object_done[a] || t.state != TrackingState::lost || (is_surface(objects_[a]) && !face))
        continue;
      std::vector<std::pair<double, size_t>> near;
      for (size_t j = 0; j < scene.objects.size(); ++j) {
        if (taken[j] || named[j]) continue;
        for (const PhysicalPrimitive& p : scene.objects[j].primitives)
          if (p.kind == t.model->kind && norm(p.center - t.pose.position) <= params_.reanchor_within_m)
            near.emplace_back(norm(p.center - t.pose.position), j);
      }
      std::sort(near.begin(), near.end());
      for (const auto& [d, j] : near) {
        const auto prim = std::find_if(
            scene.objects[j].primitives.begin(), scene.objects[j].primitives.end(),
            [&](const PhysicalPrimitive& p) { return p.kind == t.model->kind; });
        const ObjectTrack found = reanchor_track(t, *prim, here, params_.tracker);
        if (found.state != TrackingState::reinit) continue;
        t = found;
        (face ? named : taken)[j] = true;
        scene.objects[j].id =
            face ? split_surface_id(objects_[a].physical_id).first : objects_[a].physical_id;
        report.reanchored.push_back(objects_[a].virtual_name);
        break;
      }
    }
    // Fresh, never reused ids for the others, in scan order.
    std::vector<bool> matched(spec_.objects.size(), false);
    for (const AnnexedObject& o : objects_) matched[static_cast<size_t>(o.virtual_index)] = true;
    // An annexed face's box keeps its id (`p3` of `p3.top`) while the face is annexed:
    // no other object gets it meanwhile.
    auto owner_of_a_face = [&](const std::string& id) {
      return std::any_of(objects_.begin(), objects_.end(), [&](const AnnexedObject& o) {
        return is_surface(o) && split_surface_id(o.physical_id).first == id;
      });
    };
    int fresh = next_prop_id_;
    for (size_t j = 0; j < scene.objects.size(); ++j) {
      if (taken[j] || named[j]) continue;
      PhysicalObject& po = scene.objects[j];
      do po.id = "p" + std::to_string(fresh++);
      while (owner_of_a_face(po.id));
      // An id the user excluded before any prop had it: this prop, tracked, never votes.
      const auto waiting = std::find(exclude_waiting_.begin(), exclude_waiting_.end(), po.id);
      if (waiting == exclude_waiting_.end() || po.primitives.empty() ||
          j >= scan.clusters.size())
        continue;
      const PhysicalPrimitive& salient = po.primitives[0];
      excluded_.push_back({po.id, start_track(salient.kind, scan.clusters[j].points,
                                              {salient.center, rotation_from_z(salient.axis)},
                                              params_.model_points)});
      exclude_waiting_.erase(waiting);
      report.excluded.push_back(po.id);
      taken[j] = true;
      next_prop_id_ = std::max(next_prop_id_, fresh);
    }

    // The scan's surfaces after its objects, named after the objects' ids in the session
    // (`p7.top` of the prop the session calls p7); an annexed surface seen again is taken.
    const size_t object_count = scene.objects.size();
    if (spec_has_plane_) {
      for (PhysicalObject s : scan.surfaces) {
        // A background scan's surfaces moved into this frame's sensor coordinates: a
        // free region has no tracker to catch up with the head's motion meanwhile.
        for (PhysicalPrimitive& q : s.primitives) {
          q.center = transform_point(scan_to_now, q.center);
          q.axis = rotate(scan_to_now.rotation, q.axis);
          q.x_axis = rotate(scan_to_now.rotation, q.x_axis);
        }
        const auto [owner, kind] = split_surface_id(s.id);
        for (size_t j = 0; j < object_count; ++j)
          if (scan.scene.objects[j].id == owner) s.id = scene.objects[j].id + kind;
        // The faces of an excluded prop, and excluded surfaces, are not voted on.
        const bool excluded =
            std::find(excluded_surfaces_.begin(), excluded_surfaces_.end(), s.id) !=
                excluded_surfaces_.end() ||
            std::any_of(excluded_.begin(), excluded_.end(), [&](const ExcludedProp& e) {
              return e.physical_id == split_surface_id(s.id).first;
            });
        scene.objects.push_back(std::move(s));
        taken.push_back(excluded);
      }
      std::erase_if(excluded_surfaces_, [&](const std::string& id) {
        return std::none_of(scene.objects.begin() + static_cast<std::ptrdiff_t>(object_count),
                            scene.objects.end(),
                            [&](const PhysicalObject& s) { return s.id == id; });
      });
      const double band = 2 * params_.scan.plane_distance_m;
      for (AnnexedObject& o : objects_) {
        if (!is_surface(o)) continue;
        bool found = false;
        for (size_t j = object_count; j < scene.objects.size() && !found; ++j) {
          if (taken[j] || !same_surface(o, scene.objects[j], band, params_.same_prop_m)) continue;
          taken[j] = found = true;
          scene.objects[j].id = o.physical_id;
        }
        // A free region that something now stands on is lost; the release frees the
        // panel to vote for the free region the scan found instead.
        if (o.carrier == PoseCarrier::room) {
          if (found && o.track.state == TrackingState::lost) o.track.state = TrackingState::tracking;
          if (found) o.track.lost_frames = 0;
          if (!found && o.track.state != TrackingState::lost) {
            o.track.state = TrackingState::lost;
            o.track.confidence = 0;
          }
        }
      }
    }

    bool anyone_votes = false;
    for (size_t v = 0; v < spec_.objects.size(); ++v)
      anyone_votes = anyone_votes || (spec_.objects[v].annexable && !matched[v]);
    const bool anything_free = std::find(taken.begin(), taken.end(), false) != taken.end();
    if (anyone_votes && anything_free) {
      MatchResult result = match_objects(spec_, scene, params_.match, matched, taken);
      for (size_t r = 0; r < result.voters.size(); ++r) {
        const int vi = result.voters[r];
        const MatchEntry& m = result.matches[static_cast<size_t>(vi)];
        if (!m.physical_index) continue;
        const size_t j = static_cast<size_t>(*m.physical_index);
        const VoteExplanation& e = result.table[r][j];
        if (e.virtual_primitive < 0 || e.physical_primitive < 0) continue;
        const PhysicalObject& po = scene.objects[j];
        const auto pp = static_cast<size_t>(e.physical_primitive);
        const VirtualObject& v = spec_.objects[static_cast<size_t>(vi)];
        const Primitive& vp = v.primitives[static_cast<size_t>(e.virtual_primitive)];
        if (j >= object_count) {
          if (auto a = annex_surface(vi, vp, e.virtual_primitive, m.vote, scene, j, object_count,
                                     scan, scan_to_now, frame_index))
            objects_.push_back(std::move(*a));
          continue;
        }
        if (pp >= po.primitives.size() || j >= scan.clusters.size()) continue;
        const std::vector<ShapeFit>& fits = scan.clusters[j].shape.primitives;
        const Vec3 x_axis = pp < fits.size() ? fits[pp].x_axis : Vec3{1, 0, 0};
        AnnexedObject a;
        a.virtual_index = vi;
        a.virtual_name = v.name;
        a.physical_id = po.id;
        a.virtual_primitive = e.virtual_primitive;
        a.physical = po.primitives[pp];
        a.vote = m.vote;
        a.matched_frame = frame_index;
        a.fit = fit_to_prop(vp, a.physical);
        const Pose pose = object_frame(vp, a.physical, x_axis);
        a.track = start_track(a.physical.kind, scan.clusters[j].points, pose, params_.model_points);
        a.track.confidence = po.fit;
        objects_.push_back(std::move(a));
        next_prop_id_ = std::max(next_prop_id_, prop_number(po.id) + 1);
      }
      report.match_scene = std::move(scene);
      report.match = std::move(result);
    }
    // A prop annexed on a box whose face is annexed, or the face on an annexed box's, or
    // a prop re-anchored: the faces ride on it from this frame.
    ride_faces_on_props();
  }
  std::sort(objects_.begin(), objects_.end(), [](const AnnexedObject& a, const AnnexedObject& b) {
    return a.virtual_index < b.virtual_index;
  });
  report.objects = objects_;
  if (background) background->go();
  report.times.total_ms = ms_since(t_frame);
  return report;
}

}  // namespace annex
