// The held-out room generator's features (room_scene_params: chairs, two-level shelves
// and objects on their boards, objects on the floor, touching pairs, objects across a
// table edge, dark objects):
// their ground truth against the rendered pixels, then a fixed set of seeded rooms per
// feature with what the scanner does on them now (docs/perception.md has the figures).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "annex/runtime/scanner.h"
#include "annex/runtime/synthetic_scene.h"
#include "label_owner.h"

namespace annex {
namespace {

SensorNoiseParams exact() {
  SensorNoiseParams n;
  n.enabled = false;
  return n;
}

// room_scene_params with every room feature off but `feature`, forced on.
SyntheticSceneParams only(std::uint64_t seed, const std::string& feature) {
  SyntheticSceneParams p = room_scene_params(seed);
  p.chair_chance = feature == "chair" ? 1 : 0;
  p.shelf_chance = feature == "shelf" || feature == "on-shelf" ? 1 : 0;
  p.shelf_objects = feature == "on-shelf" ? 2 : 0;
  p.floor_objects = feature == "floor" ? 2 : 0;
  p.touching_share = feature == "touching" ? 1 : 0;
  p.overhang_share = feature == "overhang" ? 1 : 0;
  p.dark_share = feature == "dark" ? 1 : 0;
  p.back_chair_chance = feature == "back chair" ? 1 : 0;
  p.cabinet_chance = feature == "cabinet" ? 1 : 0;
  p.pole_chance = feature == "pole" ? 1 : 0;
  p.stacked_share = feature == "stacked" ? 1 : 0;
  p.everyday_share = feature == "everyday" ? 1 : 0;
  p.lying_share = feature == "lying" ? 1 : 0;
  if (feature == "lying") p.kinds = {ShapeKind::cylinder};  // every one that can lie does
  return p;
}

SyntheticScene room(const SyntheticSceneParams& p) {
  const Result<SyntheticScene> s = generate_scene(p);
  EXPECT_TRUE(s.ok()) << "seed " << p.seed << ": " << (s.ok() ? "" : s.error().format());
  return s.ok() ? *s : SyntheticScene{};
}

// A room with a feature and the same room without it (`off` turns the feature off).
std::pair<SyntheticScene, SyntheticScene> with_and_without(
    SyntheticSceneParams p, const std::function<void(SyntheticSceneParams&)>& off) {
  SyntheticScene with = room(p);
  off(p);
  return {std::move(with), room(p)};
}

int count_label(const SyntheticFrame& f, int label) {
  return static_cast<int>(std::count(f.labels.begin(), f.labels.end(), label));
}

// Camera-frame points of object i's pixels (the exact render keeps them all).
std::vector<Vec3> object_points(const SyntheticFrame& f, int i) {
  std::vector<Vec3> out;
  for (std::size_t k = 0; k < f.labels.size(); ++k)
    if (f.labels[k] == i && std::isfinite(f.frame.points[k].z))
      out.push_back({f.frame.points[k].x, f.frame.points[k].y, f.frame.points[k].z});
  return out;
}

TEST(SyntheticRooms, WorldScenesHaveNoRoomFeatures) {
  const SyntheticSceneParams w = world_scene_params(2001);
  EXPECT_EQ(w.chair_chance, 0);
  EXPECT_EQ(w.shelf_chance, 0);
  EXPECT_EQ(w.floor_objects, 0);
  EXPECT_EQ(w.touching_share, 0);
  EXPECT_EQ(w.overhang_share, 0);
  EXPECT_EQ(w.dark_share, 0);
  EXPECT_EQ(w.shelf_objects, 0);
  for (const SyntheticObject& o : room(w).objects) {
    EXPECT_GE(o.support, 0);
    EXPECT_LT(o.touching, 0);
    EXPECT_FALSE(o.overhang);
    EXPECT_EQ(o.albedo, 1);
  }
}

TEST(SyntheticRooms, ChairAtTheFarSideItsSeatUnderTheTableWhenItFits) {
  int under = 0;
  for (std::uint64_t seed = 6001; seed <= 6008; ++seed) {
    const SyntheticScene s = room(only(seed, "chair"));
    std::vector<SyntheticBlock> chair;
    for (const SyntheticBlock& b : s.furniture)
      if (b.role == SyntheticBlock::Role::chair) chair.push_back(b);
    ASSERT_EQ(chair.size(), 6u) << "seat, back, four legs; seed " << seed;
    const SyntheticBlock& seat = chair[0];
    const double seat_top = seat.center.z + 0.5 * seat.size_m.z;
    const double front = seat.center.y - 0.5 * seat.size_m.y;
    if (front < s.table_half_y_m) {
      // Partly under: the seat clears the table's underside.
      EXPECT_LT(seat_top, -s.table_thickness_m) << "seed " << seed;
      ++under;
    }
    for (std::size_t k = 2; k < chair.size(); ++k)  // the legs stand on the floor
      EXPECT_NEAR(chair[k].center.z - 0.5 * chair[k].size_m.z, -s.floor_depth_m, 1e-9);
    EXPECT_LT(chair[1].center.y + 0.5 * chair[1].size_m.y, s.wall_y_m);  // before the wall
    const SyntheticFrame f = render_scene(s, exact());
    EXPECT_GT(count_label(f, kLabelChair), 200) << "seed " << seed;
    // Furniture, not a support holding objects: the truth lists table, floor, side support.
    EXPECT_EQ(f.truth.supports.size(), 3u);
  }
  EXPECT_GE(under, 3);
}

TEST(SyntheticRooms, TwoLevelShelfAgainstTheWall) {
  for (std::uint64_t seed = 6001; seed <= 6006; ++seed) {
    const SyntheticScene s = room(only(seed, "shelf"));
    std::vector<SyntheticBlock> shelf;
    for (const SyntheticBlock& b : s.furniture)
      if (b.role == SyntheticBlock::Role::shelf) shelf.push_back(b);
    ASSERT_EQ(shelf.size(), 4u) << "two boards, two panels; seed " << seed;
    EXPECT_GT(shelf[1].center.z - shelf[0].center.z, 0.29);  // two levels
    for (std::size_t k = 2; k < 4; ++k)
      EXPECT_NEAR(shelf[k].center.z - 0.5 * shelf[k].size_m.z, -s.floor_depth_m, 1e-9);
    EXPECT_LE(shelf[0].center.y + 0.5 * shelf[0].size_m.y, s.wall_y_m);
    EXPECT_GT(shelf[0].center.y - 0.5 * shelf[0].size_m.y, s.table_half_y_m);
  }
}

// Whether object o stands on one of the shelf's boards.
bool on_shelf(const SyntheticScene& s, const SyntheticObject& o) {
  return o.support > 0 && s.furniture[static_cast<std::size_t>(o.support - 1)].role == SyntheticBlock::Role::shelf;
}

TEST(SyntheticRooms, ObjectsOnShelfBoardsStandOnTheBoardInViewWithTheirSupport) {
  int on_boards = 0, on_lower = 0;
  for (std::uint64_t seed = 6001; seed <= 6010; ++seed) {
    const SyntheticScene s = room(only(seed, "on-shelf"));
    const SyntheticFrame f = render_scene(s, exact());
    double lowest_board = 1e9;
    for (const SyntheticBlock& b : s.furniture)
      if (b.role == SyntheticBlock::Role::shelf && b.size_m.z < b.size_m.x) lowest_board = std::min(lowest_board, b.center.z);
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
      const SyntheticObject& o = s.objects[i];
      if (!on_shelf(s, o)) continue;
      ++on_boards;
      const SyntheticBlock& board = s.furniture[static_cast<std::size_t>(o.support - 1)];
      ASSERT_LT(board.size_m.z, board.size_m.x) << "a board, not a side panel; seed " << seed;
      on_lower += board.center.z == lowest_board;
      // Its footprint on the board, its foot on the board's top.
      EXPECT_LT(std::abs(o.center.x - board.center.x), 0.5 * board.size_m.x) << "seed " << seed;
      EXPECT_LT(std::abs(o.center.y - board.center.y), 0.5 * board.size_m.y) << "seed " << seed;
      // The truth's support for it: the board's top plane, listed among the supports.
      const PhysicalObject& truth = f.truth.objects[i];
      EXPECT_EQ(truth.support_id, "f" + std::to_string(o.support));
      const SupportSurface* plane = nullptr;
      for (const SupportSurface& sp : f.truth.supports)
        if (sp.id == truth.support_id) plane = &sp;
      ASSERT_NE(plane, nullptr) << "seed " << seed;
      const std::vector<Vec3> pts = object_points(f, static_cast<int>(i));
      EXPECT_GT(pts.size(), 50u) << "seed " << seed << " object " << i << " hidden";
      double lowest = 1e9, highest = -1e9;
      for (const Vec3& p : pts) {
        const double h = dot(plane->plane.normal, p) + plane->plane.d;
        lowest = std::min(lowest, h), highest = std::max(highest, h);
      }
      EXPECT_GT(lowest, -1e-6) << "seed " << seed;
      // Below the board above it (the boards are 2 cm thick, at least 30 cm apart).
      for (const SyntheticBlock& b : s.furniture)
        if (b.role == SyntheticBlock::Role::shelf && b.size_m.z < b.size_m.x && b.center.z > board.center.z)
          EXPECT_LT(board.center.z + 0.5 * board.size_m.z + highest, b.center.z - 0.5 * b.size_m.z) << "seed " << seed;
    }
  }
  EXPECT_GE(on_boards, 10);
  EXPECT_GE(on_lower, 2);
}

TEST(SyntheticRooms, ShelfObjectsLeaveTheRestOfTheRoomAsItWas) {
  int added = 0;
  for (std::uint64_t seed = 6001; seed <= 6010; ++seed) {
    SyntheticSceneParams p = room_scene_params(seed);
    p.shelf_chance = 1;
    const auto scenes = with_and_without(p, [](auto& q) { q.shelf_objects = 0; });
    const SyntheticScene &with = scenes.first, &without = scenes.second;
    ASSERT_GE(with.objects.size(), without.objects.size());
    EXPECT_EQ(with.camera_position.x, without.camera_position.x);
    EXPECT_EQ(with.furniture.size(), without.furniture.size());
    for (std::size_t i = 0; i < with.objects.size(); ++i) {
      if (on_shelf(with, with.objects[i])) {
        ++added;
        continue;
      }
      ASSERT_LT(i, without.objects.size());
      EXPECT_EQ(with.objects[i].center.x, without.objects[i].center.x) << "seed " << seed;
      EXPECT_EQ(with.objects[i].dimensions_m, without.objects[i].dimensions_m) << "seed " << seed;
    }
    EXPECT_EQ(with.objects.size() - without.objects.size(),
              static_cast<std::size_t>(std::count_if(with.objects.begin(), with.objects.end(),
                                                     [&](const SyntheticObject& o) { return on_shelf(with, o); })));
  }
  EXPECT_GE(added, 10);
}

// The room's extras (a chair seen from behind, a cabinet face-on, a post) come from a
// stream of their own and hide no object: every object and every other block is as it
// was, and each object shows the same pixels.
TEST(SyntheticRooms, RoomExtrasLeaveTheRestOfTheRoomAsItWas) {
  std::map<int, int> shown;
  for (std::uint64_t seed = 6001; seed <= 6020; ++seed) {
    const auto scenes = with_and_without(room_scene_params(seed), [](auto& q) {
      q.back_chair_chance = q.cabinet_chance = q.pole_chance = 0;
    });
    const SyntheticScene &with = scenes.first, &without = scenes.second;
    ASSERT_EQ(with.objects.size(), without.objects.size()) << "seed " << seed;
    ASSERT_GE(with.furniture.size(), without.furniture.size());
    for (std::size_t k = 0; k < without.furniture.size(); ++k)
      EXPECT_EQ(with.furniture[k].center.x, without.furniture[k].center.x) << "seed " << seed;
    const SyntheticFrame fw = render_scene(with, exact()), fo = render_scene(without, exact());
    for (std::size_t i = 0; i < with.objects.size(); ++i) {
      EXPECT_EQ(with.objects[i].center.x, without.objects[i].center.x) << "seed " << seed;
      EXPECT_EQ(count_label(fw, static_cast<int>(i)), count_label(fo, static_cast<int>(i)))
          << "seed " << seed;
    }
    for (int label : {kLabelBackChair, kLabelCabinet, kLabelPole})
      shown[label] += count_label(fw, label) > 0;
  }
  // A cabinet about a metre away finds a place clear of the table in fewer rooms (about
  // one in eight): ABackChairTurnsItsBackAndACabinetItsDoorsToTheCamera forces it.
  EXPECT_GE(shown[kLabelBackChair], 2);
  EXPECT_GE(shown[kLabelPole], 2);
}

// The scene's furniture blocks of one role, in order.
std::vector<SyntheticBlock> blocks_of(const SyntheticScene& s, SyntheticBlock::Role role) {
  std::vector<SyntheticBlock> out;
  for (const SyntheticBlock& b : s.furniture)
    if (b.role == role) out.push_back(b);
  return out;
}

TEST(SyntheticRooms, ABackChairTurnsItsBackAndACabinetItsDoorsToTheCamera) {
  int chairs = 0, cabinets = 0;
  for (std::uint64_t seed = 6001; seed <= 6010; ++seed) {
    const std::vector<SyntheticBlock> chair =
        blocks_of(room(only(seed, "back chair")), SyntheticBlock::Role::back_chair);
    if (!chair.empty()) {
      ASSERT_EQ(chair.size(), 6u) << "seat, back, four legs; seed " << seed;
      EXPECT_LT(chair[1].center.y, chair[0].center.y)
          << "its back on the camera's side; seed " << seed;
      ++chairs;
    }
    const SyntheticScene k = room(only(seed, "cabinet"));
    const std::vector<SyntheticBlock> cabinet = blocks_of(k, SyntheticBlock::Role::cabinet);
    if (!cabinet.empty()) {
      ASSERT_EQ(cabinet.size(), 5u) << "body, two doors, two handles; seed " << seed;
      const double front = cabinet[0].center.y - 0.5 * cabinet[0].size_m.y;
      EXPECT_NEAR(cabinet[1].center.y + 0.5 * cabinet[1].size_m.y, front, 1e-9)
          << "a door on its front";
      const double ahead = front - k.camera_position.y;
      EXPECT_GT(ahead, 0.65);
      EXPECT_LT(ahead, 1.55);
      ++cabinets;
    }
  }
  EXPECT_GE(chairs, 3);
  EXPECT_GE(cabinets, 2);
}

TEST(SyntheticRooms, FloorObjectsStandOnTheFloorBesideTheFurnitureInView) {
  int on_floor = 0;
  for (std::uint64_t seed = 6001; seed <= 6008; ++seed) {
    const SyntheticScene s = room(only(seed, "floor"));
    const SyntheticFrame f = render_scene(s, exact());
    const SupportSurface& floor = f.truth.supports[1];
    ASSERT_EQ(floor.id, "floor");
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
      if (s.objects[i].support >= 0) continue;
      ++on_floor;
      EXPECT_EQ(f.truth.objects[i].support_id, "floor");
      // Not under the table.
      const Vec3 c = s.objects[i].center;
      EXPECT_FALSE(std::abs(c.x) < s.table_half_x_m && std::abs(c.y) < s.table_half_y_m);
      const std::vector<Vec3> pts = object_points(f, static_cast<int>(i));
      EXPECT_GT(pts.size(), 100u) << "seed " << seed << " object " << i << " hidden";
      double lowest = 1e9;
      for (const Vec3& p : pts) lowest = std::min(lowest, dot(floor.plane.normal, p) + floor.plane.d);
      EXPECT_GT(lowest, -1e-6);
    }
  }
  EXPECT_GE(on_floor, 8);
}

