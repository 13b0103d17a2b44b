#pragma once
// Shared by the hand-speed tests and the tracking benchmark: a synthetic_motion
// sequence tracked frame by frame as the session does it (camera motion from the
// static scene, then every prop's PoseTracker), errors against the exact truth.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "annex/runtime/camera_motion.h"
#include "annex/runtime/depth_noise.h"
#include "annex/runtime/pose_tracker.h"
#include "annex/runtime/rigid_motion.h"
#include "annex/runtime/synthetic_motion.h"
#include "annex/runtime/target_volume_segmenter.h"
#include "tracking_test_util.h"

namespace annex::test {

inline std::vector<Vec3> labelled_points(const SyntheticFrame& f, int label) {
  std::vector<Vec3> out;
  for (size_t i = 0; i < f.labels.size(); ++i) {
    const PointXYZRGB& p = f.frame.points[i];
    if (f.labels[i] == label && std::isfinite(p.z)) out.push_back({p.x, p.y, p.z});
  }
  return out;
}

struct MotionRunOptions {
  bool camera_motion = true;  // estimate the head's motion (else: identity)
  PoseTrackerParams tracker;
  // The camera's noise the trackers and the camera motion count in (a session sets it
  // from its scan's, SessionParams).
  DepthNoise depth_noise;
};

struct MotionRun {
  // Per prop, per frame 1..n-1: error (NaN when held or lost), state, confidence.
  std::vector<std::vector<double>> translation_mm, rotation_deg, confidence;
  std::vector<std::vector<TrackingState>> states;
  // Per prop, frames following a tracked one: the distance of the predicted centre and
  // of the last centre from the truth.
  std::vector<std::vector<double>> predicted_mm, unpredicted_mm;
  std::vector<double> track_ms;   // per object per frame (segment + ICP + alignment)
  std::vector<double> camera_ms;  // per frame
  // The same as CPU time of the calling thread (what the work costs, whatever else runs).
  // camera_cpu_ms: the estimate and the next frame's static scene model, as the session
  // does both once per frame.
  std::vector<double> track_cpu_ms, camera_cpu_ms;
  int camera_still_frames = 0;  // frames the still test ended (no registration)
  // Camera motion error per frame (estimate against truth): the largest displacement
  // error at a prop's centre, and the rotation error.
  std::vector<double> camera_error_mm, camera_error_deg;

