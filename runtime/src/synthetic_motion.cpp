// Hand-speed sequences: props in any orientation, a gripping hand, a moving head.
// Plain arithmetic like synthetic_scene.cpp, on the same ray caster (shape_rays.h).
#include "annex/runtime/synthetic_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>

#include "annex/runtime/icp_tracker.h"
#include "annex/runtime/rigid_motion.h"
#include "shape_rays.h"
#include "synthetic_pixels.h"

namespace annex {
namespace {

using namespace shape_rays;
using Hit = LocalHit;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMinT = 1e-6;
constexpr double kFrameRateHz = 30.0;
constexpr Vec3 kUp{0, 0, 1};

double deg_to_rad(double deg) { return deg * std::numbers::pi / 180.0; }

Quat axis_angle(Vec3 axis, double angle_rad) {
  const Vec3 a = normalized(axis);
  const double s = std::sin(angle_rad / 2);
  return {std::cos(angle_rad / 2), a.x * s, a.y * s, a.z * s};
}

std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t salt) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (salt + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// The rate profile shared by turns and head motion: +1 for about half of each cycle, -1
// for the other half, smooth reversals between (a clipped sine).
double profile(double t, double period) {
  return std::clamp(1.5 * std::sin(2 * std::numbers::pi * t / period), -1.0, 1.0);
}

// Sum of the profile over frames 0..k-1 (evaluated mid-frame): how far a motion at unit
// peak rate has gone by frame k.
double travelled(int k, double period) {
  double s = 0;
  for (int j = 0; j < k; ++j) s += profile(j + 0.5, period);
  return s;
}

double center_height(ShapeKind kind, const std::vector<double>& d) {
  switch (kind) {
    case ShapeKind::sphere: return d[0];
    case ShapeKind::cylinder:
    case ShapeKind::cone: return d[1] * 0.5;
    case ShapeKind::torus: return d[1];
    case ShapeKind::box: return d[2] * 0.5;
    case ShapeKind::plane: return 0;
  }
  return 0;
}

double bounding_radius(ShapeKind kind, const std::vector<double>& d) {
  switch (kind) {
    case ShapeKind::sphere: return d[0];
    case ShapeKind::cylinder:
    case ShapeKind::cone: return std::hypot(d[0], d[1] * 0.5);
    case ShapeKind::torus: return d[0] + d[1];
    case ShapeKind::box: return 0.5 * std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    case ShapeKind::plane: return 0.5 * std::hypot(d[0], d[1]);
  }
  return 0;
}

std::vector<double> prop_dimensions(ShapeKind kind, std::mt19937_64& rng) {
  switch (kind) {
    case ShapeKind::sphere: return {uniform(rng, 0.04, 0.07)};
    case ShapeKind::cylinder: return {uniform(rng, 0.035, 0.05), uniform(rng, 0.12, 0.22)};
    case ShapeKind::cone: return {uniform(rng, 0.04, 0.07), uniform(rng, 0.10, 0.20)};
    case ShapeKind::torus: return {uniform(rng, 0.05, 0.07), uniform(rng, 0.015, 0.025)};
    case ShapeKind::box:
      return {uniform(rng, 0.07, 0.14), uniform(rng, 0.06, 0.12), uniform(rng, 0.06, 0.14)};
    case ShapeKind::plane: return {uniform(rng, 0.10, 0.25), uniform(rng, 0.08, 0.20)};
  }
  return {};
}

// ---- ray casting in a solid's local frame (centre at the origin, axis +Z) ----

Hit hit_local(ShapeKind kind, const std::vector<double>& dim, Vec3 o, Vec3 d) {
  switch (kind) {
    case ShapeKind::sphere: return hit_sphere(o, d, dim[0]);
    case ShapeKind::cylinder: return hit_cylinder(o, d, dim[0], dim[1]);
    case ShapeKind::cone: return hit_cone(o, d, dim[0], dim[1]);
    case ShapeKind::torus: return hit_torus(o, d, dim[0], dim[1]);
    case ShapeKind::box: return hit_box(o, d, {dim[0] * 0.5, dim[1] * 0.5, dim[2] * 0.5});
    case ShapeKind::plane: return hit_box(o, d, {dim[0] * 0.5, dim[1] * 0.5, 0.0005});
  }
  return {};
}

// A ray (room frame) against a posed solid; the normal comes back in the room frame.
Hit hit_solid(const MotionSolid& s, Vec3 origin, Vec3 dir) {
  const Quat inv = conjugate(s.pose.rotation);
  Hit h = hit_local(s.kind, s.dimensions_m, rotate(inv, origin - s.pose.position), rotate(inv, dir));
  h.normal = rotate(s.pose.rotation, h.normal);
  return h;
}

// The hand gripping a prop, in the prop's frame: three fingers across the side facing
// the camera (touching it), a palm against its side and the start of a forearm.
std::vector<MotionSolid> make_hand(const MotionProp& prop, Vec3 camera_position) {
  std::vector<MotionSolid> hand;
  const Vec3 to_camera = rotate(conjugate(prop.rest.rotation), camera_position - prop.rest.position);
  Vec3 front{to_camera.x, to_camera.y, 0};
  if (norm(front) < 1e-6) front = {0, -1, 0};
  front = normalized(front);
  const Vec3 side = cross(kUp, front);
  // Extent of the prop along a local direction at height z: a ray cast from outside.
  auto extent = [&](Vec3 dir, double z) {
    const Vec3 start = dir * 1.0 + Vec3{0, 0, z};
    const Hit h = hit_local(prop.kind, prop.dimensions_m, start, dir * -1.0);
    return h.t < kInf ? 1.0 - h.t : -1.0;
  };
  const double finger = 0.018;
  const double half_h = center_height(prop.kind, prop.dimensions_m);
  const double spacing = std::min(0.022, 0.35 * half_h);
  const Quat finger_axes = quat_from_axes(side, front, kUp);
  for (int k = -1; k <= 1; ++k) {
    const double z = k * spacing;
    const double e = extent(front, z);
    if (e <= 0) continue;
    hand.push_back({ShapeKind::box, {0.08, finger, finger},
                    {front * (e + finger * 0.5 + 0.001) + Vec3{0, 0, z}, finger_axes}});
  }
  const double e_side = std::max(0.0, extent(side * -1.0, 0));
  const Vec3 palm_center = side * -(e_side + 0.016) + front * 0.01;
  hand.push_back({ShapeKind::box, {0.03, 0.08, 0.09}, {palm_center, finger_axes}});
  hand.push_back({ShapeKind::box, {0.14, 0.055, 0.055},
                  {palm_center + side * -0.085 + Vec3{0, 0, -0.01}, finger_axes}});
  return hand;
}

// Image rectangle a sphere (camera frame) can cover; the whole image when it reaches
// behind the camera.
struct Rect {
  double u0 = 0, v0 = 0, u1 = -1, v1 = -1;
  bool contains(int u, int v) const { return u >= u0 && u <= u1 && v >= v0 && v <= v1; }
};

Rect project_sphere(const CameraIntrinsics& k, Vec3 c, double r, double grow) {
  Rect out{kInf, kInf, -kInf, -kInf};
  for (int i = 0; i < 8; ++i) {
    const Vec3 p{c.x + (i & 1 ? r : -r), c.y + (i & 2 ? r : -r), c.z + (i & 4 ? r : -r)};
    if (p.z < 0.05) return {-1e9, -1e9, 1e9, 1e9};
    const double u = k.fx * p.x / p.z + k.cx, v = k.fy * p.y / p.z + k.cy;
    out.u0 = std::min(out.u0, u), out.u1 = std::max(out.u1, u);
    out.v0 = std::min(out.v0, v), out.v1 = std::max(out.v1, v);
  }
  return {out.u0 - grow, out.v0 - grow, out.u1 + grow, out.v1 + grow};
}

constexpr std::array<std::array<std::uint8_t, 3>, 5> kPalette{
    {{220, 50, 47}, {38, 139, 210}, {133, 153, 0}, {181, 137, 0}, {108, 113, 196}}};

}  // namespace

Result<MotionScene> generate_motion_scene(const MotionSceneParams& params) {
  if (params.kinds.empty() || params.kinds.size() > 5)
    return Error{"a motion scene holds 1 to 5 props", {}};
  if (params.held < 0 || params.held > static_cast<int>(params.kinds.size()))
    return Error{"held props must be between 0 and the number of props", {}};
  if (!(params.speed_m_per_frame >= 0 && params.speed_m_per_frame <= 0.1) ||
      !(std::abs(params.spin_deg_per_frame) <= 45) ||
      !(std::abs(params.camera_yaw_deg_per_frame) <= 10) || norm(params.camera_velocity_m_per_frame) > 0.05)
    return Error{"motion rates out of range (at most 0.1 m and 45 degrees per frame for props, "
                 "0.05 m and 10 degrees per frame for the head)",
                 {}};
  if (!(params.path_radius_m > 0.02) || !(params.spin_period_frames >= 4) ||
      !(params.camera_period_frames >= 4))
    return Error{"path radius or motion periods too small", {}};
  std::mt19937_64 rng(params.seed);
  MotionScene s;
  s.params = params;
  s.camera = params.camera;
  s.table_half_x_m = uniform(rng, 0.6, 0.8);
  s.table_half_y_m = uniform(rng, 0.4, 0.5);
  s.floor_depth_m = uniform(rng, 0.72, 0.78);
  s.wall_y_m = s.table_half_y_m + uniform(rng, 0.3, 0.8);
  const double tilt = deg_to_rad(uniform(rng, 35, 50));
  const double distance = uniform(rng, 0.8, 1.0);
  const Vec3 cx{1, 0, 0}, cy{0, -std::sin(tilt), -std::cos(tilt)},
      cz{0, std::cos(tilt), -std::sin(tilt)};
  // Aimed a little above the table, where the held props travel.
  const Vec3 aim{0, 0, 0.08};
  s.camera_rest = {aim - cz * distance, quat_from_axes(cx, cy, cz)};

  const size_t n = params.kinds.size();
  for (size_t i = 0; i < n; ++i) {
    MotionProp p;
    p.kind = params.kinds[i];
    p.dimensions_m = prop_dimensions(p.kind, rng);
    p.color = kPalette[i % kPalette.size()];
    // Held props first, at the ends of the row, still ones between.
    const double slot = i == 0 ? 0.0 : i == 1 ? static_cast<double>(n - 1) : static_cast<double>(i - 1);
    const double x = n > 1 ? (slot - 0.5 * static_cast<double>(n - 1)) * 0.25 + uniform(rng, -0.02, 0.02)
                           : 0.0;
    const double y = uniform(rng, -0.05, 0.05);
    p.rest = {{x, y, center_height(p.kind, p.dimensions_m)},
              axis_angle(kUp, deg_to_rad(uniform(rng, 0, 360)))};
    p.held = static_cast<int>(i) < params.held;
    // The loop comes towards the camera, rising (in the vertical plane through the
    // prop and the camera): a prop picked up and shown, put back; it never dips below the
    // table and stays in view while the head turns.
    Vec3 toward{s.camera_rest.position.x - x, s.camera_rest.position.y - y, 0};
    p.path_forward = normalized(toward);
    p.path_up = kUp;
    const double phi = uniform(rng, 0, 2 * std::numbers::pi);
    p.spin_axis = normalized(Vec3{std::cos(phi), std::sin(phi), 0.35});
    s.props.push_back(std::move(p));
  }
  if (params.hand && !s.props.empty() && s.props[0].held)
    s.hand = make_hand(s.props[0], s.camera_rest.position);
  return s;
}

Pose motion_camera_pose(const MotionScene& s, int frame) {
  const double k = travelled(std::max(0, frame), s.params.camera_period_frames);
  const Quat yaw = axis_angle(kUp, deg_to_rad(s.params.camera_yaw_deg_per_frame * k));
  return {s.camera_rest.position + s.params.camera_velocity_m_per_frame * k,
          normalized(yaw * s.camera_rest.rotation)};
}

Pose motion_prop_pose(const MotionScene& s, int prop, int frame) {
  const MotionProp& p = s.props.at(static_cast<size_t>(prop));
  const int k = std::max(0, frame - s.params.still_frames);
  if (!p.held || k == 0) return p.rest;
  // The chord of one frame's arc is the speed.
  const double r = s.params.path_radius_m;
  const double step = 2 * std::asin(std::min(1.0, s.params.speed_m_per_frame / (2 * r)));
  // The hand picks the prop up: the speed grows over the first ramp frames.
  const int ramp = std::max(0, s.params.ramp_frames);
  const double frames_moved =
      k <= ramp ? 0.5 * k * (k + 1) / (ramp + 1.0) : 0.5 * ramp + (k - ramp) * 1.0;
  const double theta = step * frames_moved;
  const Vec3 c = p.rest.position + p.path_forward * (r * std::sin(theta)) +
                 p.path_up * (r * (1 - std::cos(theta)));
  const double angle =
      deg_to_rad(s.params.spin_deg_per_frame * travelled(k, s.params.spin_period_frames));
  return {c, normalized(p.rest.rotation * axis_angle(p.spin_axis, angle))};
}

Pose motion_prop_in_camera(const MotionScene& s, int prop, int frame) {
  return compose(inverse(motion_camera_pose(s, frame)), motion_prop_pose(s, prop, frame));
}

std::vector<MotionSolid> motion_hand(const MotionScene& s, int frame) {
  std::vector<MotionSolid> out;
  if (s.hand.empty()) return out;
  const Pose prop = motion_prop_pose(s, 0, frame);
  for (const MotionSolid& part : s.hand) out.push_back({part.kind, part.dimensions_m, compose(prop, part.pose)});
  return out;
}

SyntheticFrame render_motion_frame(const MotionScene& s, int frame, const SensorNoiseParams& noise) {
  const CameraIntrinsics& cam = s.camera;
  const Pose camera = motion_camera_pose(s, frame);
  const Pose camera_from_room = inverse(camera);
  const size_t n = static_cast<size_t>(cam.width) * cam.height;
  synthetic_pixels::Draws draws{std::mt19937_64(mix_seed(s.params.seed, static_cast<std::uint64_t>(frame)))};
  const double jitter = noise.enabled ? noise.lateral_sigma_px : 0.0;

  // Every solid of the frame with its image rectangle; label per solid.
  std::vector<MotionSolid> solids;
  std::vector<int> labels;
  for (size_t i = 0; i < s.props.size(); ++i) {
    solids.push_back({s.props[i].kind, s.props[i].dimensions_m,
                      motion_prop_pose(s, static_cast<int>(i), frame)});
    labels.push_back(static_cast<int>(i));
  }
  for (MotionSolid& part : motion_hand(s, frame)) {
    solids.push_back(std::move(part));
    labels.push_back(kLabelOccluder);
  }
  std::vector<Rect> rects;
  for (const MotionSolid& so : solids) {
    const Vec3 c = compose(camera_from_room, so.pose).position;
    rects.push_back(project_sphere(cam, c, bounding_radius(so.kind, so.dimensions_m), 2 + 5 * jitter));
  }
  const MotionSolid table{ShapeKind::box,
                          {2 * s.table_half_x_m, 2 * s.table_half_y_m, s.table_thickness_m},
                          {{0, 0, -s.table_thickness_m * 0.5}, {}}};

  const Vec3 o = camera.position;
  const auto hits = synthetic_pixels::cast_pixels(
      cam, jitter, draws, [&](int u, int v, double ray_x, double ray_y) {
        // Unit camera z: the ray parameter is the depth.
        const Vec3 dir = rotate(camera.rotation, {ray_x, ray_y, 1});
        Hit best;
        int label = kLabelNothing;
        auto take = [&](const Hit& hit, int l) {
          if (hit.t < best.t) best = hit, label = l;
        };
        take(hit_solid(table, o, dir), kLabelTable);
        if (dir.z < 0) take({(-s.floor_depth_m - o.z) / dir.z, {0, 0, 1}}, kLabelFloor);
        if (dir.y > 0) take({(s.wall_y_m - o.y) / dir.y, {0, -1, 0}}, kLabelWall);
        for (size_t i = 0; i < solids.size(); ++i)
          if (rects[i].contains(u, v)) take(hit_solid(solids[i], o, dir), labels[i]);
        if (label == kLabelNothing || !(best.t > kMinT) || best.t == kInf) return synthetic_pixels::SurfaceHit{};
        return synthetic_pixels::SurfaceHit{best.t, std::abs(dot(best.normal, normalized(dir))), label};
      });

  SyntheticFrame out;
  out.frame.index = frame;
  out.frame.timestamp_s = frame / kFrameRateHz;
  synthetic_pixels::sense_pixels(
      hits, cam, noise, draws,
      [&](int label) -> synthetic_pixels::Rgb {
        if (label >= 0) return s.props[static_cast<size_t>(label)].color;
        if (label == kLabelTable) return {165, 120, 80};
        if (label == kLabelWall) return {205, 200, 185};
        if (label == kLabelOccluder) return {205, 155, 125};
        return {90, 90, 100};
      },
      out.frame, out.labels);

  // Truth in the camera frame.
  Plane table_plane;
  table_plane.normal = rotate(camera_from_room.rotation, kUp);
  table_plane.d = -dot(table_plane.normal, compose(camera_from_room, Pose{}).position);
  out.truth.support = table_plane;
  std::vector<int> counts(s.props.size(), 0);
  for (size_t i = 0; i < n; ++i)
    if (out.labels[i] >= 0 && std::isfinite(out.frame.points[i].z))
      ++counts[static_cast<size_t>(out.labels[i])];
  for (size_t i = 0; i < s.props.size(); ++i) {
    const Pose pc = motion_prop_in_camera(s, static_cast<int>(i), frame);
    PhysicalPrimitive prim;
    prim.kind = s.props[i].kind;
    prim.dimensions_m = s.props[i].dimensions_m;
    prim.center = pc.position;
    prim.axis = pc.axis();
    prim.fit = 1.0;
    PhysicalObject obj;
    obj.id = "o";
    obj.id += std::to_string(i + 1);
    obj.primitives.push_back(prim);
    obj.point_count = counts[i];
    obj.fit = 1.0;
    out.truth.objects.push_back(std::move(obj));
  }
  return out;
}

}  // namespace annex