TEST(SyntheticRooms, TouchingPairsTouchAndStayTwoObjects) {
  int pairs = 0, in_contact = 0;
  for (std::uint64_t seed = 6001; seed <= 6008; ++seed) {
    const SyntheticScene s = room(only(seed, "touching"));
    const SyntheticFrame f = render_scene(s, exact());
    ASSERT_EQ(f.truth.objects.size(), s.objects.size());
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
      const int j = s.objects[i].touching;
      if (j < 0) continue;
      ++pairs;
      // Seen points of the two come within a pixel's footprint of each other when the
      // contact is in view (it may be hidden behind one of them).
      const std::vector<Vec3> p = object_points(f, static_cast<int>(i));
      const std::vector<Vec3> q = object_points(f, j);
      double nearest = 1e9;
      for (const Vec3& u : p)
        for (const Vec3& v : q) nearest = std::min(nearest, norm(u - v));
      in_contact += nearest < 0.01;
    }
  }
  EXPECT_GE(pairs, 8);
  EXPECT_GE(in_contact * 2, pairs);
}

TEST(SyntheticRooms, OverhangingObjectsCrossATableEdgeCentreOverTheTable) {
  int across = 0, beyond_points = 0;
  for (std::uint64_t seed = 6001; seed <= 6008; ++seed) {
    const SyntheticScene s = room(only(seed, "overhang"));
    const SyntheticFrame f = render_scene(s, exact());
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
      const SyntheticObject& o = s.objects[i];
      if (!o.overhang) continue;
      ++across;
      EXPECT_LT(std::abs(o.center.x), s.table_half_x_m);
      EXPECT_LT(std::abs(o.center.y), s.table_half_y_m);
      // Some of its seen points lie outside the table's outline: camera to table frame
      // by the inverse rotation (the axes are orthonormal).
      const Vec3 ex = table_to_camera_direction(s, {1, 0, 0});
      const Vec3 ey = table_to_camera_direction(s, {0, 1, 0});
      const Vec3 origin = table_to_camera_point(s, {0, 0, 0});
      bool beyond = false;
      for (const Vec3& p : object_points(f, static_cast<int>(i))) {
        const double x = dot(p - origin, ex), y = dot(p - origin, ey);
        beyond = beyond || std::abs(x) > s.table_half_x_m || y < -s.table_half_y_m;
      }
      beyond_points += beyond;
      EXPECT_EQ(f.truth.objects[i].support_id, "table");
    }
  }
  EXPECT_GE(across, 8);
  EXPECT_GE(beyond_points * 4, across * 3);
}