  // Errors of frames with a pose (tracking or reinit) of the props in `which`.
  std::vector<double> errors(const std::vector<std::vector<double>>& e,
                             const std::vector<int>& which) const {
    std::vector<double> out;
    for (int i : which)
      for (double x : e[static_cast<size_t>(i)])
        if (!std::isnan(x)) out.push_back(x);
    return out;
  }
  int frames_in(TrackingState s, int prop) const {
    int n = 0;
    for (TrackingState x : states[static_cast<size_t>(prop)]) n += x == s;
    return n;
  }
};

// CPU time of the calling thread, milliseconds.
inline double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

inline double ms_between(std::chrono::steady_clock::time_point a,
                         std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// Tracks every prop of the rendered `frames` from its frame-0 pixels and true pose.
// ANNEX_TRACE_MOTION=1 in the environment prints every frame's camera and prop errors.
inline MotionRun run_motion(const MotionScene& scene, const std::vector<SyntheticFrame>& frames,
                            const MotionRunOptions& options = {}) {
  using Clock = std::chrono::steady_clock;
  MotionRun run;
  const SyntheticFrame& f0 = frames.at(0);
  const CameraIntrinsics camera = estimate_intrinsics(f0.frame).value();
  const size_t n = scene.props.size();
  std::vector<ObjectTrack> tracks;
  for (size_t i = 0; i < n; ++i)
    tracks.push_back(start_track(scene.props[i].kind, labelled_points(f0, static_cast<int>(i)),
                                 motion_prop_in_camera(scene, static_cast<int>(i), 0)));
  run.translation_mm.resize(n);
  run.rotation_deg.resize(n);
  run.confidence.resize(n);
  run.states.resize(n);
  run.predicted_mm.resize(n);
  run.unpredicted_mm.resize(n);
  Plane support = *f0.truth.support;
  CameraMotionParams cam_params;
  cam_params.depth_noise = options.depth_noise;
  PoseTrackerParams tracker = options.tracker;
  tracker.volume.depth_noise = options.depth_noise;
  TrackingModel static_scene = static_scene_model(f0.frame, camera, {}, cam_params);
  Pose last_motion;
  for (size_t k = 1; k < frames.size(); ++k) {
    const SyntheticFrame& f = frames[k];
    const int frame = static_cast<int>(k);
    Pose motion;
    if (options.camera_motion) {
      const auto t0 = Clock::now();
      const double c0 = thread_cpu_ms();
      const CameraMotionResult m =
          estimate_camera_motion(static_scene, f.frame, camera, last_motion, cam_params);
      run.camera_cpu_ms.push_back(thread_cpu_ms() - c0);
      run.camera_ms.push_back(ms_between(t0, Clock::now()));
      motion = m.motion;
      last_motion = m.motion;
      run.camera_still_frames += m.still;
      const Pose truth = compose(inverse(motion_camera_pose(scene, frame)),
                                 motion_camera_pose(scene, frame - 1));
      // Where the motion puts the props' centres (what the trackers predict from): a
      // turn and a sideways step look alike from 1 m, so the translation alone is not
      // the measure.
      double worst = 0;
      for (size_t i = 0; i < n; ++i) {
        const Vec3 c = motion_prop_in_camera(scene, static_cast<int>(i), frame - 1).position;
        worst = std::max(worst, norm(transform_point(motion, c) - transform_point(truth, c)));
      }
      run.camera_error_mm.push_back(worst * 1000);
      run.camera_error_deg.push_back(rotation_angle_deg(truth.rotation, motion.rotation));
      if (std::getenv("ANNEX_TRACE_MOTION"))
        std::printf("frame %d camera %s%s err %.1f mm %.2f deg fit %.2f rms %.1f mm chi2 %.1f (truth %.2f deg)\n",
                    frame, m.ok ? "ok" : "FAILED", m.still ? " still" : "", run.camera_error_mm.back(),
                    run.camera_error_deg.back(), m.fitness, m.rms_m * 1000, m.still_chi2,
                    rotation_angle_deg(truth.rotation, Quat{}));

    }
    support = transform_plane(support, motion);
    TrackingInput in;
    in.frame = &f.frame;
    in.camera = camera;
    in.support = support;
    in.camera_motion = motion;
    for (size_t i = 0; i < n; ++i) {
      // Where the motion model expects the prop, and where it was: the start of ICP
      // with and without the prediction.
      const Pose truth_now = motion_prop_in_camera(scene, static_cast<int>(i), frame);
      if (tracks[i].state == TrackingState::tracking) {
        run.predicted_mm[i].push_back(
            norm(predict_pose(tracks[i], motion).position - truth_now.position) * 1000);
        run.unpredicted_mm[i].push_back(norm(tracks[i].pose.position - truth_now.position) * 1000);
      }
      TrackStepTimes times;
      const double c0 = thread_cpu_ms();
      tracks[i] = track_step(tracks[i], in, tracker, &times);
      run.track_cpu_ms.push_back(thread_cpu_ms() - c0);
      run.track_ms.push_back(times.segment_ms + times.icp_ms + times.align_ms);
      const TrackingState s = tracks[i].state;
      run.states[i].push_back(s);
      run.confidence[i].push_back(tracks[i].confidence);
      const bool posed = s == TrackingState::tracking || s == TrackingState::reinit;
      const Pose truth = motion_prop_in_camera(scene, static_cast<int>(i), frame);
      run.translation_mm[i].push_back(posed ? norm(tracks[i].pose.position - truth.position) * 1000
                                            : std::nan(""));
      if (std::getenv("ANNEX_TRACE_MOTION"))
        std::printf("frame %d prop %zu %s err %.1f mm conf %.2f t %.2f ms\n", frame, i,
                    std::string(tracking_state_name(s)).c_str(),
                    norm(tracks[i].pose.position - truth.position) * 1000, tracks[i].confidence,
                    times.segment_ms + times.icp_ms + times.align_ms);
      run.rotation_deg[i].push_back(
          posed ? rotation_error_deg(scene.props[i].kind, truth.rotation, tracks[i].pose.rotation)
                : std::nan(""));
    }
    if (options.camera_motion) {
      const double c0 = thread_cpu_ms();
      static_scene = static_scene_model(f.frame, camera, moving_props(tracks, cam_params), cam_params);
      run.camera_cpu_ms.back() += thread_cpu_ms() - c0;
    }
  }
  return run;
}

inline std::vector<SyntheticFrame> render_motion(const MotionScene& scene, int frames,
                                                 const SensorNoiseParams& noise = {}) {
  std::vector<SyntheticFrame> out;
  for (int k = 0; k < frames; ++k) out.push_back(render_motion_frame(scene, k, noise));
  return out;
}

}  // namespace annex::test
