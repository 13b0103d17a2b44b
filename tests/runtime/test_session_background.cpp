// AnnexSession for render loops: ScanMode::background (the scan runs on the session's
// worker and applies a frame later, with the same matches as a same-frame scan), the
// parameter checks at creation (and in scan_frame), known camera intrinsics.
#include <gtest/gtest.h>

#include <stdexcept>

#include "annex/runtime/annex_session.h"
#include "annex/runtime/params_validation.h"
#include "annex/runtime/synthetic_scene.h"
#include "session_fixture.h"

namespace annex {
namespace {

using test::make_scene;
using test::spec_for;

// Frame 0's scan applies at frame 1 (waited for here, so the test does not depend on
// timing) with the matches a same-frame session makes at frame 0; later scans start
// every scan_every frames and never in the frame they apply.
TEST(SessionBackground, ScanAppliesAFrameLaterWithTheSameMatches) {
  const SyntheticScene scene = make_scene(31);
  const HapticSpec spec = spec_for(scene);
  SessionParams params;
  params.scan_every = 4;
  AnnexSession same(spec, params);
  params.scan_mode = ScanMode::background;
  AnnexSession background(spec, params);

  const FrameReport s0 = same.process(render_scene(scene, {}, 0).frame);
  ASSERT_EQ(s0.objects.size(), 3u);
  const FrameReport b0 = background.process(render_scene(scene, {}, 0).frame);
  EXPECT_FALSE(b0.scanned);
  EXPECT_TRUE(b0.objects.empty());
  EXPECT_TRUE(background.scan_in_flight());
  background.wait_for_scan();
  const FrameReport b1 = background.process(render_scene(scene, {}, 1).frame);
  ASSERT_TRUE(b1.scanned);
  EXPECT_EQ(b1.scan_frame_index, 0);
  ASSERT_TRUE(b1.scan.has_value()) << (b1.scan_error ? b1.scan_error->format() : "");
  ASSERT_EQ(b1.objects.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(b1.objects[i].virtual_name, s0.objects[i].virtual_name);
    EXPECT_EQ(b1.objects[i].physical_id, s0.objects[i].physical_id);
    EXPECT_EQ(b1.objects[i].matched_frame, 1);
    EXPECT_LT(norm(b1.objects[i].track.pose.position - s0.objects[i].track.pose.position), 1e-9);
  }
  std::vector<int> scan_frames;
  for (int k = 2; k < 16; ++k) {
    const FrameReport r = background.process(render_scene(scene, {}, k).frame);
    ASSERT_EQ(r.objects.size(), 3u) << "frame " << k;
    for (const AnnexedObject& o : r.objects)
      EXPECT_EQ(o.track.state, TrackingState::tracking) << o.virtual_name << " frame " << k;
    if (r.scanned) {
      EXPECT_LT(r.scan_frame_index, k);
      scan_frames.push_back(r.scan_frame_index);
      EXPECT_FALSE(r.match.has_value()) << "everyone has a prop: nobody votes";
    }
    background.wait_for_scan();
  }
  // Started every scan_every frames after the match at frame 1, each applied a frame later.
  EXPECT_EQ(scan_frames, (std::vector<int>{5, 9, 13}));
}

TEST(SessionBackground, ParamsAreCheckedAtCreation) {
  SessionParams params;
  params.scan.min_cluster_points = -5;
  const Result<AnnexSession> s = AnnexSession::create({}, params);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message,
            "SessionParams.scan.min_cluster_points must be at least 1, got -5");
  EXPECT_THROW(AnnexSession({}, params), std::invalid_argument);

  params = {};
  params.tracker.icp.final_correspondence_m = 0.5;  // above max_correspondence_m
  EXPECT_NE(validate_session_params(params).error().message.find(
                "SessionParams.tracker.icp.final_correspondence_m must be in (0, 0.02]"),
            std::string::npos);
  params = {};
  params.camera = CameraIntrinsics{640, 480, 525, 525, 900, 239.5};
  EXPECT_NE(validate_session_params(params).error().message.find("SessionParams.camera.cx"),
            std::string::npos);
  // scan_frame checks the parameters set in code too, before looking at the frame.
  ScanParams scan;
  scan.cluster_tolerance_m = -0.02;
  const Result<ScanResult> r = scan_frame(render_scene(make_scene(31), {}, 0).frame, scan);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "ScanParams.cluster_tolerance_m must be greater than 0, got -0.02");
  EXPECT_TRUE(validate_session_params({}).ok());
  EXPECT_TRUE(validate_scan_params({}).ok());
  EXPECT_TRUE(validate_tracker_params({}).ok());
}

// Known intrinsics stand in for the estimate: tracking works the same with them.
TEST(SessionBackground, UsesGivenIntrinsics) {
  const SyntheticScene scene = make_scene(33);
  SessionParams params;
  params.camera = CameraIntrinsics{};  // the generator's camera
  AnnexSession session(spec_for(scene), params);
  for (int k = 0; k < 6; ++k) {
    const FrameReport r = session.process(render_scene(scene, {}, k).frame);
    ASSERT_EQ(r.objects.size(), 3u) << "frame " << k;
    for (const AnnexedObject& o : r.objects)
      EXPECT_EQ(o.track.state, TrackingState::tracking) << o.virtual_name << " frame " << k;
  }
}

}  // namespace
}  // namespace annex