TEST(SyntheticRooms, DarkObjectsLoseDepthWhereTheReturnIsWeakAndNothingElseChanges) {
  int dark = 0;
  for (std::uint64_t seed = 6001; seed <= 6004; ++seed) {
    const SyntheticScene s = room(only(seed, "dark"));
    SyntheticScene bright = s;
    for (SyntheticObject& o : bright.objects) o.albedo = 1;
    const SyntheticFrame f = render_scene(s), g = render_scene(bright);
    ASSERT_EQ(f.labels, g.labels);
    int lost = 0, kept_elsewhere = 0, elsewhere = 0;
    for (std::size_t k = 0; k < f.labels.size(); ++k) {
      const int l = f.labels[k];
      const bool a = std::isfinite(f.frame.points[k].z), b = std::isfinite(g.frame.points[k].z);
      if (l >= 0 && s.objects[static_cast<std::size_t>(l)].albedo < 1) {
        EXPECT_FALSE(a && !b);  // darkness only takes depth away
        lost += b && !a;
        if (a && b) EXPECT_EQ(f.frame.points[k].z, g.frame.points[k].z);
      } else {
        ++elsewhere;
        kept_elsewhere += a == b && (!a || f.frame.points[k].z == g.frame.points[k].z);
      }
    }
    for (const SyntheticObject& o : s.objects) dark += o.albedo < 1;
    EXPECT_GT(lost, 100) << "seed " << seed;
    EXPECT_EQ(kept_elsewhere, elsewhere) << "seed " << seed;
  }
  EXPECT_GE(dark, 8);
}

// Stacked objects (stacked_share) stand on the top of the box or cylinder under them,
// their footprint within that top; the truth names the object under them; they come
// from a stream of their own, after every other object, which stays as it was.
TEST(SyntheticRooms, StackedObjectsStandOnTheTopOfTheObjectUnderThem) {
  int stacked = 0;
  for (std::uint64_t seed = 6001; seed <= 6010; ++seed) {
    SyntheticSceneParams p = room_scene_params(seed);
    p.stacked_share = 1;
    const auto scenes = with_and_without(p, [](auto& q) { q.stacked_share = 0; });
    const SyntheticScene &with = scenes.first, &without = scenes.second;
    ASSERT_GE(with.objects.size(), without.objects.size());
    for (std::size_t i = 0; i < without.objects.size(); ++i) {
      EXPECT_EQ(with.objects[i].center.x, without.objects[i].center.x) << "seed " << seed;
      EXPECT_EQ(with.objects[i].on_object, -1) << "seed " << seed;
    }
    const SyntheticFrame f = render_scene(with, exact());
    for (std::size_t i = without.objects.size(); i < with.objects.size(); ++i) {
      const SyntheticObject& o = with.objects[i];
      ASSERT_GE(o.on_object, 0) << "seed " << seed;
      const SyntheticObject& under = with.objects[static_cast<std::size_t>(o.on_object)];
      ++stacked;
      ASSERT_TRUE(under.kind == ShapeKind::box || under.kind == ShapeKind::cylinder);
      const double top = under.kind == ShapeKind::box
                             ? under.center.z + 0.5 * under.dimensions_m[2]
                             : under.center.z + 0.5 * under.dimensions_m[1];
      const double half =
          o.kind == ShapeKind::box ? 0.5 * o.dimensions_m[2] : 0.5 * o.dimensions_m[1];
      EXPECT_NEAR(o.center.z - half, top, 1e-9) << "seed " << seed;
      const double room = under.kind == ShapeKind::box
                              ? 0.5 * std::min(under.dimensions_m[0], under.dimensions_m[1])
                              : under.dimensions_m[0];
      const double reach = std::hypot(o.center.x - under.center.x, o.center.y - under.center.y) +
                           footprint_radius(o.kind, o.dimensions_m);
      EXPECT_LE(reach, room + 1e-9) << "seed " << seed;
      EXPECT_EQ(f.truth.objects[i].on_object, "o" + std::to_string(o.on_object + 1));
      EXPECT_GT(count_label(f, static_cast<int>(i)), 0) << "seed " << seed;
    }
  }
  EXPECT_GE(stacked, 10);
}

// Everyday objects (everyday_share): mugs and cups carry a handle reaching out of their
// wall, bottles a shoulder, neck and cap up to the height drawn; the truth is the body,
// which stays on its support; every pixel the details take is the object's; the rest of
// the scene is the one without them.
TEST(SyntheticRooms, EverydayObjectsCarryHandlesOrNecksTheirTruthIsTheBody) {
  int mugs = 0, bottles = 0, cups = 0;
  for (std::uint64_t seed = 6001; seed <= 6012; ++seed) {
    SyntheticSceneParams p = room_scene_params(seed);
    p.everyday_share = 1;
    const auto scenes = with_and_without(p, [](auto& q) { q.everyday_share = 0; });
    const SyntheticScene &with = scenes.first, &without = scenes.second;
    ASSERT_EQ(with.objects.size(), without.objects.size());
    const SyntheticFrame f = render_scene(with, exact());
    const SyntheticFrame plain = render_scene(without, exact());
    for (std::size_t i = 0; i < with.objects.size(); ++i) {
      const SyntheticObject& o = with.objects[i];
      const SyntheticObject& was = without.objects[i];
      EXPECT_EQ(o.center.x, was.center.x) << "seed " << seed;
      if (o.details.empty()) continue;
      const auto& d = o.dimensions_m;
      // The body's foot stays where the plain solid's was.
      EXPECT_NEAR(o.center.z - 0.5 * d[1], was.center.z - 0.5 * was.dimensions_m[1], 1e-9);
      EXPECT_EQ(f.truth.objects[i].primitives[0].dimensions_m, d) << "seed " << seed;
      if (o.kind == ShapeKind::cone) {
        ++cups;
        EXPECT_TRUE(o.apex_down);
      } else if (o.details.front().kind == ShapeKind::cone) {
        ++bottles;
        ASSERT_EQ(o.details.size(), 3u);
        const SyntheticDetail& cap = o.details.back();
        // The neck ends at the height drawn for the plain cylinder.
        EXPECT_NEAR(o.center.z + cap.offset.z + 0.5 * cap.dimensions_m[1],
                    was.center.z + 0.5 * was.dimensions_m[1], 1e-9);
        EXPECT_LT(o.details[1].dimensions_m[0], 0.5 * d[0] + 1e-9);  // a neck, not a tin
        EXPECT_GE(o.details[1].dimensions_m[1], 0.02 - 1e-9) << "seed " << seed;  // a neck at all
      } else {
        ++mugs;
        ASSERT_EQ(o.details.size(), 3u);
        const SyntheticDetail& grip = o.details.back();
        EXPECT_GT(grip.offset.x, d[0] + 0.015);  // out of the wall, a hand's grip away
        EXPECT_LT(grip.offset.z + 0.5 * grip.dimensions_m[2], 0.5 * d[1] + 0.011);
      }
      EXPECT_GT(count_label(f, static_cast<int>(i)), count_label(plain, static_cast<int>(i)) / 4)
          << "seed " << seed;
    }
  }
  EXPECT_GE(mugs, 5);
  EXPECT_GE(bottles, 5);
  EXPECT_GE(cups, 1);
}

