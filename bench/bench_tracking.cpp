// Tracking benchmarks (docs/BENCHMARKS.md, "Tracking"): one PoseTracker step per
// object per frame, our ICP next to PCL's on the same target volumes, the
// InitialAligner (seeded, and the FPFH fallback), and the whole runtime loop on a
// 640x480 stream with 3 tracked props (no rendering).
#include <benchmark/benchmark.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "annex/runtime/annex_session.h"
#include "annex/runtime/pose_tracker.h"
#include "annex/runtime/synthetic_scene.h"
#include "motion_test_util.h"

namespace annex {
namespace {

constexpr int kFrames = 12;

struct Sequence {
  SyntheticScene scene;
  std::vector<SyntheticFrame> frames;
  CameraIntrinsics camera;
};

// Three props (cylinder, sphere, box) drifting and turning. Rendering takes about a
// second, so every benchmark below runs a fixed number of iterations: its function (and
// this setup) then runs once.
Sequence make_sequence() {
  Sequence s;
  SyntheticSceneParams p;
  p.seed = 31;
  p.object_count = 3;
  p.kinds = {ShapeKind::cylinder, ShapeKind::sphere, ShapeKind::box};
  s.scene = generate_scene(p).value();
  for (int k = 0; k < kFrames; ++k) s.frames.push_back(render_scene(s.scene, {}, k));
  s.camera = estimate_intrinsics(s.frames[0].frame).value();
  return s;
}

Pose truth_pose(const SyntheticScene& scene, int i, int frame) {
  const SyntheticScene s = scene_at_frame(scene, frame);
  const SyntheticObject& o = s.objects[static_cast<size_t>(i)];
  const double yaw = o.yaw_deg * std::numbers::pi / 180.0;
  const Vec3 x = table_to_camera_direction(s, {std::cos(yaw), std::sin(yaw), 0});
  const Vec3 z = table_to_camera_direction(s, {0, 0, 1});
  return {table_to_camera_point(s, o.center), quat_from_axes(x, cross(z, x), z)};
}

ObjectTrack track_for(const Sequence& s, int i) {
  std::vector<Vec3> pts;
  const SyntheticFrame& f = s.frames[0];
  for (size_t k = 0; k < f.labels.size(); ++k)
    if (f.labels[k] == i && std::isfinite(f.frame.points[k].z))
      pts.push_back({f.frame.points[k].x, f.frame.points[k].y, f.frame.points[k].z});
  return start_track(s.scene.objects[static_cast<size_t>(i)].kind, pts, truth_pose(s.scene, i, 0));
}

// One object, one frame: segment the cube, ICP. Arg: the object (0 cylinder, 1 sphere, 2 box).
void BM_TrackStepPerObject(benchmark::State& state) {
  const Sequence s = make_sequence();
  const int i = static_cast<int>(state.range(0));
  const ObjectTrack start = track_for(s, i);
  ObjectTrack t = start;
  int k = 1;
  for (auto _ : state) {
    TrackingInput in{
        &s.frames[static_cast<size_t>(k)].frame, s.camera, s.frames[0].truth.support, {}, {}};
    t = track_step(t, in);
    benchmark::DoNotOptimize(t.pose);
    if (++k == kFrames) {
      k = 1;
      t = start;
    }
  }
  state.SetLabel(std::string(shape_name(s.scene.objects[static_cast<size_t>(i)].kind)));
}
BENCHMARK(BM_TrackStepPerObject)
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Iterations(600)
    ->Unit(benchmark::kMillisecond);

// One ICP per frame on fixed inputs: the target volume around the previous true pose
// and that pose as the start, so both ICPs solve the same problems.
struct IcpCase {
  TargetCloud target;
  Pose initial, truth;
};

std::vector<IcpCase> icp_cases(const Sequence& s, const ObjectTrack& t, int i) {
  std::vector<IcpCase> cases;
  for (int k = 1; k < kFrames; ++k) {
    IcpCase c;
    c.initial = truth_pose(s.scene, i, k - 1);
    c.truth = truth_pose(s.scene, i, k);
    c.target = segment_target_volume(s.frames[static_cast<size_t>(k)].frame, s.camera,
                                     c.initial.position, t.model->radius_m + 0.03,
                                     s.frames[0].truth.support);
    cases.push_back(std::move(c));
  }
  return cases;
}

// Ours: point-to-plane, voxel-hash neighbours, symmetric rotations left out.
void BM_IcpOurs(benchmark::State& state) {
  const Sequence s = make_sequence();
  const int i = static_cast<int>(state.range(0));
  const ObjectTrack t = track_for(s, i);
  const std::vector<IcpCase> cases = icp_cases(s, t, i);
  double error_mm = 0;
  size_t k = 0;
  for (auto _ : state) {
    const IcpCase& c = cases[k];
    const IcpResult r = track_icp(*t.model, c.target, c.initial);
    error_mm += norm(r.pose.position - c.truth.position) * 1000;
    k = (k + 1) % cases.size();
  }
  state.counters["error_mm"] = benchmark::Counter(error_mm, benchmark::Counter::kAvgIterations);
  state.SetLabel(std::string(shape_name(s.scene.objects[static_cast<size_t>(i)].kind)));
}
BENCHMARK(BM_IcpOurs)->Arg(0)->Arg(1)->Arg(2)->Iterations(220)->Unit(benchmark::kMillisecond);

// PCL 1.13's pcl::IterativeClosestPoint (point-to-point, kd-tree) with the same
// correspondence distance (2 cm) and iteration cap (20).
void BM_IcpPcl(benchmark::State& state) {
  const Sequence s = make_sequence();
  const int i = static_cast<int>(state.range(0));
  const ObjectTrack t = track_for(s, i);
  const std::vector<IcpCase> cases = icp_cases(s, t, i);
  auto to_cloud = [](const std::vector<Vec3>& pts, const Pose& pose) {
    auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    for (const Vec3& p : pts) {
      const Vec3 q = pose.position + rotate(pose.rotation, p);
      cloud->push_back({static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z)});
    }
    return cloud;
  };
  std::vector<pcl::PointCloud<pcl::PointXYZ>::Ptr> sources, targets;
  for (const IcpCase& c : cases) {
    sources.push_back(to_cloud(t.model->points, c.initial));
    targets.push_back(to_cloud(c.target.points, Pose{}));
  }
  double error_mm = 0;
  size_t k = 0;
  pcl::PointCloud<pcl::PointXYZ> aligned;
  for (auto _ : state) {
    pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
    icp.setInputSource(sources[k]);
    icp.setInputTarget(targets[k]);
    icp.setMaxCorrespondenceDistance(0.02);
    icp.setMaximumIterations(20);
    icp.setTransformationEpsilon(1e-8);
    icp.align(aligned);
    // The model's origin moved by the final transform: compare it with the truth.
    const Eigen::Matrix4f m = icp.getFinalTransformation();
    const Vec3 o = cases[k].initial.position;
    const Vec3 moved{m(0, 0) * o.x + m(0, 1) * o.y + m(0, 2) * o.z + m(0, 3),
                     m(1, 0) * o.x + m(1, 1) * o.y + m(1, 2) * o.z + m(1, 3),
                     m(2, 0) * o.x + m(2, 1) * o.y + m(2, 2) * o.z + m(2, 3)};
    error_mm += norm(moved - cases[k].truth.position) * 1000;
    k = (k + 1) % cases.size();
  }
  state.counters["error_mm"] = benchmark::Counter(error_mm, benchmark::Counter::kAvgIterations);
  state.SetLabel(std::string(shape_name(s.scene.objects[static_cast<size_t>(i)].kind)));
}
BENCHMARK(BM_IcpPcl)->Arg(0)->Arg(1)->Arg(2)->Iterations(220)->Unit(benchmark::kMillisecond);

// Re-initialisation: the object 3 cm and 30 degrees from its last pose; seeded aligner.
void BM_InitialAlignSeeded(benchmark::State& state) {
  const Sequence s = make_sequence();
  const int i = static_cast<int>(state.range(0));
  const ObjectTrack t = track_for(s, i);
  const Pose truth = truth_pose(s.scene, i, 6);
  InitialAlignInput in;
  in.frame = &s.frames[6].frame;
  in.camera = s.camera;
  in.support = s.frames[0].truth.support;
  const double a = 30 * std::numbers::pi / 180;
  const Vec3 up = in.support->normal;
  in.orientation = normalized(Quat{std::cos(a / 2), up.x * std::sin(a / 2), up.y * std::sin(a / 2),
                                   up.z * std::sin(a / 2)} *
                              truth.rotation);
  in.positions = {truth.position + Vec3{0.03, 0, 0}};
  int ok = 0;
  for (auto _ : state) {
    const InitialAlignResult r = align_initial(*t.model, in);
    ok += r.ok;
    benchmark::DoNotOptimize(r.pose);
  }
  state.counters["ok"] = benchmark::Counter(ok, benchmark::Counter::kAvgIterations);
  state.SetLabel(std::string(shape_name(s.scene.objects[static_cast<size_t>(i)].kind)));
}
BENCHMARK(BM_InitialAlignSeeded)
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Iterations(40)
    ->Unit(benchmark::kMillisecond);

// The paper's aligner for comparison: FPFH (2.5 cm) + prerejective RANSAC on the box.
void BM_InitialAlignFpfh(benchmark::State& state) {
  const Sequence s = make_sequence();
  const ObjectTrack t = track_for(s, 2);
  const Pose truth = truth_pose(s.scene, 2, 6);
  const TargetCloud target =
      segment_target_volume(s.frames[6].frame, s.camera, truth.position, t.model->radius_m + 0.05,
                            s.frames[0].truth.support);
  int found = 0;
  for (auto _ : state) {
    const auto pose = align_fpfh(*t.model, target);
    found += pose.has_value();
    benchmark::DoNotOptimize(pose);
  }
  state.counters["found"] = benchmark::Counter(found, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_InitialAlignFpfh)->Iterations(30)->Unit(benchmark::kMillisecond);

// Hand speed (synthetic_motion.h): Arg 3 props in the hand (the cylinder, then the box)
// moving at Arg 0 mm and turning at Arg 1 degrees per frame, the others (box, sphere)
// left on the table, the head turning at Arg 2 degrees per frame; 24 frames, camera
// motion from the static scene. Counters: median errors of the held props (mm, degrees
// modulo symmetry), their lost and held frames, the still props' median error, and the
// CPU time per object per frame and of the camera motion per frame (its estimate and
// the next static scene model; thread CPU, so other processes on the machine do not
// count), the frames the still test ended and the camera motion's median displacement
// error at the props.
void BM_HandSpeed(benchmark::State& state) {
  MotionSceneParams p;
  p.seed = 5;
  p.held = static_cast<int>(state.range(3));
  p.speed_m_per_frame = static_cast<double>(state.range(0)) / 1000;
  p.spin_deg_per_frame = static_cast<double>(state.range(1));
  p.camera_yaw_deg_per_frame = static_cast<double>(state.range(2));
  const MotionScene scene = generate_motion_scene(p).value();
  const std::vector<SyntheticFrame> frames = test::render_motion(scene, 24);
  test::MotionRun run;
  for (auto _ : state) run = test::run_motion(scene, frames);
  std::vector<int> held, still;
  for (int i = 0; i < static_cast<int>(scene.props.size()); ++i)
    (scene.props[static_cast<size_t>(i)].held ? held : still).push_back(i);
  const auto t = run.errors(run.translation_mm, held), r = run.errors(run.rotation_deg, held);
  state.counters["median_mm"] = test::median(t);
  state.counters["median_deg"] = test::median(r);
  int lost = 0, held_frames = 0;
  for (int i : held) {
    lost += run.frames_in(TrackingState::lost, i);
    held_frames += run.frames_in(TrackingState::held, i);
  }
  state.counters["lost"] = lost;
  state.counters["held"] = held_frames;
  state.counters["still_mm"] = test::median(run.errors(run.translation_mm, still));
  state.counters["cpu_ms_obj"] = test::median(run.track_cpu_ms);
  std::vector<double> sorted = run.track_cpu_ms;
  std::sort(sorted.begin(), sorted.end());
  state.counters["cpu_ms_p90"] = sorted.empty() ? 0 : sorted[sorted.size() * 9 / 10];
  state.counters["camera_ms"] = test::median(run.camera_cpu_ms);
  std::vector<double> camera = run.camera_cpu_ms;
  std::sort(camera.begin(), camera.end());
  state.counters["camera_ms_p90"] = camera.empty() ? 0 : camera[camera.size() * 9 / 10];
  state.counters["camera_still"] = run.camera_still_frames;
  state.counters["camera_err_mm"] = test::median(run.camera_error_mm);
}
BENCHMARK(BM_HandSpeed)
    ->Args({2, 1, 0, 2})
    ->Args({20, 8, 0, 2})
    ->Args({40, 15, 0, 2})
    ->Args({60, 20, 0, 2})
    ->Args({40, 15, 3, 1})
    ->Args({40, 15, 3, 2})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

// The runtime loop without rendering: 3 props matched on frame 0, then tracked, a scan
// every 10 frames. Items per second = frames per second.
void BM_SessionFrame(benchmark::State& state) {
  const Sequence s = make_sequence();
  HapticSpec spec;
  for (size_t i = 0; i < s.scene.objects.size(); ++i) {
    VirtualObject v;
    v.name = "v" + std::to_string(i);
    Primitive p = make_primitive(s.scene.objects[i].kind, "body");
    for (size_t d = 0; d < p.dimensions.size(); ++d)
      p.dimensions[d].value_m = s.scene.objects[i].dimensions_m[d];
    v.primitives.push_back(p);
    spec.objects.push_back(v);
  }
  SessionParams params;
  params.threads = static_cast<int>(state.range(0));
  AnnexSession session(spec, params);
  session.process(s.frames[0].frame);
  int k = 1;
  size_t tracked = 0;
  for (auto _ : state) {
    const FrameReport r = session.process(s.frames[static_cast<size_t>(k)].frame);
    tracked += r.objects.size();
    if (++k == kFrames) k = 1;  // the props jump back: a re-initialisation now and then
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["objects"] =
      benchmark::Counter(static_cast<double>(tracked), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_SessionFrame)
    ->Arg(1)
    ->Arg(2)
    ->Iterations(220)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace annex
