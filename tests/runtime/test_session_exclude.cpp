// Props never to annex in the runtime loop: AnnexSession::exclude (released if annexed,
// never voted on again while in view), an id excluded before any prop has it, the
// spec's exclude rules, and rescan().
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>

#include "annex/runtime/annex_session.h"
#include "annex/runtime/synthetic_scene.h"
#include "session_fixture.h"

namespace annex {
namespace {

using test::spec_for;
using test::three_props;

const AnnexedObject* find_virtual(const FrameReport& r, const std::string& name) {
  for (const AnnexedObject& o : r.objects)
    if (o.virtual_name == name) return &o;
  return nullptr;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

TEST(SessionExclude, AnExcludedPropIsReleasedAndNeverAnnexedAgain) {
  const SyntheticScene scene = three_props(41);
  SessionParams params;
  params.scan_every = 3;
  AnnexSession session(spec_for(scene), params);
  FrameReport first = session.process(render_scene(scene, {}, 0).frame);
  ASSERT_EQ(first.objects.size(), 3u);
  const AnnexedObject* prop = find_virtual(first, "v1");
  ASSERT_NE(prop, nullptr);
  const std::string id = prop->physical_id;
  session.exclude(id);
  EXPECT_EQ(session.excluded_ids(), std::vector<std::string>{});  // applied at the next frame
  const FrameReport second = session.process(render_scene(scene, {}, 1).frame);
  EXPECT_EQ(second.excluded, std::vector<std::string>{id});
  EXPECT_EQ(second.released, std::vector<std::string>{"v1"});
  EXPECT_EQ(find_virtual(second, "v1"), nullptr);
  EXPECT_EQ(session.excluded_ids(), std::vector<std::string>{id});
  int scans = 0, matches = 0;
  for (int k = 2; k < 20; ++k) {
    const FrameReport r = session.process(render_scene(scene, {}, k).frame);
    scans += r.scanned;
    // v1 votes again at every scan, but not for its old prop: nothing else fits it.
    if (r.match) {
      ++matches;
      EXPECT_NE(std::find(r.match->voters.begin(), r.match->voters.end(), 1),
                r.match->voters.end());
      for (const PhysicalObject& o : r.match_scene->objects)
        if (o.id == id) {
          const auto j = static_cast<size_t>(&o - r.match_scene->objects.data());
          EXPECT_NE(r.match->matches[1].physical_index, std::optional<int>(static_cast<int>(j)));
        }
    }
    EXPECT_EQ(find_virtual(r, "v1"), nullptr) << "frame " << k;
    for (const AnnexedObject& o : r.objects) EXPECT_NE(o.physical_id, id) << "frame " << k;
    EXPECT_EQ(r.objects.size(), 2u) << "frame " << k;
  }
  EXPECT_GE(scans, 5);
  EXPECT_EQ(session.excluded_ids(), std::vector<std::string>{id});  // still in view, tracked
}

TEST(SessionExclude, AnIdExcludedBeforeTheFirstScan) {
  const SyntheticScene scene = three_props(42);
  // Which id the first scan gives v1's prop.
  AnnexSession probe(spec_for(scene), {});
  const FrameReport seen = probe.process(render_scene(scene, {}, 0).frame);
  const AnnexedObject* prop = find_virtual(seen, "v1");
  ASSERT_NE(prop, nullptr);
  const std::string id = prop->physical_id;

  AnnexSession session(spec_for(scene), {});
  session.exclude(id);
  session.exclude(id);  // twice is once
  const FrameReport first = session.process(render_scene(scene, {}, 0).frame);
  EXPECT_EQ(first.excluded, std::vector<std::string>{id});
  EXPECT_TRUE(first.released.empty());
  EXPECT_EQ(find_virtual(first, "v1"), nullptr);
  ASSERT_EQ(first.objects.size(), 2u);
  ASSERT_TRUE(first.match.has_value());
  for (int k = 1; k < 12; ++k) {
    const FrameReport r = session.process(render_scene(scene, {}, k).frame);
    EXPECT_EQ(find_virtual(r, "v1"), nullptr) << "frame " << k;
  }
  EXPECT_EQ(session.excluded_ids(), std::vector<std::string>{id});
}

// Out of view for release_after_frames, the excluded prop's exclusion ends; an id no
// prop ever gets keeps waiting.
TEST(SessionExclude, TheExclusionEndsWhenThePropLeavesTheView) {
  const SyntheticScene scene = three_props(43);
  SessionParams params;
  params.scan_every = 2;
  params.release_after_frames = 3;
  AnnexSession session(spec_for(scene), params);
  const FrameReport first = session.process(render_scene(scene, {}, 0).frame);
  const AnnexedObject* prop = find_virtual(first, "v1");
  ASSERT_NE(prop, nullptr);
  const std::string id = prop->physical_id;
  session.exclude(id);
  session.exclude("p999");
  bool ended = false;
  for (int k = 1; k < 30 && !ended; ++k) {
    SyntheticFrame f = render_scene(scene, {}, k);
    if (k >= 3)  // v1's prop leaves the view
      for (size_t i = 0; i < f.labels.size(); ++i)
        if (f.labels[i] == 1) f.frame.points[i].z = std::numeric_limits<float>::quiet_NaN();
    session.process(f.frame);
    ended = !contains(session.excluded_ids(), id);
    EXPECT_TRUE(contains(session.excluded_ids(), "p999"));
  }
  EXPECT_TRUE(ended);
}

TEST(SessionExclude, SpecRulesKeepPropsOut) {
  const SyntheticScene scene = three_props(44);
  HapticSpec spec = spec_for(scene);
  const ShapeKind kind = scene.objects[1].kind;
  spec.exclude.push_back({"no_v1_shape", kind, {}});
  AnnexSession session(spec, {});
  const FrameReport r = session.process(render_scene(scene, {}, 0).frame);
  ASSERT_TRUE(r.match.has_value());
  EXPECT_EQ(find_virtual(r, "v1"), nullptr);
  EXPECT_EQ(r.objects.size(), 2u);
  int excluded = 0;
  for (size_t j = 0; j < r.match->excluded_by.size(); ++j)
    if (r.match->excluded_by[j] == 0) {
      ++excluded;
      EXPECT_EQ(r.match_scene->objects[j].primitives[0].kind, kind);
    }
  EXPECT_EQ(excluded, 1);
}

TEST(SessionExclude, RescanScansTheNextFrame) {
  const SyntheticScene scene = three_props(45);
  SessionParams params;
  params.scan_every = 100;
  AnnexSession session(spec_for(scene), params);
  EXPECT_TRUE(session.process(render_scene(scene, {}, 0).frame).scanned);
  EXPECT_FALSE(session.process(render_scene(scene, {}, 1).frame).scanned);
  session.rescan();
  EXPECT_TRUE(session.process(render_scene(scene, {}, 2).frame).scanned);
  EXPECT_FALSE(session.process(render_scene(scene, {}, 3).frame).scanned);
}

}  // namespace
}  // namespace annex