// Lying cylinders (lying_share): a plain cylinder on the table or a furniture top rests
// on its side on the spot it stood on, its axis level along its yaw, its footprint on
// the top; every pixel rendered lies on its side or a cap (within 0.1 mm); the truth's
// axis is level; the rest of the scene is the one without them.
TEST(SyntheticRooms, LyingCylindersRestOnTheirSideTheirAxisLevel) {
  int lying = 0;
  for (std::uint64_t seed = 6001; seed <= 6030; ++seed) {
    SyntheticSceneParams p = room_scene_params(seed);
    p.lying_share = 1;
    const auto scenes = with_and_without(p, [](auto& q) { q.lying_share = 0; });
    const SyntheticScene &with = scenes.first, &without = scenes.second;
    ASSERT_EQ(with.objects.size(), without.objects.size());
    const SyntheticFrame f = render_scene(with, exact());
    for (std::size_t i = 0; i < with.objects.size(); ++i) {
      const SyntheticObject& o = with.objects[i];
      const SyntheticObject& was = without.objects[i];
      EXPECT_EQ(o.center.x, was.center.x) << "seed " << seed;
      EXPECT_EQ(o.center.y, was.center.y) << "seed " << seed;
      if (!o.lying) continue;
      ++lying;
      ASSERT_EQ(o.kind, ShapeKind::cylinder);
      EXPECT_TRUE(o.details.empty() && o.on_object < 0 && o.touching < 0 && !o.cut);
      EXPECT_GE(o.support, 0) << "seed " << seed;
      const double r = o.dimensions_m[0], h = o.dimensions_m[1];
      EXPECT_NEAR(o.center.z - r, was.center.z - 0.5 * h, 1e-9) << "seed " << seed;  // same top
      if (o.support == 0) {
        const double yaw = o.yaw_deg * std::numbers::pi / 180;
        const double reach_x = 0.5 * h * std::abs(std::cos(yaw)) + r * std::abs(std::sin(yaw));
        const double reach_y = 0.5 * h * std::abs(std::sin(yaw)) + r * std::abs(std::cos(yaw));
        EXPECT_LE(std::abs(o.center.x) + reach_x, with.table_half_x_m) << "seed " << seed;
        EXPECT_LE(std::abs(o.center.y) + reach_y, with.table_half_y_m) << "seed " << seed;
      }
      const PhysicalPrimitive& truth = f.truth.objects[i].primitives[0];
      EXPECT_NEAR(dot(truth.axis, f.truth.support->normal), 0, 1e-9) << "seed " << seed;
      const std::vector<Vec3> pts = object_points(f, static_cast<int>(i));
      ASSERT_GT(pts.size(), 50u) << "seed " << seed;
      for (const Vec3& q : pts) {
        const Vec3 rel = q - truth.center;
        const double along = dot(rel, truth.axis);
        const double across = norm(rel - truth.axis * along);
        // On the side (across == r) or a cap (|along| == h / 2), within 0.1 mm.
        EXPECT_LE(std::min(std::abs(across - r), std::abs(std::abs(along) - 0.5 * h)), 1e-4);
        EXPECT_LE(std::abs(along), 0.5 * h + 1e-4);
        EXPECT_LE(across, r + 1e-4);
      }
    }
  }
  EXPECT_GE(lying, 8);
}

TEST(SyntheticRooms, FeatureSharesOutOfRangeAreErrors) {
  for (int which = 0; which < 13; ++which) {
    SyntheticSceneParams p = room_scene_params(6001);
    if (which == 0) p.chair_chance = 1.5;
    if (which == 1) p.shelf_chance = -0.1;
    if (which == 2) p.floor_objects = -1;
    if (which == 3) p.touching_share = 2;
    if (which == 4) p.overhang_share = -1;
    if (which == 5) p.dark_share = 1.01;
    if (which == 6) p.shelf_objects = -1;
    if (which == 7) p.back_chair_chance = 1.5;
    if (which == 8) p.cabinet_chance = -0.5;
    if (which == 9) p.pole_chance = 2;
    if (which == 10) p.stacked_share = -0.2;
    if (which == 11) p.everyday_share = 1.2;
    if (which == 12) p.lying_share = -0.5;
    EXPECT_FALSE(generate_scene(p).ok()) << which;
  }
}

// --- the scanner on a fixed set per feature ---

struct FeatureFigures {
  int objects = 0, found = 0, correct = 0, pieces_extra = 0, on_floor_support = 0, on_own_support = 0;
  int pairs = 0, pairs_split = 0, false_chair = 0, false_shelf = 0;
  int stacks = 0, stacks_on_right = 0;  // both found; the upper reported on the lower
  int level = 0;  // classed right, the axis within 10 degrees of the truth's (lying: level)
};

// The scanner on rooms `first`..`last` with `feature` alone, counting the objects
// within `reach_m` that have the feature (all objects when `feature` is furniture).
FeatureFigures scan_feature(const std::string& feature, std::uint64_t first, std::uint64_t last,
                            double reach_m, double near_m = 0, const ScanParams& params = {}) {
  FeatureFigures r;
  for (std::uint64_t seed = first; seed <= last; ++seed) {
    const SyntheticScene s = room(only(seed, feature));
    const SyntheticFrame f = render_scene(s);
    const Result<ScanResult> scan = scan_frame(f.frame, params);
    EXPECT_TRUE(scan.ok()) << "seed " << seed;
    if (!scan) continue;
    std::vector<int> owner;
    for (const ScanCluster& c : scan->clusters) owner.push_back(majority_label(f, c));
    for (std::size_t k = 0; k < owner.size(); ++k) {
      if (scan->scene.objects[k].partial) continue;
      r.false_chair += owner[k] == kLabelChair;
      r.false_shelf += owner[k] == kLabelShelf;
    }
    std::vector<int> pick(s.objects.size(), -1), pieces(s.objects.size(), 0);
    for (std::size_t k = 0; k < owner.size(); ++k) {
      if (owner[k] < 0) continue;
      const auto t = static_cast<std::size_t>(owner[k]);
      ++pieces[t];
      if (pick[t] < 0 || scan->clusters[k].pixels.size() >
                             scan->clusters[static_cast<std::size_t>(pick[t])].pixels.size())
        pick[t] = static_cast<int>(k);
    }
    for (std::size_t t = 0; t < s.objects.size(); ++t) {
      const SyntheticObject& o = s.objects[t];
      const PhysicalObject& truth = f.truth.objects[t];
      const bool has =
          (feature == "floor" && o.support < 0) || (feature == "touching" && o.touching >= 0) ||
          (feature == "overhang" && o.overhang) || (feature == "dark" && o.albedo < 1) ||
          (feature == "on-shelf" && on_shelf(s, o)) || (feature == "stacked" && o.on_object >= 0) ||
          (feature == "everyday" && !o.details.empty()) || (feature == "lying" && o.lying) ||
          feature == "chair" || feature == "shelf";
      const double range = norm(truth.primitives[0].center);
      if (!has || truth.partial || range > reach_m || range < near_m) continue;
      if (feature == "touching") {
        const auto j = static_cast<std::size_t>(o.touching);
        if (!f.truth.objects[j].partial) {
          ++r.pairs;
          r.pairs_split += pick[t] >= 0 && pick[j] >= 0;
        }
      }
      ++r.objects;
      if (pick[t] < 0) continue;
      ++r.found;
      if (feature == "stacked" && pick[static_cast<std::size_t>(o.on_object)] >= 0) {
        ++r.stacks;
        const auto lower = static_cast<std::size_t>(pick[static_cast<std::size_t>(o.on_object)]);
        r.stacks_on_right += scan->scene.objects[static_cast<std::size_t>(pick[t])].on_object ==
                             scan->scene.objects[lower].id;
      }
      r.pieces_extra += pieces[t] - 1;
      const PhysicalObject& got = scan->scene.objects[static_cast<std::size_t>(pick[t])];
      const bool right =
          !got.primitives.empty() && got.primitives[0].kind == truth.primitives[0].kind;
      r.correct += right;
      r.level += right && std::abs(dot(got.primitives[0].axis, truth.primitives[0].axis)) >
                              std::cos(10 * std::numbers::pi / 180);
      for (const SupportSurface& sp : scan->scene.supports)
        if (sp.id == got.support_id && std::abs(sp.plane.d - f.truth.supports[1].plane.d) < 0.03)
          ++r.on_floor_support;
      // On the support the truth gives it (the plane within 3 cm and 1 degree).
      for (const SupportSurface& sp : scan->scene.supports)
        for (const SupportSurface& tsp : f.truth.supports)
          if (sp.id == got.support_id && tsp.id == truth.support_id &&
              std::abs(sp.plane.d - tsp.plane.d) < 0.03 && dot(sp.plane.normal, tsp.plane.normal) > 0.9998)
            ++r.on_own_support;
    }
  }
  std::printf(
      "%s: objects %d found %d class %d extra pieces %d on floor %d on own support %d pairs %d "
      "split %d chair props %d shelf props %d stacks %d on the right object %d\n",
      feature.c_str(), r.objects, r.found, r.correct, r.pieces_extra, r.on_floor_support,
      r.on_own_support, r.pairs, r.pairs_split, r.false_chair, r.false_shelf, r.stacks,
      r.stacks_on_right);
  return r;
}

// A cylinder lying on its side (lying_share): within 1.5 m every one is a cylinder along
// its axis (the lying cylinder resting on the plane along either side of the box's
// footprint, or the cylinder in any orientation); at 1.5-2.5 m short wide tins on their
// side read as spheres and boxes: 20 of 27 here (16 before session 44), under the 90 %
// goal (docs/perception.md, "Objects lying on their side").
TEST(ScannerRooms, LyingCylindersWithinOneAndAHalfMetresAreCylindersAlongTheirAxis) {
  const FeatureFigures near = scan_feature("lying", 13001, 13020, 1.5);
  EXPECT_GE(near.objects, 6);
  EXPECT_EQ(near.found, near.objects);
  EXPECT_EQ(near.correct, near.objects);
  EXPECT_EQ(near.level, near.correct);
  const FeatureFigures far = scan_feature("lying", 13001, 13020, 2.5, 1.5);
  EXPECT_GE(far.objects, 20);
  EXPECT_EQ(far.found, far.objects);
  EXPECT_GE(far.correct, 0.7 * far.objects);
  EXPECT_EQ(far.level, far.correct);
}

