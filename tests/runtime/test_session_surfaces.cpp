// Virtual panels (plane primitives) in the runtime loop: the session matches them to the
// scan's flat surfaces, a box's top rides on its moving box, a support's free region
// stays in the room while the camera moves, surfaces are excluded like props, and scans
// skip surfaces when no virtual object has a plane.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <optional>
#include <filesystem>
#include <string>

#include "annex/formats/haptic_format.h"
#include "annex/runtime/annex_session.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/rigid_motion.h"
#include "annex/runtime/synthetic_motion.h"
#include "annex/runtime/synthetic_scene.h"

namespace annex {
namespace {

HapticSpec panel_spec(double size_x, double size_y) {
  const std::string text = "annex-haptic 1\nobject panel\n  primitive face plane\n    size_x " +
                           std::to_string(size_x) + "\n    size_y " + std::to_string(size_y) +
                           "\n  end\nend\n";
  Result<HapticSpec> spec = parse_haptic(text, "panel.haptic");
  EXPECT_TRUE(spec.ok()) << spec.error().format();
  return spec ? *spec : HapticSpec{};
}

const AnnexedObject* find_virtual(const FrameReport& r, const std::string& name) {
  for (const AnnexedObject& o : r.objects)
    if (o.virtual_name == name) return &o;
  return nullptr;
}

// A 22 x 16 x 8 cm box on the table, seen from 0.75 m back and 0.7 m up, drifting along
// x by `drift_m_per_frame`.
SyntheticScene box_on_the_table(double drift_m_per_frame) {
  SyntheticScene scene;
  scene.camera_position = {0, -0.75, 0.7};
  scene.camera_tilt_deg = 45;
  scene.objects.push_back(resting_object(ShapeKind::box, {0.22, 0.16, 0.08}, -0.1, 0));
  scene.objects.back().velocity_m_per_frame = {drift_m_per_frame, 0, 0};
  return scene;
}

// The centre of the top of the frame's one box, from its ground truth.
Vec3 true_top(const SyntheticFrame& f) {
  EXPECT_EQ(f.truth.objects.size(), 1u);
  EXPECT_TRUE(f.truth.support.has_value());
  if (f.truth.objects.empty() || !f.truth.support) return {};
  const PhysicalPrimitive& box = f.truth.objects[0].primitives.at(0);
  return box.center + normalized(f.truth.support->normal) * (box.dimensions_m[2] / 2);
}

// Where the panel's centre is (its primitive sits at the model's origin).
Vec3 panel_centre(const HapticSpec& spec, const AnnexedObject& o) {
  return decompose_model_transform(world_from_model(spec, o)).translation;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// A box drifting across the table, 8 mm a frame: a panel of its top's size is laid on
// the top and moves with the box's track, on the face's centre within 2 cm each frame.
TEST(SessionSurfaces, APanelOnABoxTopMovesWithTheBox) {
  const SyntheticScene scene = box_on_the_table(0.008);
  const HapticSpec spec = panel_spec(0.22, 0.16);
  SessionParams params;
  params.scan_every = 5;
  AnnexSession session(spec, params);
  int annexed_frames = 0;
  Vec3 first_at, last_at;
  for (int k = 0; k < 25; ++k) {
    const SyntheticFrame f = render_scene(scene, {}, k);
    const FrameReport r = session.process(f.frame, k);
    const AnnexedObject* panel = find_virtual(r, "panel");
    if (!panel) continue;
    EXPECT_TRUE(ends_with(panel->physical_id, ".top")) << panel->physical_id;
    EXPECT_EQ(panel->carrier, PoseCarrier::track);
    const Vec3 at = panel_centre(spec, *panel);
    EXPECT_LT(norm(at - true_top(f)), 0.02) << "frame " << k << " state "
                                    << tracking_state_name(panel->track.state);
    if (annexed_frames++ == 0) first_at = at;
    last_at = at;
  }
  EXPECT_GE(annexed_frames, 20);
  EXPECT_GT(norm(last_at - first_at), 0.12) << "the panel did not follow the box";
}

// A crate (a box prop) and a panel of its top's size, both annexable: one virtual object
// takes the box as a prop, the other its top as a panel. The box is tracked once: the
// panel rides on the crate's track (the same model, the same pose, every frame) and lies
// on the drifting box's top within 2 cm.
TEST(SessionSurfaces, ABoxAnnexedAsAPropAndAsAPanelIsTrackedOnce) {
  const SyntheticScene scene = box_on_the_table(0.008);
  Result<HapticSpec> spec = parse_haptic(
      "annex-haptic 1\n"
      "object crate\n  primitive body box\n    size_x 0.22\n    size_y 0.16\n    size_z 0.08\n"
      "  end\nend\n"
      "object panel\n  primitive face plane\n    size_x 0.22\n    size_y 0.16\n  end\nend\n",
      "crate_and_panel.haptic");
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  SessionParams params;
  params.scan_every = 5;
  AnnexSession session(*spec, params);
  int both = 0;
  Vec3 first_at, last_at;
  for (int k = 0; k < 25; ++k) {
    const SyntheticFrame f = render_scene(scene, {}, k);
    const FrameReport r = session.process(f.frame, k);
    const AnnexedObject* crate = find_virtual(r, "crate");
    const AnnexedObject* panel = find_virtual(r, "panel");
    if (!crate || !panel) {
      EXPECT_EQ(both, 0) << "frame " << k << ": one of the two was dropped";
      continue;
    }
    EXPECT_EQ(panel->physical_id, crate->physical_id + ".top") << "frame " << k;
    EXPECT_EQ(crate->carrier, PoseCarrier::track);
    EXPECT_EQ(panel->carrier, PoseCarrier::prop) << "frame " << k;
    EXPECT_EQ(panel->track.model.get(), crate->track.model.get()) << "frame " << k;
    EXPECT_EQ(panel->track.pose, crate->track.pose) << "frame " << k;
    EXPECT_EQ(panel->track.state, crate->track.state) << "frame " << k;
    const Vec3 at = panel_centre(*spec, *panel);
    EXPECT_LT(norm(at - true_top(f)), 0.02) << "frame " << k;
    if (both++ == 0) first_at = at;
    last_at = at;
  }
  EXPECT_GE(both, 20);
  EXPECT_GT(norm(last_at - first_at), 0.12) << "the panel did not follow the box";

  // Excluding the crate's box releases the crate and the panel on its top.
  const FrameReport last = session.process(render_scene(scene, {}, 25).frame, 25);
  const AnnexedObject* crate = find_virtual(last, "crate");
  ASSERT_NE(crate, nullptr);
  const std::string box_id = crate->physical_id;
  session.exclude(box_id);
  const FrameReport r = session.process(render_scene(scene, {}, 26).frame, 26);
  EXPECT_EQ(r.excluded, std::vector<std::string>{box_id});
  EXPECT_EQ(r.released, (std::vector<std::string>{"crate", "panel"}));
}

// A box with a panel on its top (no prop of the box annexed) is hidden while it is
// carried 12 cm away: the face's track of its box goes lost, and the first scan after
// the box reappears re-anchors it under the same id, as a lost prop is; the panel then
// lies on the top at its new place within 2 cm.
TEST(SessionSurfaces, ALostBoxFaceIsReanchoredUnderItsId) {
  const SyntheticScene scene = box_on_the_table(0);
  SyntheticScene moved = scene;
  moved.objects[0].center = moved.objects[0].center + Vec3{0.12, 0, 0};
  const HapticSpec spec = panel_spec(0.22, 0.16);
  SessionParams params;
  params.scan_every = 5;
  params.camera_motion = false;
  AnnexSession session(spec, params);
  std::string id;
  std::optional<int> reanchored_at;
  bool went_unseen = false;
  for (int k = 0; k < 16; ++k) {
    SyntheticFrame f = render_scene(k < 8 ? scene : moved, {}, k);
    if (k >= 6 && k < 10)
      for (size_t i = 0; i < f.labels.size(); ++i)
        if (f.labels[i] == 0) f.frame.points[i].z = std::numeric_limits<float>::quiet_NaN();
    const FrameReport r = session.process(f.frame, k);
    const AnnexedObject* panel = find_virtual(r, "panel");
    ASSERT_NE(panel, nullptr) << "frame " << k << ": released";
    if (k == 0) id = panel->physical_id;
    EXPECT_TRUE(ends_with(id, ".top")) << id;
    EXPECT_EQ(panel->physical_id, id) << "frame " << k;
    EXPECT_EQ(panel->carrier, PoseCarrier::track);
    went_unseen = went_unseen || (k >= 6 && k < 10 && panel->track.state != TrackingState::tracking);
    if (k > 0 && r.match)
      EXPECT_TRUE(r.match->voters.empty()) << "frame " << k << ": the panel voted again";
    if (!reanchored_at &&
        std::find(r.reanchored.begin(), r.reanchored.end(), "panel") != r.reanchored.end())
      reanchored_at = k;
    if (reanchored_at && k > *reanchored_at) {
      EXPECT_EQ(panel->track.state, TrackingState::tracking) << "frame " << k;
      EXPECT_LT(norm(panel_centre(spec, *panel) - true_top(f)), 0.02) << "frame " << k;
    }
  }
  EXPECT_TRUE(went_unseen) << "the hidden box was tracked: nothing to re-anchor";
  ASSERT_TRUE(reanchored_at.has_value());
  EXPECT_EQ(*reanchored_at, 10);  // the first scan after it reappeared
}

// A head turning and stepping: the table's free region, with no tracker of its own,
// stays where it is in the room, within 3 cm, carried by the camera's motion; its pose
// line names the support's free region. A background scan applies a frame after its
// frame: the head's motion meanwhile is made up for.
class SessionSurfacesRoom : public testing::TestWithParam<ScanMode> {};

TEST_P(SessionSurfacesRoom, APanelOnTheTableStaysInTheRoomAsTheCameraMoves) {
  MotionSceneParams mp;
  mp.kinds = {ShapeKind::cylinder, ShapeKind::sphere};
  mp.held = 0;
  mp.camera_yaw_deg_per_frame = 4.0;
  mp.camera_velocity_m_per_frame = {0.015, 0, 0};
  Result<MotionScene> scene = generate_motion_scene(mp);
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  const HapticSpec spec = panel_spec(0.30, 0.20);
  SessionParams params;
  params.scan_every = 1000;  // one scan: from then on only the camera's motion moves it
  params.camera = scene->camera;
  params.scan_mode = GetParam();
  AnnexSession session(spec, params);
  std::optional<Vec3> in_room;
  int checked = 0;
  double camera_moved_it = 0;  // how far a panel fixed in the camera's frame would be off
  for (int k = 4; k < 32; ++k) {  // from a frame where the head moves
    const SyntheticFrame f = render_motion_frame(*scene, k);
    // background: the scan of frame 4 applies 1 to 4 frames later, however long it takes.
    if (k == 8) session.wait_for_scan();
    const FrameReport r = session.process(f.frame, k);
    const AnnexedObject* panel = find_virtual(r, "panel");
    if (!panel) continue;
    EXPECT_TRUE(ends_with(panel->physical_id, ".free")) << panel->physical_id;
    EXPECT_EQ(panel->carrier, PoseCarrier::room);
    const Pose room_from_camera = motion_camera_pose(*scene, k);
    const Vec3 at = panel_centre(spec, *panel);
    if (!in_room) {
      // Where the scan saw the region, in the room: the scan's frame's camera pose.
      ASSERT_TRUE(r.scan.has_value());
      const auto seen = std::find_if(r.scan->surfaces.begin(), r.scan->surfaces.end(),
                                     [&](const PhysicalObject& o) { return o.id == panel->physical_id; });
      ASSERT_NE(seen, r.scan->surfaces.end());
      in_room = transform_point(motion_camera_pose(*scene, r.scan_frame_index),
                                seen->primitives[0].center);
      EXPECT_LT(norm(transform_point(room_from_camera, at) - *in_room), 0.03);
      EXPECT_NE(format_pose_line(k, spec, *panel).find(" " + panel->physical_id + " state="),
                std::string::npos);
      continue;
    }
    const Vec3 expected = transform_point(inverse(room_from_camera), *in_room);
    EXPECT_LT(norm(at - expected), 0.03) << "frame " << k;
    const Vec3 at_match = transform_point(inverse(motion_camera_pose(*scene, panel->matched_frame)), *in_room);
    camera_moved_it = std::max(camera_moved_it, norm(expected - at_match));
    ++checked;
  }
  EXPECT_GE(checked, 20);
  EXPECT_GT(camera_moved_it, 0.06) << "the camera did not move enough to tell";
}

INSTANTIATE_TEST_SUITE_P(Modes, SessionSurfacesRoom,
                         testing::Values(ScanMode::same_frame, ScanMode::background),
                         [](const testing::TestParamInfo<ScanMode>& i) {
                           return i.param == ScanMode::same_frame ? std::string("SameFrame")
                                                                  : std::string("Background");
                         });

// A spec without planes: the session's scans look for no surfaces; with a plane they do.
TEST(SessionSurfaces, ScansSkipSurfacesWhenNoVirtualObjectHasAPlane) {
  SyntheticScene scene;
  scene.camera_position = {0, -0.75, 0.7};
  scene.objects.push_back(resting_object(ShapeKind::box, {0.22, 0.16, 0.08}, -0.1, 0));
  const Frame frame = render_scene(scene, {}, 0).frame;
  HapticSpec crate;
  VirtualObject v;
  v.name = "crate";
  v.primitives.push_back(make_primitive(ShapeKind::box, "body"));
  crate.objects.push_back(v);
  AnnexSession without(crate, {});
  const FrameReport a = without.process(frame, 0);
  ASSERT_TRUE(a.scan.has_value());
  EXPECT_TRUE(a.scan->surfaces.empty());
  AnnexSession with(panel_spec(0.22, 0.16), {});
  const FrameReport b = with.process(frame, 0);
  ASSERT_TRUE(b.scan.has_value());
  EXPECT_FALSE(b.scan->surfaces.empty());
  ScanParams off;
  off.plane_candidates = false;
  Result<ScanResult> scan = scan_frame(frame, off);
  ASSERT_TRUE(scan.ok());
  EXPECT_TRUE(scan->surfaces.empty());
  EXPECT_EQ(scan->scene, b.scan->scene);  // the objects do not depend on it
}

// The real laptop frame, still: a 35 x 24 cm screen goes to the laptop's lid; excluded,
// it is released and laid on the table's free region instead, never on the lid again.
TEST(SessionSurfaces, ARealLaptopLidCarriesAScreenUntilExcluded) {
  const auto path = std::filesystem::path(ANNEX_SHARED_DIR) / "data" / "real" /
                    "frame_20121214T142255.814212.pcd";
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << "../shared/data/real is absent: real-scan test skipped";
  Result<Frame> frame = read_pcd(path);
  ASSERT_TRUE(frame.ok()) << frame.error().format();
  const HapticSpec spec = panel_spec(0.35, 0.24);
  SessionParams params;
  params.scan_every = 2;
  AnnexSession session(spec, params);
  const FrameReport first = session.process(*frame, 0);
  const AnnexedObject* screen = find_virtual(first, "panel");
  ASSERT_NE(screen, nullptr);
  EXPECT_EQ(screen->physical_id, "p1.face");
  EXPECT_GT(screen->vote, 90);
  session.exclude("p1.face");
  const FrameReport second = session.process(*frame, 1);
  EXPECT_EQ(second.excluded, std::vector<std::string>{"p1.face"});
  EXPECT_EQ(second.released, std::vector<std::string>{"panel"});
  for (int k = 2; k < 8; ++k) {
    const FrameReport r = session.process(*frame, k);
    if (const AnnexedObject* o = find_virtual(r, "panel")) {
      EXPECT_NE(o->physical_id, "p1.face") << "frame " << k;
      EXPECT_TRUE(ends_with(o->physical_id, ".free")) << o->physical_id;
    }
  }
  const std::vector<std::string> ids = session.excluded_ids();
  EXPECT_NE(std::find(ids.begin(), ids.end(), "p1.face"), ids.end());

  // Excluding the laptop itself (p1, before any scan) excludes its lid's face too.
  AnnexSession no_laptop(spec, params);
  no_laptop.exclude("p1");
  const FrameReport r = no_laptop.process(*frame, 0);
  EXPECT_EQ(r.excluded, std::vector<std::string>{"p1"});
  const AnnexedObject* o = find_virtual(r, "panel");
  ASSERT_NE(o, nullptr);
  EXPECT_NE(o->physical_id, "p1.face");
}

}  // namespace
}  // namespace annex
