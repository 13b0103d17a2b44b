// Tracking at hand speed (synthetic_motion.h): props grabbed, moved 40 mm and turned
// 15 degrees per frame, a hand gripping one, the head turning 3 degrees per frame.
// The model comes from each prop's frame-0 pixels and true pose, so these measure the
// tracker (prediction, search near the prediction, occlusion handling, camera motion).
#include <gtest/gtest.h>

#include <cstdio>

#include "annex/runtime/depth_noise.h"
#include "annex/runtime/track_model_completion.h"
#include "motion_test_util.h"

namespace annex {
namespace {

using test::median;

MotionScene make_motion(std::uint64_t seed, double speed_m, double spin_deg, double camera_deg,
                        int held, bool hand = false) {
  MotionSceneParams p;
  p.seed = seed;
  p.speed_m_per_frame = speed_m;
  p.spin_deg_per_frame = spin_deg;
  p.camera_yaw_deg_per_frame = camera_deg;
  p.held = held;
  p.hand = hand;
  Result<MotionScene> s = generate_motion_scene(p);
  if (!s) ADD_FAILURE() << s.error().format();
  return s ? *s : MotionScene{};
}

void print(const char* what, const test::MotionRun& run, const std::vector<int>& props) {
  const auto t = run.errors(run.translation_mm, props), r = run.errors(run.rotation_deg, props);
  std::printf("%s: median %.2f mm, %.2f deg over %zu poses; max %.1f mm; track %.2f ms/object\n",
              what, median(t), median(r), t.size(),
              t.empty() ? 0.0 : *std::max_element(t.begin(), t.end()), median(run.track_ms));
}

TEST(SyntheticMotion, HeldPropsMoveAtTheRequestedSpeed) {
  const MotionScene scene = make_motion(3, 0.04, 15, 3, 1);
  ASSERT_EQ(scene.props.size(), 3u);
  double max_turn = 0, max_yaw = 0;
  for (int k = 1; k < 30; ++k) {
    const Pose a = motion_prop_pose(scene, 0, k - 1), b = motion_prop_pose(scene, 0, k);
    // Full speed once the hand has picked the prop up (ramp_frames, 3).
    if (k > 3) EXPECT_NEAR(norm(b.position - a.position), 0.04, 1e-9) << "frame " << k;
    EXPECT_LE(norm(b.position - a.position), 0.04 + 1e-9) << "frame " << k;
    max_turn = std::max(max_turn, rotation_angle_deg(a.rotation, b.rotation));
    max_yaw = std::max(max_yaw, rotation_angle_deg(motion_camera_pose(scene, k - 1).rotation,
                                                   motion_camera_pose(scene, k).rotation));
    // The still props do not move in the room.
    EXPECT_EQ(motion_prop_pose(scene, 1, k), scene.props[1].rest);
    // The loop stays above the table.
    EXPECT_GE(b.position.z, scene.props[0].rest.position.z - 1e-9);
  }
  EXPECT_NEAR(max_turn, 15, 1e-6);
  EXPECT_NEAR(max_yaw, 3, 1e-6);
  MotionSceneParams bad;
  bad.speed_m_per_frame = 0.3;
  EXPECT_FALSE(generate_motion_scene(bad).ok());
}

TEST(SyntheticMotion, RendersPropsHandAndTruth) {
  const MotionScene scene = make_motion(4, 0.04, 15, 0, 1, true);
  ASSERT_FALSE(scene.hand.empty());
  const SyntheticFrame f = render_motion_frame(scene, 5);
  int hand = 0;
  std::vector<int> props(scene.props.size(), 0);
  for (int l : f.labels) {
    hand += l == kLabelOccluder;
    if (l >= 0) ++props[static_cast<size_t>(l)];
  }
  EXPECT_GT(hand, 300);
  for (int c : props) EXPECT_GT(c, 300);
  // Every prop pixel lies on the prop's surface: within its bounding sphere of the truth.
  const Pose truth = motion_prop_in_camera(scene, 0, 5);
  for (const Vec3& p : test::labelled_points(f, 0)) EXPECT_LT(norm(p - truth.position), 0.2);
  ASSERT_TRUE(f.truth.support.has_value());
}

// Two props in the hand (a cylinder and a box), a sphere left on the table.
TEST(HandSpeed, FollowsPropsAt40mmAnd15DegreesPerFrame) {
  const MotionScene scene = make_motion(5, 0.04, 15, 0, 2);
  const std::vector<SyntheticFrame> frames = test::render_motion(scene, 24);
  const test::MotionRun run = test::run_motion(scene, frames);
  print("40 mm + 15 deg/frame", run, {0, 1});
  print("  still", run, {2});
  for (int i = 0; i < 3; ++i) EXPECT_EQ(run.frames_in(TrackingState::lost, i), 0) << "prop " << i;
  EXPECT_LE(median(run.errors(run.translation_mm, {0, 1})), 5.0);
  EXPECT_LE(median(run.errors(run.rotation_deg, {0, 1})), 3.0);
  EXPECT_LE(median(run.errors(run.translation_mm, {2})), 1.0);

  // The motion model: ICP starts where the prop is expected, not where it was.
  const auto predicted = run.errors(run.predicted_mm, {0, 1});
  const auto unpredicted = run.errors(run.unpredicted_mm, {0, 1});
  std::printf("  ICP starts %.1f mm from the truth (median; %.1f mm from the last pose)\n",
              median(predicted), median(unpredicted));
  EXPECT_LT(median(predicted), 0.35 * median(unpredicted));
  EXPECT_LT(median(predicted), 12.0);
}

// One prop in the hand at 40 mm + 15 degrees per frame, two still on the table, while
// the head turns 3 degrees per frame and sways 1 cm per frame.
MotionScene head_turning_scene() {
  MotionSceneParams p;
  p.seed = 6;
  p.held = 1;
  p.camera_yaw_deg_per_frame = 3;
  p.camera_velocity_m_per_frame = {0.01, 0, 0};
  return generate_motion_scene(p).value();
}

// The head turns 3 degrees per frame (and sways 1 cm per frame) while a prop is moved:
// the camera motion is recovered from the static scene, still props stay still.
TEST(HandSpeed, SameWhileTheHeadTurns3DegreesPerFrame) {
  const MotionScene scene = head_turning_scene();
  const test::MotionRun run = test::run_motion(scene, test::render_motion(scene, 24));
  print("40 mm + 15 deg/frame, head 3 deg/frame", run, {0});
  print("  still", run, {1, 2});
  const double worst_mm = *std::max_element(run.camera_error_mm.begin(), run.camera_error_mm.end());
  const double worst_deg =
      *std::max_element(run.camera_error_deg.begin(), run.camera_error_deg.end());
  std::printf("  camera motion error at the props: median %.2f mm (max %.1f), %.3f deg (max %.2f)\n",
              median(run.camera_error_mm), worst_mm, median(run.camera_error_deg), worst_deg);
  // The turn is recovered to a tenth of a degree; a turn and a sideways step look alike
  // from a metre, so the displacement at the props errs by about a centimetre, which
  // the props' own ICP takes up (docs/tracking.md, Limits).
  EXPECT_LE(median(run.camera_error_deg), 0.3);
  EXPECT_LE(worst_deg, 2.5);
  EXPECT_LE(median(run.camera_error_mm), 20.0);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(run.frames_in(TrackingState::lost, i), 0) << "prop " << i;
  EXPECT_LE(median(run.errors(run.translation_mm, {0})), 5.0);
  EXPECT_LE(median(run.errors(run.rotation_deg, {0})), 3.0);
  // Still props: tracked on every frame, within a few millimetres.
  for (int i : {1, 2}) EXPECT_EQ(run.frames_in(TrackingState::tracking, i), 23) << "prop " << i;
  const auto still = run.errors(run.translation_mm, {1, 2});
  EXPECT_LE(median(still), 1.0);
  EXPECT_LE(*std::max_element(still.begin(), still.end()), 5.0);
}

// The head-turn sequence seen by an active stereo camera (2.4 times the Kinect's noise at
// 2 m): the held prop is followed within the hand-speed goals whichever noise the
// trackers count in; with the camera's own model more closely (0.8 against 1.1 mm).
// The head's turn is not recovered: pure yaw leaves the table's plane in place, and
// with this noise the still test cannot tell a 3 degree turn from none (the props' ICP
// takes the turn up; docs/tracking.md, Limits).
TEST(HandSpeed, AStereoCameraFollowsTheHeldPropWithItsOwnNoise) {
  const MotionScene scene = head_turning_scene();
  SensorNoiseParams noise;
  noise.axial = *depth_noise_named("stereo");
  const std::vector<SyntheticFrame> frames = test::render_motion(scene, 24, noise);
  for (const bool own : {false, true}) {
    test::MotionRunOptions o;
    if (own) o.depth_noise = noise.axial;
    const test::MotionRun run = test::run_motion(scene, frames, o);
    print(own ? "stereo camera, its noise model" : "stereo camera, the Kinect's model", run, {0});
    print("  still", run, {1, 2});
    std::printf("  camera motion error at the props: median %.1f mm, %.2f deg\n",
                median(run.camera_error_mm), median(run.camera_error_deg));
    for (int i = 0; i < 3; ++i) EXPECT_EQ(run.frames_in(TrackingState::lost, i), 0) << "prop " << i;
    EXPECT_LE(median(run.errors(run.translation_mm, {0})), 5.0);
    EXPECT_LE(median(run.errors(run.rotation_deg, {0})), 3.0);
    EXPECT_LE(median(run.errors(run.translation_mm, {1, 2})), 2.0);
  }
}

// Slow sequences (2 mm and 1 degree per frame) stay at about a millimetre.
TEST(HandSpeed, SlowPropsStayWithinAMillimetre) {
  const MotionScene scene = make_motion(7, 0.002, 1, 0, 2);
  const test::MotionRun run = test::run_motion(scene, test::render_motion(scene, 16));
  print("2 mm + 1 deg/frame", run, {0, 1});
  for (int i = 0; i < 3; ++i) EXPECT_EQ(run.frames_in(TrackingState::tracking, i), 15);
  EXPECT_LE(median(run.errors(run.translation_mm, {0, 1, 2})), 1.5);
}

// A hand grips a still prop, its fingers across the side facing the camera: the model
// points behind the fingers take no part, so the pose stays on the prop and the
// confidence drops instead.
TEST(IcpTracker, AHandGrippingThePropDoesNotPullThePose) {
  const MotionScene with_hand = make_motion(8, 0, 0, 0, 1, true);
  MotionScene bare = with_hand;
  bare.hand.clear();
  const SyntheticFrame f_bare = render_motion_frame(bare, 0);
  const SyntheticFrame f_hand = render_motion_frame(with_hand, 0);
  const CameraIntrinsics k = estimate_intrinsics(f_bare.frame).value();
  const Pose truth = motion_prop_in_camera(with_hand, 0, 0);
  const ObjectTrack t = start_track(with_hand.props[0].kind, test::labelled_points(f_bare, 0), truth);
  int hand_pixels = 0;
  for (int l : f_hand.labels) hand_pixels += l == kLabelOccluder;
  ASSERT_GT(hand_pixels, 500);
  const Pose start{truth.position + Vec3{0.006, -0.005, -0.006}, truth.rotation};
  auto run = [&](const SyntheticFrame& f, bool occlusion_test) {
    const TargetCloud target =
        segment_target_volume(f.frame, k, start.position, t.model->radius_m + 0.04, f.truth.support);
    const DepthView view{&f.frame, k};
    return track_icp(*t.model, target, start, {}, occlusion_test ? &view : nullptr);
  };
  const IcpResult clear = run(f_bare, true), gripped = run(f_hand, true);
  const IcpResult blind = run(f_hand, false);
  std::printf("hand: error %.2f mm (%.2f mm without the occlusion test), confidence %.2f "
              "(%.2f without the hand)\n",
              norm(gripped.pose.position - truth.position) * 1000,
              norm(blind.pose.position - truth.position) * 1000, gripped.confidence,
              clear.confidence);
  EXPECT_TRUE(gripped.ok);
  EXPECT_LT(norm(gripped.pose.position - truth.position), 0.003);
  EXPECT_LT(gripped.confidence, clear.confidence - 0.1);
  EXPECT_LT(gripped.coverage, 0.95);
}

// The hand moves with the prop at 40 mm and 15 degrees per frame.
TEST(HandSpeed, FollowsAPropGrippedByAHand) {
  const MotionScene scene = make_motion(9, 0.04, 15, 0, 1, true);
  MotionScene bare = scene;
  bare.hand.clear();
  const test::MotionRun run = test::run_motion(scene, test::render_motion(scene, 24));
  const test::MotionRun free_run = test::run_motion(bare, test::render_motion(bare, 24));
  print("40 mm + 15 deg/frame, gripped", run, {0});
  EXPECT_EQ(run.frames_in(TrackingState::lost, 0), 0);
  EXPECT_LE(median(run.errors(run.translation_mm, {0})), 5.0);
  EXPECT_LE(median(run.errors(run.rotation_deg, {0})), 3.0);
  const double conf_hand = median(run.confidence[0]), conf_free = median(free_run.confidence[0]);
  std::printf("  confidence: median %.2f gripped, %.2f free\n", conf_hand, conf_free);
  EXPECT_LT(conf_hand, conf_free);
}

// The motion model: constant acceleration in the room, carried through the camera's turn.
TEST(PoseTracker, PredictsFromTheRoomMotionAndTheCamera) {
  ObjectTrack t;
  t.pose = {{0.1, 0, 1}, {}};
  t.velocity_m_per_frame = {0.02, 0, 0};
  t.acceleration_m_per_frame2 = {0, 0.005, 0};
  const double a = 0.1;  // radians per frame about the sensor's y
  t.turn_per_frame = {std::cos(a / 2), 0, std::sin(a / 2), 0};
  Pose p = predict_pose(t, {}, 1);
  EXPECT_NEAR(p.position.x, 0.12, 1e-12);
  EXPECT_NEAR(p.position.y, 0.005, 1e-12);
  EXPECT_NEAR(rotation_angle_deg(p.rotation, t.turn_per_frame), 0, 1e-9);
  p = predict_pose(t, {}, 2);  // two frames: 2 v + 3 a
  EXPECT_NEAR(p.position.x, 0.14, 1e-12);
  EXPECT_NEAR(p.position.y, 0.015, 1e-12);
  // A camera that moved 5 cm left: everything moves 5 cm right in the sensor frame.
  const Pose cam{{0.05, 0, 0}, {}};
  p = predict_pose(t, cam, 1);
  EXPECT_NEAR(p.position.x, 0.17, 1e-12);
}

// The head turns while the box is in the hand (seed 5, frame 8): the box has turned so
// far that its part still in the image is a face the match-time view did not show, so
// ICP from the true pose finds nothing to pair; the completed model (the box's other
// faces, from its centre and the offsets of the faces it shows) is tracked there.
TEST(ModelCompletion, ABoxTurnedAwayFromItsMatchViewIsStillTracked) {
  const MotionScene scene = make_motion(5, 0.04, 15, 3, 2);
  const SyntheticFrame f0 = render_motion_frame(scene, 0), f8 = render_motion_frame(scene, 8);
  const CameraIntrinsics k = estimate_intrinsics(f0.frame).value();
  const Pose truth0 = motion_prop_in_camera(scene, 1, 0), truth = motion_prop_in_camera(scene, 1, 8);
  ASSERT_EQ(scene.props[1].kind, ShapeKind::box);
  const std::vector<Vec3> pts = test::labelled_points(f0, 1);
  const ObjectTrack view_only = start_track(ShapeKind::box, pts, truth0, 600, false);
  const ObjectTrack completed = start_track(ShapeKind::box, pts, truth0);
  // The half extents come out of the view: the box's true sides, within the noise.
  TrackingModel copy = *view_only.model;
  const ModelCompletion c = complete_tracking_model(copy);
  const std::vector<double>& d = scene.props[1].dimensions_m;
  EXPECT_NEAR(c.half_extents_m.x * 2, d[0], 0.006);
  EXPECT_NEAR(c.half_extents_m.y * 2, d[1], 0.006);
  EXPECT_NEAR(c.half_extents_m.z * 2, d[2], 0.006);
  EXPECT_GT(c.added_points, 100);
  EXPECT_EQ(completed.model->points.size(), view_only.model->points.size() + c.added_points);
  // Other shapes are left as they are.
  TrackingModel cylinder = *view_only.model;
  cylinder.kind = ShapeKind::cylinder;
  EXPECT_EQ(complete_tracking_model(cylinder).added_points, 0);

  const Pose start{truth.position + Vec3{0.004, -0.003, 0.004}, truth.rotation};
  const TargetCloud target = segment_target_volume(f8.frame, k, start.position,
                                                   completed.model->radius_m + 0.03, std::nullopt);
  const DepthView view{&f8.frame, k};
  const IcpResult before = track_icp(*view_only.model, target, start, {}, &view);
  const IcpResult after = track_icp(*completed.model, target, start, {}, &view);
  std::printf("box turned %.0f deg: view-only model fitness %.2f, completed %.2f (error %.2f mm)\n",
              rotation_angle_deg(truth0.rotation, truth.rotation), before.fitness, after.fitness,
              norm(after.pose.position - truth.position) * 1000);
  EXPECT_FALSE(before.ok);
  ASSERT_TRUE(after.ok);
  EXPECT_LT(norm(after.pose.position - truth.position), 0.005);
  // A sliver of one face in view: its tilt is what pins the turn.
  EXPECT_LT(test::rotation_error_deg(ShapeKind::box, truth.rotation, after.pose.rotation), 6.0);
}

// The head turns while the box is in the hand (seed 5, frame 8): most of the box has left
// the image. The points outside it are neither seen nor hidden, so the fit is judged on
// the part in view, and the confidence says how little that is.
TEST(IcpTracker, APropHalfOutOfTheImageIsJudgedOnItsPartInView) {
  const MotionScene scene = make_motion(5, 0.04, 15, 3, 2);
  const SyntheticFrame f0 = render_motion_frame(scene, 0), f8 = render_motion_frame(scene, 8);
  const CameraIntrinsics k = estimate_intrinsics(f0.frame).value();
  const ObjectTrack t =
      start_track(ShapeKind::box, test::labelled_points(f0, 1), motion_prop_in_camera(scene, 1, 0));
  const Pose truth = motion_prop_in_camera(scene, 1, 8);
  int outside = 0, facing = 0;
  for (size_t i = 0; i < t.model->points.size(); ++i) {
    const Vec3 p = transform_point(truth, t.model->points[i]);
    if (dot(rotate(truth.rotation, t.model->normals[i]), p) > 0) continue;
    ++facing;
    const double u = k.fx * p.x / p.z + k.cx, v = k.fy * p.y / p.z + k.cy;
    outside += u < -0.5 || v < -0.5 || u >= k.width - 0.5 || v >= k.height - 0.5;
  }
  ASSERT_GT(outside, facing / 2);  // the scene is what the test says
  const Pose start{truth.position + Vec3{0.003, 0.003, -0.003}, truth.rotation};
  const TargetCloud target =
      segment_target_volume(f8.frame, k, start.position, t.model->radius_m + 0.03, std::nullopt);
  const DepthView view{&f8.frame, k};
  const IcpResult r = track_icp(*t.model, target, start, {}, &view);
  std::printf("box %d of %d facing points outside the image: fitness %.2f, confidence %.2f, "
              "error %.2f mm\n", outside, facing, r.fitness, r.confidence,
              norm(r.pose.position - truth.position) * 1000);
  ASSERT_TRUE(r.ok);
  EXPECT_LT(norm(r.pose.position - truth.position), 0.005);
  EXPECT_LT(r.confidence, 0.5);
}


// The camera's motion from the static scene alone (no props move): the estimate's
// displacement error at the props' centres and its rotation error per frame.
struct CameraMotionErrors {
  std::vector<double> mm, deg;
  int still = 0, failed = 0;
};

CameraMotionErrors camera_motion_errors(const MotionScene& scene, int frames,
                                        const CameraMotionParams& params) {
  CameraMotionErrors out;
  const std::vector<SyntheticFrame> f = test::render_motion(scene, frames);
  const CameraIntrinsics k = estimate_intrinsics(f[0].frame).value();
  Pose last;
  for (int i = 1; i < frames; ++i) {
    const TrackingModel previous = static_scene_model(f[static_cast<size_t>(i - 1)].frame, k, {}, params);
    const CameraMotionResult m =
        estimate_camera_motion(previous, f[static_cast<size_t>(i)].frame, k, last, params);
    last = m.motion;
    out.still += m.still;
    out.failed += !m.ok;
    const Pose truth =
        compose(inverse(motion_camera_pose(scene, i)), motion_camera_pose(scene, i - 1));
    double worst = 0;
    for (size_t p = 0; p < scene.props.size(); ++p) {
      const Vec3 c = motion_prop_in_camera(scene, static_cast<int>(p), i - 1).position;
      worst = std::max(worst, norm(transform_point(m.motion, c) - transform_point(truth, c)));
    }
    out.mm.push_back(worst * 1000);
    out.deg.push_back(rotation_angle_deg(truth.rotation, m.motion.rotation));
  }
  return out;
}

// A still camera: the residuals of the static scene paired by pixel are the Kinect's
// noise, so the still test (chi-square, 99 %) ends nearly every frame with the identity;
// without it the pixel-paired estimate stays within a few millimetres at the props.
TEST(CameraMotion, AStillCameraIsFoundStill) {
  const MotionScene scene = make_motion(7, 0.0, 0, 0, 0);
  CameraMotionParams params;
  const CameraMotionErrors with = camera_motion_errors(scene, 12, params);
  std::printf("still camera: still test ended %d of 11 frames\n", with.still);
  EXPECT_GE(with.still, 9);
  EXPECT_EQ(with.failed, 0);
  EXPECT_LT(*std::max_element(with.mm.begin(), with.mm.end()), 3.0);
  params.still.enabled = false;
  const CameraMotionErrors without = camera_motion_errors(scene, 12, params);
  std::printf("still camera, no still test: median %.2f mm, max %.2f mm, %.3f deg\n",
              median(without.mm), *std::max_element(without.mm.begin(), without.mm.end()),
              median(without.deg));
  EXPECT_EQ(without.still, 0);
  EXPECT_EQ(without.failed, 0);
  EXPECT_LT(median(without.mm), 2.0);
  EXPECT_LT(*std::max_element(without.mm.begin(), without.mm.end()), 5.0);
}

// A head turning 3 degrees per frame (and swaying 1 cm): never still, the turn
// recovered within a fraction of a degree, the props' displacement within a centimetre
// (median; a small turn and a sideways step look alike in a room of planes).
TEST(CameraMotion, AHeadTurningIsNeverStillAndItsTurnIsRecovered) {
  MotionSceneParams p;
  p.seed = 7;
  p.held = 0;
  p.camera_yaw_deg_per_frame = 3;
  p.camera_velocity_m_per_frame = {0.01, 0, 0};
  const MotionScene scene = generate_motion_scene(p).value();
  const CameraMotionErrors e = camera_motion_errors(scene, 12, {});
  std::printf("head turning: median %.2f mm (max %.1f), %.3f deg (max %.2f), still %d\n",
              median(e.mm), *std::max_element(e.mm.begin(), e.mm.end()), median(e.deg),
              *std::max_element(e.deg.begin(), e.deg.end()), e.still);
  EXPECT_EQ(e.still, 0);
  EXPECT_EQ(e.failed, 0);
  EXPECT_LT(median(e.deg), 0.3);
  EXPECT_LT(median(e.mm), 10.0);
}

}  // namespace
}  // namespace annex