TEST(ScannerRooms, ObjectsOnTheFloorFoundOnTheFloor) {
  const FeatureFigures r = scan_feature("floor", 6001, 6010, 4.0);
  EXPECT_GE(r.objects, 10);
  EXPECT_GE(r.found * 10, r.objects * 8);
  EXPECT_GE(r.on_floor_support * 10, r.found * 9);
}

// An object standing on another's top within 1.5 m: found, classed and reported on the
// object under it; without the level cut (object_segmenter.h) fewer of them are found.
TEST(ScannerRooms, StackedObjectsWithinOneAndAHalfMetresStandOnTheObjectUnderThem) {
  const FeatureFigures r = scan_feature("stacked", 6001, 6040, 1.5);
  ScanParams without;
  without.segment.level_cut = false;
  const FeatureFigures before = scan_feature("stacked", 6001, 6040, 1.5, 0, without);
  EXPECT_GE(r.objects, 15);
  EXPECT_GE(r.found * 10, r.objects * 9);
  EXPECT_GE(r.correct * 10, r.objects * 8);
  EXPECT_GE(r.stacks_on_right * 10, r.stacks * 9);
  EXPECT_GT(r.found, before.found);
}

// Mugs and bottles on a table 0.8 to 1.2 m away (the tabletop generator, five cylinders
// a scene, every one everyday) are one object each: a bottle's neck, cut from its
// shoulder at the crease, rises from that slope on the body's axis and joins it
// (neck_*); a mug's handle, cut where it meets the wall, hangs beside it and joins it
// (part_hang_reach_m). Without the two rules some are pieces reported whole.
TEST(ScannerRooms, MugsAndBottlesAreOneObjectEach) {
  const auto pieces = [](const ScanParams& params) {
    int objects = 0, extra = 0, round = 0;
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
      SyntheticSceneParams p;
      p.seed = seed;
      p.object_count = 5;
      p.kinds = {ShapeKind::cylinder};
      p.everyday_share = 1;
      const SyntheticFrame f = render_scene(room(p));
      const Result<ScanResult> scan = scan_frame(f.frame, params);
      EXPECT_TRUE(scan.ok()) << "seed " << seed;
      if (!scan) continue;
      std::vector<int> whole(f.truth.objects.size(), 0);
      for (std::size_t k = 0; k < scan->clusters.size(); ++k) {
        const int t = majority_label(f, scan->clusters[k]);
        if (t < 0 || scan->scene.objects[k].partial) continue;
        ++whole[static_cast<std::size_t>(t)];
        const auto& prims = scan->scene.objects[k].primitives;
        round += !prims.empty() && prims[0].kind == ShapeKind::cylinder;
      }
      for (std::size_t t = 0; t < whole.size(); ++t) {
        if (f.truth.objects[t].partial) continue;
        ++objects;
        extra += std::max(0, whole[t] - 1);
      }
    }
    return std::array{objects, extra, round};
  };
  const auto [objects, extra, round] = pieces({});
  ScanParams without;
  without.neck_max_width_share = 0;
  without.part_hang_reach_m = 0;
  const int extra_without = pieces(without)[1];
  EXPECT_GE(objects, 30);
  EXPECT_EQ(extra, 0);
  EXPECT_GE(extra_without, 3);
  EXPECT_GE(round * 10, objects * 9);
}

// A room whose every cylinder is everyday, rendered, and the index of its bottle (or its
// mug: `mug`) lo to hi metres from the camera (-1 none).
struct EverydayRoom {
  SyntheticScene scene;
  SyntheticFrame frame;
  int object = -1;
};
EverydayRoom everyday_room(std::uint64_t seed, double lo_m, double hi_m, bool mug = false) {
  SyntheticSceneParams p = room_scene_params(seed);
  p.everyday_share = 1;
  EverydayRoom r{room(p), {}, -1};
  r.frame = render_scene(r.scene);
  for (std::size_t i = 0; i < r.scene.objects.size(); ++i) {
    const SyntheticObject& o = r.scene.objects[i];
    const double range = norm(r.frame.truth.objects[i].primitives[0].center);
    // A bottle's details start with its shoulder's cone, a mug's handle is three boxes.
    const bool wanted = o.details.size() == 3 &&
                        o.details[0].kind == (mug ? ShapeKind::box : ShapeKind::cone) &&
                        o.kind == ShapeKind::cylinder;
    if (wanted && range > lo_m && range < hi_m) r.object = static_cast<int>(i);
  }
  return r;
}

// A bottle 1.95 m away (rooms 12014, every cylinder everyday): one cone through its body
// and neck explains every point within the noise, as the body's cylinder and its neck do
// together; the residuals, weighed by the information criterion, make it a cylinder with
// its neck (pair_min_secondary_share). Without that weighing, a cone.
TEST(ScannerRooms, AFarBottleIsABodyAndANeckNotOneCone) {
  const EverydayRoom r = everyday_room(12014, 1.9, 2.0);
  const SyntheticFrame& f = r.frame;
  const int bottle = r.object;
  ASSERT_GE(bottle, 0);
  const auto shape = [&](const ScanParams& params) {
    const Result<ScanResult> scan = scan_frame(f.frame, params);
    EXPECT_TRUE(scan.ok());
    std::vector<ShapeKind> kinds;
    if (!scan) return kinds;
    for (std::size_t k = 0; k < scan->clusters.size(); ++k)
      if (majority_label(f, scan->clusters[k]) == bottle)
        for (const PhysicalPrimitive& prim : scan->scene.objects[k].primitives)
          kinds.push_back(prim.kind);
    return kinds;
  };
  EXPECT_EQ(shape({}), (std::vector<ShapeKind>{ShapeKind::cylinder, ShapeKind::cylinder}));
  ScanParams without;
  without.shape.pair_min_secondary_share = 1;
  EXPECT_EQ(shape(without), std::vector<ShapeKind>{ShapeKind::cone});
}

// A bottle 1.26 m away (rooms 12029, every cylinder everyday) whose shoulder and neck
// are a third of its height: its body's cylinder explains 59 % of its points, under
// min_coverage, and it was `unknown`; with its neck the two explain it. The body's
// height ends at the shoulder: the bottle's cap, high above the side on a small disc
// about the axis, is no top of the body.
TEST(ScannerRooms, ABottleWhoseBodyExplainsTooLittleIsItsBodyAndNeck) {
  const EverydayRoom r = everyday_room(12029, 1.2, 1.3);
  const SyntheticFrame& f = r.frame;
  const int bottle = r.object;
  ASSERT_GE(bottle, 0);
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_TRUE(scan.ok());
  const auto& body = f.truth.objects[static_cast<std::size_t>(bottle)].primitives[0].dimensions_m;
  int found = 0;
  for (std::size_t k = 0; k < scan->clusters.size(); ++k) {
    if (majority_label(f, scan->clusters[k]) != bottle || scan->scene.objects[k].partial) continue;
    ++found;
    const std::vector<PhysicalPrimitive>& prims = scan->scene.objects[k].primitives;
    ASSERT_EQ(prims.size(), 2u);
    EXPECT_EQ(prims[0].kind, ShapeKind::cylinder);
    EXPECT_NEAR(prims[0].dimensions_m[0], body[0], 0.004);
    EXPECT_NEAR(prims[0].dimensions_m[1], body[1], 0.01);
  }
  EXPECT_EQ(found, 1);
}

// A bottle 1.54 m away (rooms 12102, every cylinder everyday) whose neck's cylinder,
// fitted on its lower part as a body's is, takes in the shoulder: 2.3 cm on a body of
// 3.5 cm, wider than a neck (pair_max_neck_share), and one cone through body and neck
// won. Its upper part's circle, 1.9 cm, is a neck's: a cylinder with its neck.
TEST(ScannerRooms, ABottlesNeckIsMeasuredAboveItsShoulder) {
  const EverydayRoom r = everyday_room(12102, 1.5, 1.6);
  ASSERT_GE(r.object, 0) << "the generator no longer puts the bottle in 12102";
  const Result<ScanResult> scan = scan_frame(r.frame.frame);
  ASSERT_TRUE(scan.ok());
  const double body =
      r.frame.truth.objects[static_cast<std::size_t>(r.object)].primitives[0].dimensions_m[0];
  int found = 0;
  for (std::size_t k = 0; k < scan->clusters.size(); ++k) {
    if (majority_label(r.frame, scan->clusters[k]) != r.object) continue;
    ++found;
    const std::vector<PhysicalPrimitive>& prims = scan->scene.objects[k].primitives;
    ASSERT_EQ(prims.size(), 2u);
    EXPECT_EQ(prims[0].kind, ShapeKind::cylinder);
    EXPECT_NEAR(prims[0].dimensions_m[0], body, 0.002);
    EXPECT_LT(prims[1].dimensions_m[0], prims[0].dimensions_m[0]);
  }
  EXPECT_EQ(found, 1);
}

