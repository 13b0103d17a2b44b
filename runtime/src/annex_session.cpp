// The runtime loop: ObjectFinder (scan, vote, match) and one PoseTracker per match.
#include "annex/runtime/annex_session.h"

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <thread>

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

// Runs fn(0..count-1) on up to `threads` threads (the calling thread is not one of them,
// so it can scan meanwhile); `join` waits for all.
class TaskGroup {
 public:
  template <typename Fn>
  TaskGroup(int count, int threads, Fn fn) {
    const int n = std::min(count, std::max(1, threads));
    for (int w = 0; w < n; ++w)
      workers_.emplace_back([this, count, fn] {
        for (int i = next_++; i < count; i = next_++) fn(i);
      });
  }
  void join() {
    for (std::thread& t : workers_) t.join();
    workers_.clear();
  }
  ~TaskGroup() { join(); }

 private:
  std::atomic<int> next_{0};
  std::vector<std::thread> workers_;
};

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
  return affine_from_pose(object.track.pose) * scale * inverse_rigid(prim.pose);
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
  return line;
}

AnnexSession::AnnexSession(HapticSpec spec, SessionParams params)
    : spec_(std::move(spec)), params_(std::move(params)) {}

FrameReport AnnexSession::process(const Frame& frame) {
  const auto t_frame = Clock::now();
  FrameReport report;
  report.frame_index = frame.index;
  // Recovered from the first frame that allows it (until then cubes are cut by a full scan).
  if (!camera_ || camera_->width != frame.width || camera_->height != frame.height) {
    camera_.reset();
    if (Result<CameraIntrinsics> k = estimate_intrinsics(frame)) camera_ = *k;
  }

  // Scan until something is annexed, then every scan_every frames.
  const bool scan_now = objects_.empty() || ++frames_since_scan_ >= params_.scan_every;

  // Trackers run on the pool while this thread scans.
  TrackingInput input;
  input.frame = &frame;
  input.camera = camera_;
  input.support = supports_.empty() ? std::nullopt : std::optional<Plane>(supports_.front().plane);
  std::vector<ObjectTrack> tracked(objects_.size());
  std::vector<TrackingInput> inputs(objects_.size(), input);
  for (size_t i = 0; i < objects_.size(); ++i)
    if (auto s = support_below(supports_, objects_[i].track.pose.position)) inputs[i].support = s;
  for (size_t i = 0; i < objects_.size(); ++i)
    for (const PhysicalObject& o : last_scan_objects_)
      for (const PhysicalPrimitive& p : o.primitives)
        if (p.kind == objects_[i].track.model->kind) inputs[i].candidates.push_back(p.center);
  const auto t_track = Clock::now();
  TaskGroup pool(static_cast<int>(objects_.size()), params_.threads, [&](int i) {
    tracked[i] = track_step(objects_[i].track, inputs[i], params_.tracker);
  });
  if (scan_now) {
    const auto t0 = Clock::now();
    Result<ScanResult> scan = scan_frame(frame, params_.scan);
    report.times.scan_ms = ms_since(t0);
    report.scanned = true;
    frames_since_scan_ = 0;
    if (scan) {
      report.scan = std::move(scan.value());
    } else {
      report.scan_error = scan.error();
    }
  }
  pool.join();
  report.times.track_ms = ms_since(t_track);
  for (size_t i = 0; i < objects_.size(); ++i) objects_[i].track = std::move(tracked[i]);

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
    // Which scanned objects are props already annexed (nearest first, one each).
    PhysicalScene scene = scan.scene;
    std::vector<bool> taken(scene.objects.size(), false);
    std::vector<std::tuple<double, size_t, size_t>> pairs;
    for (size_t a = 0; a < objects_.size(); ++a)
      for (size_t j = 0; j < scene.objects.size(); ++j) {
        const double d = distance_to(scene.objects[j], objects_[a].track.pose.position);
        if (d <= params_.same_prop_m) pairs.emplace_back(d, a, j);
      }
    std::sort(pairs.begin(), pairs.end());
    std::vector<bool> object_done(objects_.size(), false);
    for (const auto& [d, a, j] : pairs) {
      if (object_done[a] || taken[j]) continue;
      object_done[a] = true;
      taken[j] = true;
      scene.objects[j].id = objects_[a].physical_id;
    }
    // Fresh, never reused ids for the others, in scan order.
    std::vector<bool> matched(spec_.objects.size(), false);
    for (const AnnexedObject& o : objects_) matched[static_cast<size_t>(o.virtual_index)] = true;
    int fresh = next_prop_id_;
    for (size_t j = 0; j < scene.objects.size(); ++j)
      if (!taken[j]) scene.objects[j].id = "p" + std::to_string(fresh++);

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
        if (pp >= po.primitives.size() || j >= scan.clusters.size()) continue;
        const VirtualObject& v = spec_.objects[static_cast<size_t>(vi)];
        const Primitive& vp = v.primitives[static_cast<size_t>(e.virtual_primitive)];
        const std::vector<ShapeFit>& fits = scan.clusters[j].shape.primitives;
        const Vec3 x_axis = pp < fits.size() ? fits[pp].x_axis : Vec3{1, 0, 0};
        AnnexedObject a;
        a.virtual_index = vi;
        a.virtual_name = v.name;
        a.physical_id = po.id;
        a.virtual_primitive = e.virtual_primitive;
        a.physical = po.primitives[pp];
        a.vote = m.vote;
        a.matched_frame = frame.index;
        a.fit = fit_to_prop(vp, a.physical);
        const Pose pose = object_frame(vp, a.physical, x_axis);
        a.track = start_track(a.physical.kind, scan.clusters[j].points, pose, params_.model_points);
        a.track.confidence = po.fit;
        objects_.push_back(std::move(a));
        const int id = std::stoi(po.id.substr(1));
        next_prop_id_ = std::max(next_prop_id_, id + 1);
      }
      report.match_scene = std::move(scene);
      report.match = std::move(result);
    }
  }
  std::sort(objects_.begin(), objects_.end(), [](const AnnexedObject& a, const AnnexedObject& b) {
    return a.virtual_index < b.virtual_index;
  });
  report.objects = objects_;
  report.times.total_ms = ms_since(t_frame);
  return report;
}

}  // namespace annex