// A mug 2.2 m away (rooms 12078, every cylinder everyday) and one 1.07 m away (12048):
// within the tolerance the depth noise gives 2.2 m away (18 mm), a wider circle through
// the body's front and the handle explains the side's points as well as the body's own
// circle does; the points' own scatter about it (1 to 2 mm, smoothed) tells them apart
// (circle_own_scatter). With every circle at the tolerance the far mug is a sphere (the
// wide circle's foot holds the table seen beside the mug) and the near one's radius
// 4 mm too wide.
TEST(ScannerRooms, AMugsCircleIsItsBodysNotOneThroughItsHandle) {
  const auto mug_radius = [](std::uint64_t seed, double lo_m, double hi_m, bool own_scatter) {
    const EverydayRoom r = everyday_room(seed, lo_m, hi_m, true);
    EXPECT_GE(r.object, 0) << "the generator no longer puts a mug in " << seed;
    ScanParams params;
    params.shape.circle_own_scatter = own_scatter;
    const Result<ScanResult> scan = scan_frame(r.frame.frame, params);
    EXPECT_TRUE(scan.ok());
    if (r.object < 0 || !scan) return std::pair{0.0, -1.0};
    const double truth =
        r.frame.truth.objects[static_cast<std::size_t>(r.object)].primitives[0].dimensions_m[0];
    for (std::size_t k = 0; k < scan->clusters.size(); ++k) {
      const auto& prims = scan->scene.objects[k].primitives;
      if (majority_label(r.frame, scan->clusters[k]) == r.object && !prims.empty() &&
          prims[0].kind == ShapeKind::cylinder)
        return std::pair{truth, prims[0].dimensions_m[0]};
    }
    return std::pair{truth, -1.0};  // not a cylinder
  };
  const auto [far_truth, far] = mug_radius(12078, 2.15, 2.35, true);
  EXPECT_NEAR(far, far_truth, 0.003);
  EXPECT_EQ(mug_radius(12078, 2.15, 2.35, false).second, -1.0);
  const auto [near_truth, near] = mug_radius(12048, 1.0, 1.1, true);
  EXPECT_NEAR(near, near_truth, 0.002);
  EXPECT_GT(std::abs(mug_radius(12048, 1.0, 1.1, false).second - near_truth), 0.003);
}

// A tin standing on another 2.1 m away (rooms 11038, half the tops stacked), where the
// crease test marks nothing: one primitive explains the two poorly and leaves the upper
// tin out above the rest, so the touching cut cuts level there and both are found; not
// without that cut (nor the outline's step, which finds it too).
TEST(ScannerRooms, AFarStackOnePrimitiveExplainsPoorlyIsCutLevel) {
  SyntheticSceneParams p = room_scene_params(11038);
  p.stacked_share = 0.5;
  const SyntheticScene s = room(p);
  const SyntheticFrame f = render_scene(s);
  const auto found = [&](const ScanParams& params, int truth) {
    const Result<ScanResult> scan = scan_frame(f.frame, params);
    EXPECT_TRUE(scan.ok());
    if (!scan) return false;
    return std::any_of(scan->clusters.begin(), scan->clusters.end(),
                       [&](const ScanCluster& c) { return majority_label(f, c) == truth; });
  };
  int upper = -1;
  for (std::size_t i = 0; i < s.objects.size(); ++i)
    if (s.objects[i].on_object >= 0 && norm(f.truth.objects[i].primitives[0].center) > 2.0 &&
        norm(f.truth.objects[i].primitives[0].center) < 2.2)
      upper = static_cast<int>(i);
  ASSERT_GE(upper, 0);
  EXPECT_TRUE(found({}, upper));
  ScanParams without;
  without.touching_level_cut = false;
  without.touching_width_step = false;
  EXPECT_FALSE(found(without, upper));
}

// The clusters of a scan whose pixels are mostly object `truth`'s.
int pieces_of(const SyntheticFrame& f, const ScanResult& scan, int truth) {
  return static_cast<int>(
      std::count_if(scan.clusters.begin(), scan.clusters.end(),
                    [&](const ScanCluster& c) { return majority_label(f, c) == truth; }));
}

// Stacked rooms' object `on_object`s standing between near and far metres away, or -1.
int stacked_between(const SyntheticScene& s, const SyntheticFrame& f, double near, double far) {
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const double d = norm(f.truth.objects[i].primitives[0].center);
    if (s.objects[i].on_object >= 0 && d > near && d < far) return static_cast<int>(i);
  }
  return -1;
}

// The upper object of rooms `seed` (half the tops stacked) standing between near and far
// metres away, and the one under it: how many clusters each is the most of, with the
// scan's defaults and with the outline's step off.
struct StackPieces {
  int upper = 0, lower = 0, upper_without_step = 0;
};
StackPieces stack_pieces(std::uint64_t seed, double near, double far) {
  SyntheticSceneParams p = room_scene_params(seed);
  p.stacked_share = 0.5;
  const SyntheticScene s = room(p);
  const SyntheticFrame f = render_scene(s);
  const int upper = stacked_between(s, f, near, far);
  EXPECT_GE(upper, 0) << seed;
  if (upper < 0) return {};
  const Result<ScanResult> scan = scan_frame(f.frame, {});
  ScanParams without;
  without.touching_width_step = false;
  const Result<ScanResult> one = scan_frame(f.frame, without);
  EXPECT_TRUE(scan.ok() && one.ok()) << seed;
  if (!scan.ok() || !one.ok()) return {};
  return {pieces_of(f, *scan, upper),
          pieces_of(f, *scan, s.objects[static_cast<std::size_t>(upper)].on_object),
          pieces_of(f, *one, upper)};
}

// A tin standing on a wider tin on the floor 2.25 m away (rooms 11041): one cone explains
// the two whole, so no misfit shows a stack, but their outline steps in width where the
// upper tin stands (touching_split.h, width_step): both are found; not without the
// outline's step. And a tin on a box 2.17 m away (rooms 11040), which one box explains
// poorly but whose misfit does not lie above the rest: beyond the crease test's reach
// the outline is tried on it too.
TEST(ScannerRooms, AFarStackIsCutWhereItsOutlineSteps) {
  for (const auto& [seed, near, far] : {std::tuple{11041, 2.0, 2.5}, std::tuple{11040, 2.1, 2.3}}) {
    const StackPieces pieces = stack_pieces(static_cast<std::uint64_t>(seed), near, far);
    EXPECT_EQ(pieces.upper, 1) << seed;
    EXPECT_EQ(pieces.lower, 1) << seed;
    EXPECT_EQ(pieces.upper_without_step, 0) << seed;
  }
}

// Single bodies whose outline steps for another reason are not cut: a tin 1.05 m away
// whose lower half a box in front hides (rooms 11020: the box's edge is no outline of
// the tin), and a tin 2.44 m away with a ball at its foot (fresh rooms 9748: the lower
// part, ball and tin, stands on two feet).
TEST(ScannerRooms, AnOutlineStepAnotherObjectMakesCutsNoBodyLevel) {
  const auto pieces = [](std::uint64_t seed, double stacked, double near, double far) {
    SyntheticSceneParams p = room_scene_params(seed);
    p.stacked_share = stacked;
    const SyntheticScene s = room(p);
    const SyntheticFrame f = render_scene(s);
    const Result<ScanResult> scan = scan_frame(f.frame, {});
    EXPECT_TRUE(scan.ok());
    int count = -1;
    for (std::size_t i = 0; i < s.objects.size() && scan.ok(); ++i) {
      const SyntheticObject& o = s.objects[i];
      const double d = norm(f.truth.objects[i].primitives[0].center);
      if (o.kind == ShapeKind::cylinder && d > near && d < far && o.on_object < 0)
        count = pieces_of(f, *scan, static_cast<int>(i));
    }
    return count;
  };
  EXPECT_EQ(pieces(11020, 0.5, 1.0, 1.1), 1);
  EXPECT_EQ(pieces(9748, 0, 2.4, 2.5), 1);
}

TEST(ScannerRooms, TouchingPairsWithinTwoAndAHalfMetresAreTwoObjects) {
  const FeatureFigures r = scan_feature("touching", 6001, 6010, 2.5);
  EXPECT_GE(r.pairs, 6);
  EXPECT_GE(r.pairs_split * 10, r.pairs * 8);
}

// The touching rooms first..last (within 2.5 m) scanned without a rule and with it:
// more pairs found as two objects, no fewer classed right, no more extra pieces.
// Returns the two figures, without first.
std::pair<FeatureFigures, FeatureFigures> touching_without_and_with(std::uint64_t first, std::uint64_t last,
                                                                    const ScanParams& without) {
  const FeatureFigures before = scan_feature("touching", first, last, 2.5, 0, without);
  const FeatureFigures after = scan_feature("touching", first, last, 2.5);
  EXPECT_GT(after.pairs_split, before.pairs_split);
  EXPECT_GE(after.correct, before.correct);
  EXPECT_LE(after.pieces_extra, before.pieces_extra);
  return {before, after};
}

// Touching pairs the segmenter leaves as one cluster (no crease above the noise), one
// primitive explaining them poorly: cut in two by the information criterion
// (touching_split.h). Against the scan without the cut on the same rooms.
TEST(ScannerRooms, TouchingPairsOnePrimitiveExplainsPoorlyAreCutInTwo) {
  ScanParams off;
  off.touching_max_coverage = 0;
  touching_without_and_with(6001, 6040, off);
}

// Two bodies of a size under one primitive (two balls: a box or a cylinder over both)
// leave out a share of each, so the one-side test alone does not refit the cut; their
// footprint narrows to their contact, which a convex body's never does. Against the
// scan with the one-side test alone on the same rooms; more classed right too.
TEST(ScannerRooms, TouchingPairsWhoseFootprintNarrowsBetweenThemAreCutInTwo) {
  ScanParams one_side;
  one_side.touching_waist_share = 0;
  const auto [before, after] = touching_without_and_with(6041, 6080, one_side);
  EXPECT_GT(after.correct, before.correct);
}

// A part's minimum is the pixels a 5 cm body shows at its depth, not a fixed count:
// against the minimum of a 9 cm body (about the 400 pixels it was, at 2 m) on the same
// touching rooms, more pairs found as two objects (78 -> 80 of 91), more classed right.
TEST(ScannerRooms, TouchingPartsAsSmallAsAFiveCentimetreBodyAreCut) {
  ScanParams fixed;
  fixed.touching_min_part_size_m = 0.09;
  const auto [before, after] = touching_without_and_with(6001, 6080, fixed);
  EXPECT_GT(after.correct, before.correct);
}

TEST(ScannerRooms, ObjectsAcrossATableEdgeAreOneObjectOfTheirShape) {
  const FeatureFigures r = scan_feature("overhang", 6001, 6010, 2.5);
  EXPECT_GE(r.objects, 8);
  EXPECT_GE(r.found * 10, r.objects * 9);
  // 1 until session 18 (6002's object at 1.45 m); with each support region on its own
  // plane, 6007's at 1.17 m is in two pieces too (29 of the 30 classed right either way).
  EXPECT_LE(r.pieces_extra, 2);
  EXPECT_GE(r.correct * 10, r.found * 85 / 10);
}

TEST(ScannerRooms, DarkObjectsNearTheCameraFoundAndClassed) {
  const FeatureFigures r = scan_feature("dark", 6001, 6010, 1.5);
  EXPECT_GE(r.objects, 6);
  EXPECT_GE(r.found * 10, r.objects * 9);
  EXPECT_GE(r.correct * 10, r.found * 9);
}

// Session 8: 7 of 20 found, all classed right, 4 of them on their board's plane (the
// board not found as a support, or its objects taken with the shelf). Session 9, a far
// board a support by its seen area and no leg rule on a raised board: 15 found, 12
// classed right, 10 on their board's plane. Holds that.
TEST(ScannerRooms, ObjectsOnShelfBoardsFoundOnTheirBoard) {
  const FeatureFigures r = scan_feature("on-shelf", 6001, 6012, 4.0);
  EXPECT_GE(r.objects, 12);
  EXPECT_GE(r.found * 10, r.objects * 7);
  EXPECT_GE(r.correct * 10, r.objects * 6);
  EXPECT_GE(r.on_own_support * 3, r.found * 2);
}

// A shelf cut by the image border, its side and board edge fitted as one box, spans
// the board and what stands on it; merged as its "part", that object was lost. An object
// cut by the border or hidden holds no part: against the scan where any object does, on
// the same rooms, more objects on the shelf's boards found.
TEST(ScannerRooms, ObjectsOnShelfBoardsAreNoPartOfTheShelfTheBorderCuts) {
  // Both without the seen-under rule (session 15, partial_when_seen_under), which takes
  // one of the four shelf pieces reported whole (room 6046) when bigger objects hold
  // every part, not with this rule on: 3 against 4, the default's 4 being those before
  // the seen-under rule. This test weighs unseen_hold_no_parts alone.
  ScanParams any;
  any.unseen_hold_no_parts = false;
  any.partial_when_seen_under = false;
  ScanParams unseen_hold_none;
  unseen_hold_none.partial_when_seen_under = false;
  const FeatureFigures before = scan_feature("on-shelf", 6013, 6052, 4.0, 0, any);
  const FeatureFigures after = scan_feature("on-shelf", 6013, 6052, 4.0, 0, unseen_hold_none);
  EXPECT_GT(after.found, before.found);
  EXPECT_GE(after.correct, before.correct);
  EXPECT_LE(after.false_shelf, before.false_shelf);
}

// Held-out seed 5069: a frustum widening up (r 11.3 cm, h 12.5 cm) 1.13 m away whose
// flared side the cylinder of its rim leaves unexplained (it explains 95 % of the points,
// the frustum all); the cylinder won by the complexity margin, a fixed share of the
// score whatever the number of points. The information criterion weighs them.
TEST(ScannerRooms, BowlWhoseSideTheRimCylinderMissesIsAFrustum) {
  const SyntheticScene s = room(world_scene_params(5069));
  const SyntheticFrame f = render_scene(s);
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_TRUE(scan.ok());
  int bowls = 0;
  for (std::size_t k = 0; k < scan->clusters.size(); ++k) {
    const int t = majority_label(f, scan->clusters[k]);
    if (t < 0 || !s.objects[static_cast<std::size_t>(t)].apex_down) continue;
    const SyntheticObject& truth = s.objects[static_cast<std::size_t>(t)];
    if (truth.dimensions_m[0] < 0.1) continue;
    ++bowls;
    const PhysicalObject& got = scan->scene.objects[k];
    ASSERT_FALSE(got.primitives.empty());
    EXPECT_EQ(got.primitives[0].kind, ShapeKind::cone);
    EXPECT_NEAR(got.primitives[0].dimensions_m[0], truth.dimensions_m[0], 0.005);
    EXPECT_NEAR(got.primitives[0].narrow_radius_m, truth.narrow_radius_m, 0.01);
  }
  EXPECT_EQ(bowls, 1);
}

// Held-out seed 5117: a flat cone apex up (r 11.9 cm, h 7.7 cm) 1.38 m away whose
// cylinder start (cov 0.26) sent the cone fit off to a cone 1.3 m wide: no cone
// candidate, read as a cylinder. The second start, from the footprint's circle, fits it.
TEST(ScannerRooms, FlatConeWhoseCylinderStartFailsIsACone) {
  const SyntheticScene s = room(world_scene_params(5117));
  const SyntheticFrame f = render_scene(s);
  const Result<ScanResult> scan = scan_frame(f.frame);
  ASSERT_TRUE(scan.ok());
  int cones = 0;
  for (std::size_t k = 0; k < scan->clusters.size(); ++k) {
    const int t = majority_label(f, scan->clusters[k]);
    if (t < 0) continue;
    const SyntheticObject& truth = s.objects[static_cast<std::size_t>(t)];
    if (truth.kind != ShapeKind::cone || truth.apex_down || truth.dimensions_m[0] < 0.11) continue;
    ++cones;
    const PhysicalObject& got = scan->scene.objects[k];
    ASSERT_FALSE(got.primitives.empty());
    EXPECT_EQ(got.primitives[0].kind, ShapeKind::cone);
    EXPECT_NEAR(got.primitives[0].dimensions_m[0], truth.dimensions_m[0], 0.005);
    EXPECT_NEAR(got.primitives[0].dimensions_m[1], truth.dimensions_m[1], 0.005);
  }
  EXPECT_EQ(cones, 1);
}

// Dark objects 1.5 to 2.5 m away keep a scatter of pixels facing the camera; the
// clustering joins the fragments their missing depth parts (dropout_join.h). Session 8:
// 50 of 66 found (46 without the join), 41 classed right. Session 10: the returned
// pixels in grid blocks whose own grid pixel has no depth are taken with the part
// beside them, and the size floor counts the missing pixels a part encloses as its
// area (dropout_block_pixels, silhouette_pixels): 58 found, 46 classed right (49 and
// 40 on the code before). Session 31: every fragment under the size floor is offered to
// the join, not only those under half of it (dropout_join_to_floor): 59 of 66 found, 54
// classed right (58 and 51 without).
TEST(ScannerRooms, DarkObjectsInTheMiddleBandFoundFromThePointsThatAreThere) {
  const FeatureFigures r = scan_feature("dark", 6001, 6030, 2.5, 1.5);
  EXPECT_GE(r.objects, 60);
  EXPECT_GE(r.found * 100, r.objects * 88);
  EXPECT_GE(r.correct * 100, r.objects * 80);
  ScanParams half;
  half.dropout_join_to_floor = false;
  const FeatureFigures before = scan_feature("dark", 6001, 6030, 2.5, 1.5, half);
  EXPECT_GT(r.correct, before.correct);
}

// The join's widest gap is a scan parameter and config key (dropout_max_gap_px): checked
// when set, and it is the one the scan uses (a gap of one pixel joins no fragment the
// clustering's window leaves apart, so fewer dark objects are found).
TEST(ScannerRooms, DropoutGapIsAScanParameter) {
  const Result<ScanParams> conf = parse_scan_config("dropout_max_gap_px 0\n", "t.conf");
  ASSERT_FALSE(conf.ok());
  EXPECT_EQ(conf.error().location, (Location{"t.conf", 1, 20})) << conf.error().format();
  const Result<ScanParams> three = parse_scan_config("dropout_max_gap_px 3\n", "t.conf");
  ASSERT_TRUE(three.ok());
  EXPECT_EQ(three->dropout_max_gap_px, 3);
  ScanParams bad;
  bad.dropout_max_gap_px = 0;
  const SyntheticFrame f = render_scene(room(only(6001, "dark")));
  const Result<ScanResult> r = scan_frame(f.frame, bad);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("ScanParams.dropout_max_gap_px"), std::string::npos) << r.error().message;
  int found[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    ScanParams p;
    p.dropout_max_gap_px = k == 0 ? 1 : ScanParams{}.dropout_max_gap_px;
    for (std::uint64_t seed = 6001; seed <= 6030; ++seed) {
      const SyntheticScene s = room(only(seed, "dark"));
      const SyntheticFrame frame = render_scene(s);
      const Result<ScanResult> scan = scan_frame(frame.frame, p);
      ASSERT_TRUE(scan.ok());
      std::vector<char> seen(s.objects.size(), 0);
      for (const ScanCluster& c : scan->clusters) {
        const int t = majority_label(frame, c);
        if (t >= 0 && s.objects[static_cast<std::size_t>(t)].albedo < 1) seen[static_cast<std::size_t>(t)] = 1;
      }
      found[k] += static_cast<int>(std::count(seen.begin(), seen.end(), 1));
    }
  }
  EXPECT_LT(found[0], found[1]);
}

TEST(ScannerRooms, ChairsAndShelvesAreNotReportedWholeAsProps) {
  const FeatureFigures chairs = scan_feature("chair", 6001, 6010, 4.0);
  const FeatureFigures shelves = scan_feature("shelf", 6001, 6010, 4.0);
  // The table's objects are still found beside them.
  EXPECT_GE(chairs.found * 10, chairs.objects * 8);
  EXPECT_GE(shelves.found * 10, shelves.objects * 8);
  EXPECT_LE(chairs.false_chair, 2);
  EXPECT_LE(shelves.false_shelf, 2);
}


// Held-out room 5035: a border sliver at the left edge is fitted as a cylinder of r 0.5 m
// (an arc cut by the border), and the ball at the table's front edge (0.88 m) and a flat
// bowl (1.37 m), 30 cm from it in the image, lie inside that solid: taken as its parts,
// they were one `unknown` object with it. An object cut by the border holds no part
// (unseen_hold_no_parts): both are found and classed right with the rule, neither
// without it.
TEST(ScannerRooms, ASliverCutByTheBorderHoldsNoBallAndBowl) {
  const SyntheticScene s = room(room_scene_params(5035));
  const SyntheticFrame f = render_scene(s);
  int right[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    ScanParams p;
    p.unseen_hold_no_parts = k == 1;
    // The ball's pixels beyond the table's edge (overhang_margin_m) make it the bigger
    // of the two, no part of the sliver's: off, to see this rule alone.
    p.overhang_margin_m = 0;
    // The sliver's refit from ball and bowl is no sliver shape either, so the give-back
    // of a spoiling part (part_fit_slack) undoes the join too: off, for the same reason.
    p.part_fit_slack = 1.0;
    // The supports as they were found then: with each region on its own plane
    // (support_fit_sigmas, session 18) both come out right without the rule too.
    p.support_fit_sigmas = 0;
    // ... and the sliver's circle as it was fitted then (at the tolerance): at its points'
    // own scatter (session 42) it holds neither without the rule too.
    p.shape.circle_own_scatter = false;
    const Result<ScanResult> scan = scan_frame(f.frame, p);
    ASSERT_TRUE(scan.ok());
    for (std::size_t c = 0; c < scan->clusters.size(); ++c) {
      const int t = majority_label(f, scan->clusters[c]);
      if (t < 0) continue;
      const PhysicalObject& got = scan->scene.objects[c];
      // Truth 0 is the ball, truth 2 the bowl.
      if ((t == 0 || t == 2) && !got.primitives.empty() &&
          got.primitives[0].kind == s.objects[static_cast<std::size_t>(t)].kind)
        ++right[k];
    }
  }
  EXPECT_EQ(right[0], 0);
  EXPECT_EQ(right[1], 2);
}

// Held-out room 5118: the touching cut of a ball gives the ball's part a piece of the
// flat torus it touches; the piece lies in the torus's solid, and merged into it the
// torus's refit was a cylinder (coverage 0.86, the torus alone 1.00). A piece that turns
// its owner into another shape, explaining less by part_fit_slack, is given back: the
// torus is a torus with the rule, a cylinder without.
TEST(ScannerRooms, APieceThatTurnsItsOwnerIntoAnotherShapeIsGivenBack) {
  const SyntheticScene s = room(room_scene_params(5118));
  const SyntheticFrame f = render_scene(s);
  std::size_t torus = s.objects.size();
  for (std::size_t t = 0; t < s.objects.size(); ++t)
    if (s.objects[t].kind == ShapeKind::torus && !f.truth.objects[t].partial) torus = t;
  ASSERT_LT(torus, s.objects.size());
  ShapeKind got[2] = {ShapeKind::plane, ShapeKind::plane};
  for (int k = 0; k < 2; ++k) {
    ScanParams p;
    p.part_fit_slack = k == 1 ? ScanParams{}.part_fit_slack : 1.0;
    // With a solid hiding its own far side (shape_own_side_hides, session 23) the merged
    // torus's refit is no cylinder, and it stays a torus without the rule too; so it does
    // with a torus fitted to its own points (shape_torus_own_points, session 44), the
    // piece's higher points left out. Both off, to see this rule alone.
    p.shape.own_side_hides = false;
    p.shape.torus_own_points = false;
    const Result<ScanResult> scan = scan_frame(f.frame, p);
    ASSERT_TRUE(scan.ok());
    // The torus's object: the biggest of the clusters mostly its pixels.
    std::size_t biggest = 0;
    for (std::size_t c = 0; c < scan->clusters.size(); ++c) {
      const std::size_t n = scan->clusters[c].pixels.size();
      const PhysicalObject& o = scan->scene.objects[c];
      if (majority_label(f, scan->clusters[c]) == static_cast<int>(torus) && n > biggest &&
          !o.primitives.empty())
        biggest = n, got[k] = o.primitives[0].kind;
    }
  }
  EXPECT_NE(got[0], ShapeKind::torus);
  EXPECT_EQ(got[1], ShapeKind::torus);
}

// Held-out room 5108: a cylinder (r 4 cm, h 19.4 cm) 0.91 m away across the table's front
// edge. The prism test kept only what stands inside the table's hull: its top's disc cut
// straight along the edge, which a box explained at 0.5 mm RMS. Pixels in the height
// band up to overhang_margin_m beyond the hull join the cluster grown from inside it:
// a cylinder with the rule, a box without.
TEST(ScannerRooms, AnObjectAcrossTheTableEdgeKeepsWhatOverhangs) {
  const SyntheticScene s = room(room_scene_params(5108));
  const SyntheticFrame f = render_scene(s);
  ShapeKind got[2] = {ShapeKind::plane, ShapeKind::plane};
  int seen[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    ScanParams p;
    p.overhang_margin_m = k == 0 ? 0 : ScanParams{}.overhang_margin_m;
    const Result<ScanResult> scan = scan_frame(f.frame, p);
    ASSERT_TRUE(scan.ok());
    for (std::size_t c = 0; c < scan->clusters.size(); ++c) {
      const int t = majority_label(f, scan->clusters[c]);
      if (t < 0 || !s.objects[static_cast<std::size_t>(t)].overhang) continue;
      ASSERT_FALSE(scan->scene.objects[c].primitives.empty());
      got[k] = scan->scene.objects[c].primitives[0].kind;
      ++seen[k];
    }
  }
  EXPECT_EQ(seen[0], 1);
  EXPECT_EQ(seen[1], 1);
  EXPECT_EQ(got[0], ShapeKind::box);
  EXPECT_EQ(got[1], ShapeKind::cylinder);
}

}  // namespace
}  // namespace annex
