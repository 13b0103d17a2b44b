// Synthetic tabletop scenes: random layout, analytic ray casting, Kinect noise.
// No PCL here on purpose: the generator is plain arithmetic and compiles fast.
#include "annex/runtime/synthetic_scene.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>

#include "shape_rays.h"
#include "synthetic_pixels.h"

namespace annex {
namespace {

using namespace shape_rays;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMinT = 1e-6;  // ignore hits at the ray origin
constexpr double kFrameRateHz = 30.0;
constexpr Vec3 kUp{0, 0, 1};

double deg_to_rad(double deg) { return deg * std::numbers::pi / 180.0; }

// Rows of the camera-to-table rotation's transpose: the camera axes in the table frame.
struct CameraAxes {
  Vec3 x, y, z;
};

CameraAxes camera_axes(double tilt_deg, double roll_deg = 0) {
  const double s = std::sin(deg_to_rad(tilt_deg)), c = std::cos(deg_to_rad(tilt_deg));
  const Vec3 x{1, 0, 0}, y{0, -s, -c};
  if (roll_deg == 0) return {x, y, {0, c, -s}};
  // Rolled about the optical axis: the image's x and y turn in their plane.
  const double sr = std::sin(deg_to_rad(roll_deg)), cr = std::cos(deg_to_rad(roll_deg));
  return {x * cr + y * sr, y * cr - x * sr, {0, c, -s}};
}

// Mixes the scene seed with a frame index so every frame has its own noise stream.
std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t salt) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (salt + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// Height of the shape's centre above the table it rests on.
double center_height(const SyntheticObject& o) {
  const auto& d = o.dimensions_m;
  switch (o.kind) {
    case ShapeKind::sphere: return d[0];
    case ShapeKind::cylinder:
      return o.lying ? d[0] : d[1] * 0.5;
    case ShapeKind::cone: return d[1] * 0.5;
    case ShapeKind::torus: return d[1];
    case ShapeKind::box: return d[2] * 0.5;
    case ShapeKind::plane: return 0;  // a sheet lying on the table
  }
  return 0;
}

double half_height(const SyntheticObject& o) { return center_height(o); }

// Radius of the circle the object covers on the table, whatever its yaw.
double footprint_radius(const SyntheticObject& o) {
  if (o.lying) return std::hypot(o.dimensions_m[0], 0.5 * o.dimensions_m[1]);
  return annex::footprint_radius(o.kind, o.dimensions_m);
}

// A lying cylinder's footprint: its length along the yaw, its diameter across.
Vec3 lying_footprint(const SyntheticObject& o) {
  return {o.dimensions_m[1], 2 * o.dimensions_m[0], 0};
}

// Half the object's horizontal extent along the horizontal unit vector u: a box's
// support function, the footprint radius for round shapes.
double extent_along(const SyntheticObject& o, Vec3 u) {
  const bool rectangle = o.kind == ShapeKind::box || o.kind == ShapeKind::plane || o.lying;
  if (!rectangle) return footprint_radius(o);
  const Vec3 size = o.lying ? lying_footprint(o) : Vec3{o.dimensions_m[0], o.dimensions_m[1], 0};
  const double yaw = o.yaw_deg * std::numbers::pi / 180.0;
  const double along_x = std::abs(std::cos(yaw) * u.x + std::sin(yaw) * u.y);
  const double along_y = std::abs(-std::sin(yaw) * u.x + std::cos(yaw) * u.y);
  return 0.5 * (along_x * size.x + along_y * size.y);
}

int uniform_int(std::mt19937_64& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(rng);
}

// Cones of every kind (world_scene_params): apex up or down, pointed or cut, flat or
// tall. A cone apex down always keeps a foot (it could not stand on its tip).
void vary_cone(SyntheticObject& o, std::mt19937_64& rng) {
  o.dimensions_m = {uniform(rng, 0.04, 0.12), uniform(rng, 0.03, 0.25)};
  o.apex_down = uniform(rng, 0, 1) < 0.5;
  const bool cut = o.apex_down || uniform(rng, 0, 1) < 0.5;
  o.narrow_radius_m = cut ? o.dimensions_m[0] * uniform(rng, 0.35, 0.75) : 0.0;
}

std::vector<double> random_dimensions(ShapeKind kind, std::mt19937_64& rng) {
  switch (kind) {
    case ShapeKind::sphere: return {uniform(rng, 0.03, 0.08)};
    case ShapeKind::cylinder: return {uniform(rng, 0.03, 0.06), uniform(rng, 0.08, 0.30)};
    case ShapeKind::cone: return {uniform(rng, 0.04, 0.08), uniform(rng, 0.08, 0.25)};
    case ShapeKind::torus: return {uniform(rng, 0.04, 0.08), uniform(rng, 0.015, 0.03)};
    case ShapeKind::box:
      return {uniform(rng, 0.05, 0.25), uniform(rng, 0.05, 0.25), uniform(rng, 0.05, 0.25)};
    case ShapeKind::plane: return {uniform(rng, 0.10, 0.30), uniform(rng, 0.10, 0.30)};
  }
  return {};
}

// Pixel rectangle a table-frame box projects to; empty when it is behind the camera.
struct PixelRect {
  double u0 = 0, v0 = 0, u1 = -1, v1 = -1;
  bool empty() const { return u1 < u0 || v1 < v0; }
  double area() const { return empty() ? 0 : (u1 - u0) * (v1 - v0); }
};

PixelRect project_box(const SyntheticScene& s, Vec3 center, Vec3 half) {
  PixelRect r{kInf, kInf, -kInf, -kInf};
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner{center.x + (i & 1 ? half.x : -half.x), center.y + (i & 2 ? half.y : -half.y),
                      center.z + (i & 4 ? half.z : -half.z)};
    const Vec3 p = table_to_camera_point(s, corner);
    if (p.z < 0.05) return {0, 0, static_cast<double>(s.camera.width - 1),
                            static_cast<double>(s.camera.height - 1)};
    const double u = s.camera.fx * p.x / p.z + s.camera.cx;
    const double v = s.camera.fy * p.y / p.z + s.camera.cy;
    r.u0 = std::min(r.u0, u), r.u1 = std::max(r.u1, u);
    r.v0 = std::min(r.v0, v), r.v1 = std::max(r.v1, v);
  }
  return r;
}

// The box round the object and its details (a handle reaches out, a neck up).
PixelRect object_rect(const SyntheticScene& s, const SyntheticObject& o) {
  double f = footprint_radius(o), lo = -half_height(o), hi = half_height(o);
  for (const SyntheticDetail& part : o.details) {
    f = std::max(f, std::hypot(part.offset.x, part.offset.y) +
                        annex::footprint_radius(part.kind, part.dimensions_m));
    const double half =
        part.kind == ShapeKind::box ? 0.5 * part.dimensions_m[2] : 0.5 * part.dimensions_m[1];
    lo = std::min(lo, part.offset.z - half), hi = std::max(hi, part.offset.z + half);
  }
  return project_box(s, o.center + Vec3{0, 0, 0.5 * (lo + hi)}, {f, f, 0.5 * (hi - lo)});
}

double overlap_area(const PixelRect& a, const PixelRect& b) {
  const double w = std::min(a.u1, b.u1) - std::max(a.u0, b.u0);
  const double h = std::min(a.v1, b.v1) - std::max(a.v0, b.v0);
  return w > 0 && h > 0 ? w * h : 0;
}

// ---- ray casting, in the object's local frame (centre at the origin, axis +Z) ----

Vec3 rotate_z(Vec3 v, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}

// A ray against one object, in the table frame.
LocalHit hit_object(const SyntheticObject& obj, Vec3 origin, Vec3 dir) {
  const double yaw = deg_to_rad(obj.yaw_deg);
  const Vec3 o = rotate_z(origin - obj.center, -yaw);
  const Vec3 d = rotate_z(dir, -yaw);
  const auto& dim = obj.dimensions_m;
  LocalHit h;
  switch (obj.kind) {
    case ShapeKind::sphere: h = hit_sphere(o, d, dim[0]); break;
    case ShapeKind::cylinder:
      if (obj.lying) {  // turned a quarter about local y: its axis along local x
        h = hit_cylinder({-o.z, o.y, o.x}, {-d.z, d.y, d.x}, dim[0], dim[1]);
        h.normal = {h.normal.z, h.normal.y, -h.normal.x};
      } else {
        h = hit_cylinder(o, d, dim[0], dim[1]);
      }
      break;
    case ShapeKind::cone: {
      // Apex down: the cone mirrored about its middle.
      const double m = obj.apex_down ? -1 : 1;
      h = hit_cone({o.x, o.y, m * o.z}, {d.x, d.y, m * d.z}, dim[0], dim[1], obj.narrow_radius_m);
      h.normal.z *= m;
      break;
    }
    case ShapeKind::torus: h = hit_torus(o, d, dim[0], dim[1]); break;
    case ShapeKind::box: h = hit_box(o, d, {dim[0] * 0.5, dim[1] * 0.5, dim[2] * 0.5}); break;
    case ShapeKind::plane: h = hit_box(o, d, {dim[0] * 0.5, dim[1] * 0.5, 0.0005}); break;
  }
  for (const SyntheticDetail& part : obj.details) {
    const Vec3 po = o - part.offset;
    const auto& pd = part.dimensions_m;
    LocalHit ph;
    if (part.kind == ShapeKind::cylinder)
      ph = hit_cylinder(po, d, pd[0], pd[1]);
    else if (part.kind == ShapeKind::cone)
      ph = hit_cone(po, d, pd[0], pd[1], part.narrow_radius_m);
    else
      ph = hit_box(po, d, {pd[0] * 0.5, pd[1] * 0.5, pd[2] * 0.5});
    if (ph.t < h.t) h = ph;
  }
  h.normal = rotate_z(h.normal, yaw);
  return h;
}

constexpr std::array<std::array<std::uint8_t, 3>, 10> kPalette{{{220, 50, 47},
                                                                {38, 139, 210},
                                                                {133, 153, 0},
                                                                {181, 137, 0},
                                                                {211, 54, 130},
                                                                {42, 161, 152},
                                                                {203, 75, 22},
                                                                {108, 113, 196},
                                                                {240, 240, 240},
                                                                {30, 30, 30}}};

int block_label(SyntheticBlock::Role role) {
  switch (role) {
    case SyntheticBlock::Role::leg: return kLabelLeg;
    case SyntheticBlock::Role::chair: return kLabelChair;
    case SyntheticBlock::Role::shelf: return kLabelShelf;
    case SyntheticBlock::Role::back_chair:
      return kLabelBackChair;
    case SyntheticBlock::Role::cabinet:
      return kLabelCabinet;
    case SyntheticBlock::Role::pole:
      return kLabelPole;
    case SyntheticBlock::Role::support:
    case SyntheticBlock::Role::tall: return kLabelFurniture;
  }
  return kLabelFurniture;
}

// A dark object's infrared return, albedo * cos(incidence) / z^2 (z in metres), against
// the sensor's detection floor: none below 0.02, all above 0.07, linear between (a
// white surface head-on stays above it to 3.8 m); other surfaces keep their model.
std::function<double(const synthetic_pixels::SurfaceHit&)> dark_return(const SyntheticScene& s) {
  bool any = false;
  for (const SyntheticObject& o : s.objects) any = any || o.albedo < 1;
  if (!any) return {};
  std::vector<double> albedo;
  for (const SyntheticObject& o : s.objects) albedo.push_back(o.albedo);
  return [albedo](const synthetic_pixels::SurfaceHit& h) {
    if (h.label < 0 || albedo[static_cast<std::size_t>(h.label)] >= 1) return 1.0;
    const double r = albedo[static_cast<std::size_t>(h.label)] * h.cos_incidence / (h.depth * h.depth);
    return std::clamp((r - 0.02) / 0.05, 0.0, 1.0);
  };
}

}  // namespace

double kinect_axial_sigma_m(double z_m) {
  return DepthNoise{}.sigma_z(z_m);
}

Vec3 table_to_camera_direction(const SyntheticScene& scene, Vec3 d) {
  const CameraAxes a = camera_axes(scene.camera_tilt_deg, scene.camera_roll_deg);
  return {dot(a.x, d), dot(a.y, d), dot(a.z, d)};
}

Vec3 table_to_camera_point(const SyntheticScene& scene, Vec3 p) {
  return table_to_camera_direction(scene, p - scene.camera_position);
}

namespace {
constexpr int kLayoutAttempts = 30;
// Which side of the table the second support goes (the tall furniture the other);
// draws from the stream only when there is furniture beside the table.
double uniform_side(const SyntheticSceneParams& params, std::mt19937_64& rng) {
  if (params.side_support_objects <= 0 && !params.tall_furniture) return 1;
  return uniform(rng, 0, 1) < 0.5 ? -1 : 1;
}
constexpr int kPlacementAttempts = 300;
void add_room_furniture(const SyntheticSceneParams& params, SyntheticScene& s, std::mt19937_64& rng);
void add_floor_objects(const SyntheticSceneParams& params, SyntheticScene& s, std::mt19937_64& rng,
                       std::vector<PixelRect>& rects);
void add_shelf_objects(const SyntheticSceneParams& params, SyntheticScene& s, std::vector<PixelRect>& rects);
void add_room_extras(const SyntheticSceneParams& params, SyntheticScene& s);
void add_stacked_objects(const SyntheticSceneParams& params, SyntheticScene& s);
void add_everyday_objects(const SyntheticSceneParams& params, SyntheticScene& s);
void add_lying_objects(const SyntheticSceneParams& params, SyntheticScene& s);
std::optional<SyntheticScene> try_layout(const SyntheticSceneParams& params, std::mt19937_64& rng,
                                         int& placed_count);
}  // namespace

Result<SyntheticScene> generate_scene(const SyntheticSceneParams& params) {
  if (params.object_count < 0) return Error{"object count must not be negative", {}};
  if (params.object_count > 0 && params.kinds.empty())
    return Error{"no shape kinds to choose from", {}};
  if (!(params.camera_distance_min_m > 0.3) ||
      params.camera_distance_max_m < params.camera_distance_min_m ||
      !(params.camera_tilt_min_deg >= 0) || params.camera_tilt_max_deg > 89 ||
      params.camera_tilt_max_deg < params.camera_tilt_min_deg)
    return Error{"camera distance or tilt range out of bounds", {}};
  if (!(params.table_height_min_m >= 0.2) || params.table_height_max_m < params.table_height_min_m ||
      params.table_height_max_m > 1.5 || !(params.camera_roll_max_deg >= 0) ||
      params.camera_roll_max_deg > 30)
    return Error{"table height range outside 0.2-1.5 m or camera roll outside 0-30 degrees", {}};
  if (params.side_support_objects < 0 || !(params.cut_share >= 0 && params.cut_share <= 1))
    return Error{"side support objects must not be negative, cut share within [0, 1]", {}};
  auto share = [](double x) { return x >= 0 && x <= 1; };
  if (params.floor_objects < 0 || params.shelf_objects < 0 || !share(params.chair_chance) ||
      !share(params.shelf_chance) || !share(params.touching_share) ||
      !share(params.overhang_share) || !share(params.dark_share) ||
      !share(params.back_chair_chance) || !share(params.cabinet_chance) ||
      !share(params.pole_chance) || !share(params.stacked_share) || !share(params.everyday_share) ||
      !share(params.lying_share))
    return Error{
        "floor and shelf objects must not be negative; chair, shelf, back chair, cabinet and "
        "pole chances, touching, overhang, dark, stacked, everyday and lying shares within "
        "[0, 1]",
        {}};

  // Whole layouts are redrawn (camera included) when the objects do not fit; the
  // random stream stays the seed's, so the result is still deterministic.
  std::mt19937_64 rng(params.seed);
  int best_placed = -1;
  for (int layout = 0; layout < kLayoutAttempts; ++layout) {
    int placed = 0;
    std::optional<SyntheticScene> s = try_layout(params, rng, placed);
    if (s) return std::move(*s);
    best_placed = std::max(best_placed, placed);
  }
  return Error{"could place only " + std::to_string(best_placed) + " of " +
                   std::to_string(params.object_count) +
                   " objects in view without overlap (seed " + std::to_string(params.seed) + ")",
               {}};
}

namespace {

bool is_boxy(const SyntheticObject& o) {
  return o.kind == ShapeKind::box || o.kind == ShapeKind::plane;
}

// Half the object's horizontal extent along u at height z above its support (0 where
// the object does not reach): the radius profile of a round shape, a box's support
// function over its height.
double extent_at(const SyntheticObject& o, Vec3 u, double z) {
  const auto& d = o.dimensions_m;
  const double h = 2 * center_height(o);
  if (z < 0 || z > h) return 0;
  switch (o.kind) {
    case ShapeKind::sphere: return std::sqrt(std::max(0.0, d[0] * d[0] - (z - d[0]) * (z - d[0])));
    case ShapeKind::cylinder: {
      if (!o.lying) return d[0];
      SyntheticObject slice = o;  // the cross-section at z: a rectangle as long as the axis
      slice.dimensions_m[0] = std::sqrt(std::max(0.0, d[0] * d[0] - (z - d[0]) * (z - d[0])));
      return extent_along(slice, u);
    }
    case ShapeKind::cone: {
      const double up = o.apex_down ? z / h : 1 - z / h;  // 1 at the wide end
      return o.narrow_radius_m + (d[0] - o.narrow_radius_m) * up;
    }
    case ShapeKind::torus: return d[0] + std::sqrt(std::max(0.0, d[1] * d[1] - (z - d[1]) * (z - d[1])));
    case ShapeKind::box:
    case ShapeKind::plane: return extent_along(o, u);
  }
  return 0;
}

// Beside `partner` on the same table, touching it: along one of a box partner's axes
// (a box placed there turned like it, face to face), else any way, at the distance
// where the two profiles meet at one height and nowhere overlap.
void place_touching(SyntheticObject& obj, const SyntheticObject& partner, std::mt19937_64& rng) {
  double heading = uniform(rng, 0, 2 * std::numbers::pi);
  if (is_boxy(partner)) heading = deg_to_rad(partner.yaw_deg + 90.0 * uniform_int(rng, 0, 3));
  if (is_boxy(obj)) obj.yaw_deg = std::fmod(heading * 180.0 / std::numbers::pi + 360.0, 360.0);
  const Vec3 u{std::cos(heading), std::sin(heading), 0};
  const double top = 2 * std::min(center_height(obj), center_height(partner));
  double gap = extent_along(partner, u) + extent_along(obj, u);  // a sheet: no height
  if (top > 0) gap = 0;
  for (double z = 0; top > 0 && z <= top + 1e-9; z += top / 200)
    gap = std::max(gap, extent_at(partner, u, z) + extent_at(obj, u * -1.0, z));
  obj.center = {partner.center.x + u.x * gap, partner.center.y + u.y * gap, center_height(obj)};
}

// Across the table's front, left or right edge: the centre over the table (it stands),
// 25 to 75 % of its extent across the edge beyond it. False when it cannot fit.
bool place_overhanging(SyntheticObject& obj, const SyntheticScene& s, std::mt19937_64& rng) {
  const int edge = uniform_int(rng, 0, 2);  // 0 front (towards the camera), 1 left, 2 right
  const Vec3 out = edge == 0 ? Vec3{0, -1, 0} : Vec3{edge == 1 ? -1.0 : 1.0, 0, 0};
  const double e = extent_along(obj, out) * uniform(rng, 0.25, 0.75);  // inside by e
  const double along_half = edge == 0 ? s.table_half_x_m : s.table_half_y_m;
  const double along_extent = extent_along(obj, edge == 0 ? Vec3{1, 0, 0} : Vec3{0, 1, 0});
  const double room = along_half - along_extent - 0.02;
  if (room <= 0) return false;
  const double along = uniform(rng, -room, room);
  if (edge == 0) obj.center = {along, -s.table_half_y_m + e, center_height(obj)};
  else obj.center = {out.x * (s.table_half_x_m - e), along, center_height(obj)};
  return true;
}

// Whether the table or a furniture block hides point p (table frame) from the camera.
bool sight_blocked(const SyntheticScene& s, Vec3 p) {
  const Vec3 o = s.camera_position, d = p - o;
  auto before = [](const LocalHit& h) { return h.t > kMinT && h.t < 0.995; };
  const Vec3 table_half{s.table_half_x_m, s.table_half_y_m, s.table_thickness_m * 0.5};
  if (before(hit_box(o - Vec3{0, 0, -s.table_thickness_m * 0.5}, d, table_half))) return true;
  for (const SyntheticBlock& b : s.furniture)
    if (before(hit_box(o - b.center, d, b.size_m * 0.5))) return true;
  return false;
}

// A chair's size and place: its seat's centre (x, y) on the floor plan, the seat's width
// and depth, the seat top's height above the floor and the back's height above it.
struct ChairSize {
  double x, y, w, d, seat_top, back;
};

// A chair's seat, back and four legs as furniture blocks; its back on the seat's far
// side (back_sign +1, away from the camera) or near side (-1, towards it).
void add_chair(SyntheticScene& s, const ChairSize& c, double back_sign, SyntheticBlock::Role role) {
  const double thick = 0.03, leg = 0.03, floor = -s.floor_depth_m;
  s.furniture.push_back({{c.x, c.y, floor + c.seat_top - 0.5 * thick}, {c.w, c.d, thick}, role});
  s.furniture.push_back(
      {{c.x, c.y + back_sign * 0.5 * (c.d - thick), floor + c.seat_top + 0.5 * c.back},
       {c.w, thick, c.back},
       role});
  const double leg_height = c.seat_top - thick;
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      s.furniture.push_back({{c.x + sx * (0.5 * c.w - 0.02 - 0.5 * leg),
                              c.y + sy * (0.5 * c.d - 0.02 - 0.5 * leg), floor + 0.5 * leg_height},
                             {leg, leg, leg_height},
                             role});
}

// A chair at the table's far side and a two-level shelf against the wall, each by its
// chance; the wall moves back to make room. Nothing drawn when both chances are 0.
void add_room_furniture(const SyntheticSceneParams& params, SyntheticScene& s, std::mt19937_64& rng) {
  const bool chair = params.chair_chance > 0 && uniform(rng, 0, 1) < params.chair_chance;
  const bool shelf = params.shelf_chance > 0 && uniform(rng, 0, 1) < params.shelf_chance;
  if (!chair && !shelf) return;
  const double side = uniform(rng, 0, 1) < 0.5 ? -1 : 1;  // the chair's half, the shelf the other
  const double floor = -s.floor_depth_m;
  if (chair) {
    const double w = uniform(rng, 0.4, 0.48), d = uniform(rng, 0.4, 0.48);
    const double seat_top = uniform(rng, 0.42, 0.48), back = uniform(rng, 0.35, 0.5);
    // Its seat's front edge under the table when the seat clears the table's underside
    // (and its legs clear the table's), else a gap behind the table.
    const bool fits_under = seat_top + 0.02 < s.floor_depth_m - s.table_thickness_m;
    const double under = fits_under ? uniform(rng, 0.05, 0.2) : -uniform(rng, 0.03, 0.12);
    const double x = side * uniform(rng, 0.0, s.table_half_x_m - 0.11 - 0.5 * w);
    const double y = s.table_half_y_m - under + 0.5 * d;
    add_chair(s, {x, y, w, d, seat_top, back}, 1, SyntheticBlock::Role::chair);
    s.wall_y_m = std::max(s.wall_y_m, y + 0.5 * d + 0.05);
  }
  if (shelf) {
    const double w = uniform(rng, 0.6, 0.9), d = uniform(rng, 0.28, 0.38);
    const double low = uniform(rng, 0.25, 0.4), high = low + uniform(rng, 0.3, 0.4);
    const double board = 0.02;
    s.wall_y_m = std::max(s.wall_y_m, s.table_half_y_m + d + 0.1);
    const double x = -side * (0.5 * w + uniform(rng, 0.25, 0.45));
    const double y = s.wall_y_m - 0.5 * d - 0.005;
    for (double z : {low, high})
      s.furniture.push_back({{x, y, floor + z - 0.5 * board}, {w - 2 * board, d, board}, SyntheticBlock::Role::shelf});
    for (double sx : {-1.0, 1.0})
      s.furniture.push_back({{x + sx * 0.5 * (w - board), y, floor + 0.5 * high}, {board, d, high},
                             SyntheticBlock::Role::shelf});
  }
}

// An object of a random kind and size, yaw and colour, for a place beside the table's
// (the floor, a shelf board); its caller places it.
SyntheticObject random_object_beside(const SyntheticSceneParams& params, std::mt19937_64& rng) {
  SyntheticObject obj;
  obj.kind = params.kinds[std::uniform_int_distribution<std::size_t>(0, params.kinds.size() - 1)(rng)];
  obj.dimensions_m = random_dimensions(obj.kind, rng);
  if (params.varied_cones && obj.kind == ShapeKind::cone) vary_cone(obj, rng);
  obj.yaw_deg = uniform(rng, 0, 360);
  obj.color = kPalette[static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(kPalette.size()) - 1))];
  return obj;
}

// Whether an image box lies inside the view, 8 pixels from its border, and overlaps no
// placed object's box by more than max_overlap of the smaller.
bool whole_in_view(const SyntheticScene& s, const PixelRect& r, const std::vector<PixelRect>& rects,
                   double max_overlap) {
  const double margin_px = 8, width = s.camera.width, height = s.camera.height;
  if (r.u0 < margin_px || r.v0 < margin_px || r.u1 > width - 1 - margin_px || r.v1 > height - 1 - margin_px)
    return false;
  for (const PixelRect& other : rects)
    if (overlap_area(r, other) > max_overlap * std::min(r.area(), other.area())) return false;
  return true;
}

// Objects standing on the floor beside a piece of furniture (or the table), in view,
// seen over the table and furniture, clear of everything; skipped when no place is found.
void add_floor_objects(const SyntheticSceneParams& params, SyntheticScene& s, std::mt19937_64& rng,
                       std::vector<PixelRect>& rects) {
  if (params.floor_objects <= 0 || params.kinds.empty()) return;
  std::vector<Vec3> anchors_center{{0, 0, 0}}, anchors_half{{s.table_half_x_m, s.table_half_y_m, 0}};
  for (const SyntheticBlock& b : s.furniture)
    if (b.role == SyntheticBlock::Role::support || b.role == SyntheticBlock::Role::tall) {
      anchors_center.push_back(b.center);
      anchors_half.push_back(b.size_m * 0.5);
    }
  for (int j = 0; j < params.floor_objects; ++j) {
    SyntheticObject obj = random_object_beside(params, rng);
    obj.support = -1;
    const double f = footprint_radius(obj);
    for (int attempt = 0; attempt < kPlacementAttempts; ++attempt) {
      const auto a = static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(anchors_center.size()) - 1));
      const Vec3 c = anchors_center[a], h = anchors_half[a];
      const int face = uniform_int(rng, 0, 2);  // in front, left, right of it
      const double gap = f + uniform(rng, 0.03, 0.2);
      Vec3 p = face == 0 ? Vec3{c.x + uniform(rng, -h.x, h.x), c.y - h.y - gap, 0}
                         : Vec3{c.x + (face == 1 ? -1 : 1) * (h.x + gap), c.y + uniform(rng, -h.y, h.y), 0};
      p.z = -s.floor_depth_m + center_height(obj);
      obj.center = p;
      // Not under the table, inside furniture, past the wall or against another object.
      if (std::abs(p.x) < s.table_half_x_m + f + 0.02 && std::abs(p.y) < s.table_half_y_m + f + 0.02) continue;
      if (p.y + f + 0.02 > s.wall_y_m) continue;
      bool clear = true;
      for (const SyntheticBlock& b : s.furniture)
        if (std::abs(p.x - b.center.x) < 0.5 * b.size_m.x + f + 0.02 &&
            std::abs(p.y - b.center.y) < 0.5 * b.size_m.y + f + 0.02)
          clear = false;
      for (const SyntheticObject& other : s.objects)
        if (std::hypot(p.x - other.center.x, p.y - other.center.y) < f + footprint_radius(other) + 0.02)
          clear = false;
      if (!clear) continue;
      const Vec3 top = p + Vec3{0, 0, half_height(obj)};
      if (table_to_camera_point(s, p).z > 3.8 || sight_blocked(s, top) || sight_blocked(s, p)) continue;
      const PixelRect r = object_rect(s, obj);
      if (!whole_in_view(s, r, rects, params.max_view_overlap)) continue;
      rects.push_back(r);
      s.objects.push_back(obj);
      break;
    }
  }
}

// The shelf's boards (thinner than wide; its side panels are not) and, for each, the
// room above it up to the next board (infinite for the top one).
std::vector<std::pair<std::size_t, double>> shelf_boards(const SyntheticScene& s) {
  std::vector<std::pair<std::size_t, double>> boards;
  for (std::size_t k = 0; k < s.furniture.size(); ++k) {
    const SyntheticBlock& b = s.furniture[k];
    if (b.role != SyntheticBlock::Role::shelf || !(b.size_m.z < b.size_m.x)) continue;
    const double top = b.center.z + 0.5 * b.size_m.z;
    double room = kInf;
    for (const SyntheticBlock& a : s.furniture)
      if (a.role == SyntheticBlock::Role::shelf && a.size_m.z < a.size_m.x && a.center.z > b.center.z)
        room = std::min(room, a.center.z - 0.5 * a.size_m.z - top);
    boards.emplace_back(k, room);
  }
  return boards;
}

// Objects standing on the shelf's boards: their whole footprint on the board, 3 cm
// below the board above, their top and the front of their foot seen past the table,
// the furniture and that board, in range and in view, clear of every other object.
// From a stream of their own (the scene's seed mixed), so the room's other draws stay.
void add_shelf_objects(const SyntheticSceneParams& params, SyntheticScene& s, std::vector<PixelRect>& rects) {
  if (params.shelf_objects <= 0 || params.kinds.empty()) return;
  const std::vector<std::pair<std::size_t, double>> boards = shelf_boards(s);
  if (boards.empty()) return;
  std::mt19937_64 rng(mix_seed(params.seed, 0x5e1f));
  const double clearance = 0.03;
  for (int j = 0; j < params.shelf_objects; ++j) {
    SyntheticObject obj = random_object_beside(params, rng);
    const double f = footprint_radius(obj);
    for (int attempt = 0; attempt < kPlacementAttempts; ++attempt) {
      const auto& [k, room] = boards[static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(boards.size()) - 1))];
      const SyntheticBlock& b = s.furniture[k];
      const double hx = 0.5 * b.size_m.x - f - 0.01, hy = 0.5 * b.size_m.y - f - 0.01;
      if (hx <= 0 || hy <= 0 || 2 * half_height(obj) + clearance > room) continue;
      const double top = b.center.z + 0.5 * b.size_m.z;
      const Vec3 p{b.center.x + uniform(rng, -hx, hx), b.center.y + uniform(rng, -hy, hy), top + center_height(obj)};
      obj.center = p;
      bool clear = true;
      for (const SyntheticObject& other : s.objects)
        if (std::hypot(p.x - other.center.x, p.y - other.center.y) < f + footprint_radius(other) + 0.02 &&
            std::abs(p.z - other.center.z) < half_height(obj) + half_height(other) + 0.02)
          clear = false;
      if (!clear) continue;
      const Vec3 crown{p.x, p.y, top + 2 * half_height(obj)}, foot{p.x, p.y - f, top};
      if (table_to_camera_point(s, p).z > 3.8 || sight_blocked(s, crown) || sight_blocked(s, foot)) continue;
      const PixelRect r = object_rect(s, obj);
      if (!whole_in_view(s, r, rects, params.max_view_overlap)) continue;
      obj.support = static_cast<int>(k) + 1;
      rects.push_back(r);
      s.objects.push_back(obj);
      break;
    }
  }
}

// The nearest and farthest camera depth of a table-frame box's corners.
std::pair<double, double> depth_range(const SyntheticScene& s, Vec3 center, Vec3 half) {
  double lo = kInf, hi = -kInf;
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner{center.x + (i & 1 ? half.x : -half.x), center.y + (i & 2 ? half.y : -half.y),
                      center.z + (i & 4 ? half.z : -half.z)};
    const double z = table_to_camera_point(s, corner).z;
    lo = std::min(lo, z), hi = std::max(hi, z);
  }
  return {lo, hi};
}

// A place on the floor for a box of half sizes `half` standing there: `ahead` metres in
// front of the camera (horizontally, within [near, far]) and in its horizontal view, in
// front of the wall, 3 cm clear of the table, the furniture and every object's
// footprint, a share of the image at least, and hiding no object: where its image box
// meets an object's (grown by the jitter's reach) it lies wholly behind that object, so
// every object is seen as before. None when no place is found.
std::optional<Vec3> place_extra(const SyntheticScene& s, std::mt19937_64& rng, Vec3 half,
                                double near, double far) {
  const double gap = 0.03, min_image_share = 0.03, grow_px = 6, half_view = 0.55;
  std::vector<PixelRect> object_rects;
  std::vector<double> object_far;
  for (const SyntheticObject& o : s.objects) {
    const PixelRect r = object_rect(s, o);
    const double f = footprint_radius(o);
    object_rects.push_back({r.u0 - grow_px, r.v0 - grow_px, r.u1 + grow_px, r.v1 + grow_px});
    object_far.push_back(depth_range(s, o.center, {f, f, half_height(o)}).second);
  }
  const PixelRect image{0, 0, s.camera.width - 1.0, s.camera.height - 1.0};
  auto clear_of = [&](Vec3 c, Vec3 center, Vec3 other_half) {
    return std::abs(c.x - center.x) > half.x + other_half.x + gap ||
           std::abs(c.y - center.y) > half.y + other_half.y + gap;
  };
  for (int attempt = 0; attempt < kPlacementAttempts; ++attempt) {
    const double ahead = uniform(rng, near, far);
    const Vec3 c{s.camera_position.x + uniform(rng, -half_view, half_view) * ahead,
                 s.camera_position.y + ahead, -s.floor_depth_m + half.z};
    if (c.y + half.y + gap > s.wall_y_m ||
        !clear_of(c, {0, 0, 0}, {s.table_half_x_m, s.table_half_y_m, 0}))
      continue;
    bool clear = true;
    for (const SyntheticBlock& b : s.furniture)
      clear = clear && clear_of(c, b.center, b.size_m * 0.5);
    for (const SyntheticObject& o : s.objects) {
      const double f = footprint_radius(o);
      clear = clear && clear_of(c, o.center, {f, f, 0});
    }
    const PixelRect r = project_box(s, c, half);
    if (!clear || overlap_area(r, image) < min_image_share * image.area()) continue;
    const double near_z = depth_range(s, c, half).first;
    for (std::size_t k = 0; k < object_rects.size(); ++k)
      clear = clear && (overlap_area(r, object_rects[k]) == 0 || near_z > object_far[k] + gap);
    if (clear) return c;
  }
  return std::nullopt;
}

// A chair seen from behind: its back on the camera's side of the seat, 0.9 to 2.5 m away.
void add_back_chair(SyntheticScene& s, std::mt19937_64& rng) {
  const double w = uniform(rng, 0.4, 0.48), d = uniform(rng, 0.4, 0.48);
  const double seat_top = uniform(rng, 0.42, 0.48), back = uniform(rng, 0.35, 0.5);
  const std::optional<Vec3> c =
      place_extra(s, rng, {0.5 * w, 0.5 * d, 0.5 * (seat_top + back)}, 0.9, 2.5);
  if (c) add_chair(s, {c->x, c->y, w, d, seat_top, back}, -1, SyntheticBlock::Role::back_chair);
}

// A cabinet face-on, its front 0.7 to 1.5 m ahead of the camera: a body, two doors standing
// proud of it with a gap between them, a plinth below them, a bar handle on each.
void add_cabinet(SyntheticScene& s, std::mt19937_64& rng) {
  const double w = uniform(rng, 0.6, 1.0), d = uniform(rng, 0.35, 0.5), h = uniform(rng, 0.7, 1.1);
  const double door = 0.018, handle = 0.022, plinth = 0.08, rim = 0.015, door_gap = 0.006;
  const double depth = d + door + handle;
  const std::optional<Vec3> c =
      place_extra(s, rng, {0.5 * w, 0.5 * depth, 0.5 * h}, 0.7 + 0.5 * depth, 1.5 + 0.5 * depth);
  if (!c) return;
  const double front = c->y - 0.5 * depth, floor = -s.floor_depth_m;
  const auto role = SyntheticBlock::Role::cabinet;
  s.furniture.push_back({{c->x, front + handle + door + 0.5 * d, c->z}, {w, d, h}, role});
  const double door_w = 0.5 * (w - 2 * rim - door_gap), door_h = h - plinth - rim;
  for (double sx : {-1.0, 1.0}) {
    const double door_x = c->x + sx * (0.5 * door_gap + 0.5 * door_w);
    s.furniture.push_back({{door_x, front + handle + 0.5 * door, floor + plinth + 0.5 * door_h},
                           {door_w, door, door_h},
                           role});
    s.furniture.push_back(
        {{c->x + sx * (0.5 * door_gap + 0.04), front + 0.5 * handle, floor + h - rim - 0.15},
         {0.015, handle, 0.12},
         role});
  }
}

// A post from the floor up past the view (a pillar, a lamp's stand), 0.7 to 2.2 m away.
void add_pole(SyntheticScene& s, std::mt19937_64& rng) {
  const double side = uniform(rng, 0.06, 0.12), height = 2.5;
  const std::optional<Vec3> c =
      place_extra(s, rng, {0.5 * side, 0.5 * side, 0.5 * height}, 0.7, 2.2);
  if (c) s.furniture.push_back({*c, {side, side, height}, SyntheticBlock::Role::pole});
}

// A dark object (dark_share): its albedo, and a grey to match.
void darken(SyntheticObject& o, double albedo) {
  o.albedo = albedo;
  const auto grey = static_cast<std::uint8_t>(60 * albedo + 15);
  o.color = {grey, grey, static_cast<std::uint8_t>(grey + 5)};
}

// Half the width of the level top `o` offers another object: a box's shorter side, a
// cylinder's radius; 0 for shapes with no flat top.
double top_half_width(const SyntheticObject& o) {
  if (o.kind == ShapeKind::box) return 0.5 * std::min(o.dimensions_m[0], o.dimensions_m[1]);
  if (o.kind == ShapeKind::cylinder && !o.lying) return o.dimensions_m[0];
  return 0;
}

// An object standing on `lower`'s top: a box, cylinder or cone drawn as any other until
// its footprint fits on the top less kRim_m (a mug on a book, a small tin on a large
// one), else made narrower to a random share of the top (a tin on a tin of its size),
// its centre anywhere its footprint stays on the top. Empty when it would be smaller
// than the scan's 5 cm objects.
std::optional<SyntheticObject> object_on_top(const SyntheticSceneParams& params,
                                             const SyntheticObject& lower, std::mt19937_64& rng) {
  constexpr double kRim_m = 0.005, kSmallest_m = 0.05;
  constexpr int kDraws = 8;
  static constexpr std::array kinds{ShapeKind::box, ShapeKind::cylinder, ShapeKind::cone};
  const double room = top_half_width(lower) - kRim_m;
  SyntheticObject obj;
  for (int draw = 0; draw < kDraws; ++draw) {
    obj.kind = kinds[static_cast<std::size_t>(uniform_int(rng, 0, 2))];
    obj.dimensions_m = random_dimensions(obj.kind, rng);
    obj.narrow_radius_m = 0;
    obj.apex_down = false;
    if (params.varied_cones && obj.kind == ShapeKind::cone) vary_cone(obj, rng);
    if (footprint_radius(obj) <= room) break;
  }
  obj.yaw_deg =
      lower.kind == ShapeKind::box ? lower.yaw_deg + uniform(rng, -25, 25) : uniform(rng, 0, 360);
  obj.color = kPalette[static_cast<std::size_t>(
      uniform_int(rng, 0, static_cast<int>(kPalette.size()) - 1))];
  const double f = footprint_radius(obj);
  if (f > room) {
    const double k =
        room * uniform(rng, 0.5, 1.0) / f;  // the horizontal sizes scaled; the height kept
    obj.dimensions_m[0] *= k;
    if (obj.kind == ShapeKind::box) obj.dimensions_m[1] *= k;
    if (obj.kind == ShapeKind::cone) obj.narrow_radius_m *= k;
  }
  const double largest = obj.kind == ShapeKind::box
                             ? *std::max_element(obj.dimensions_m.begin(), obj.dimensions_m.end())
                             : std::max(2 * obj.dimensions_m[0], obj.dimensions_m[1]);
  if (largest < kSmallest_m) return std::nullopt;
  const double slack = std::max(0.0, room - footprint_radius(obj));
  const double a = uniform(rng, 0, 2 * std::numbers::pi), r = slack * std::sqrt(uniform(rng, 0, 1));
  const double top = lower.center.z + half_height(lower);
  obj.center = {lower.center.x + r * std::cos(a), lower.center.y + r * std::sin(a),
                top + center_height(obj)};
  obj.support = lower.support;
  obj.velocity_m_per_frame = lower.velocity_m_per_frame;  // carried along with it
  obj.spin_deg_per_frame = lower.spin_deg_per_frame;
  if (uniform(rng, 0, 1) < params.dark_share) darken(obj, uniform(rng, 0.15, 0.35));
  return obj;
}

// stacked_share of the boxes and cylinders whole in view (not on a shelf board, whose
// clearance is tight) carry an object on their top, when it too is whole in view and
// overlaps no third object's image box beyond max_view_overlap. Drawn from its own
// stream and added last, so the scene is otherwise the one without stacks.
void add_stacked_objects(const SyntheticSceneParams& params, SyntheticScene& s) {
  if (params.stacked_share <= 0) return;
  std::mt19937_64 rng(mix_seed(params.seed, 0x57ac));
  const std::size_t before = s.objects.size();
  for (std::size_t k = 0; k < before; ++k) {
    const SyntheticObject& lower = s.objects[k];
    const bool on_board =
        lower.support > 0 && s.furniture[static_cast<std::size_t>(lower.support - 1)].role ==
                                 SyntheticBlock::Role::shelf;
    if (uniform(rng, 0, 1) >= params.stacked_share || lower.cut || on_board ||
        top_half_width(lower) <= 0)
      continue;
    std::optional<SyntheticObject> obj = object_on_top(params, lower, rng);
    if (!obj) continue;
    std::vector<PixelRect> others;
    for (std::size_t j = 0; j < s.objects.size(); ++j)
      if (j != k) others.push_back(object_rect(s, s.objects[j]));
    if (!whole_in_view(s, object_rect(s, *obj), others, params.max_view_overlap)) continue;
    obj->on_object = static_cast<int>(k);
    s.objects.push_back(std::move(*obj));
  }
}

// A C-shaped handle on the body's local +x side: two arms from inside its wall out to a
// grip, boxes 8-12 mm thick. `radius_at(z)`: the body's radius at height z over its
// centre; `height` its height.
void add_handle(SyntheticObject& o, double height, const std::function<double(double)>& radius_at,
                std::mt19937_64& rng) {
  constexpr double kIntoWall_m = 0.004;  // the arms start inside the wall: no seam
  const double reach = uniform(rng, 0.02, 0.03), thick = uniform(rng, 0.008, 0.012);
  const double width = uniform(rng, 0.01, 0.015), span = height * uniform(rng, 0.5, 0.7);
  const double mid = height * uniform(rng, 0.0, 0.1);
  const double top = mid + 0.5 * (span - thick), bottom = mid - 0.5 * (span - thick);
  const double outer = std::max(radius_at(top), radius_at(bottom)) + reach;
  for (double z : {top, bottom}) {
    const double inner = radius_at(z) - kIntoWall_m;
    o.details.push_back(
        {ShapeKind::box, {outer - inner, width, thick}, 0, {0.5 * (inner + outer), 0, z}});
  }
  o.details.push_back({ShapeKind::box, {thick, width, span}, 0, {outer - 0.5 * thick, 0, mid}});
}

// The handle's side turned away from the nearest object on the same support (a
// touching neighbour most of all), give or take 60 degrees.
double handle_yaw(const SyntheticScene& s, std::size_t k, std::mt19937_64& rng) {
  const SyntheticObject& o = s.objects[k];
  double nearest = 1e9, away_deg = uniform(rng, 0, 360);
  for (std::size_t j = 0; j < s.objects.size(); ++j) {
    const SyntheticObject& other = s.objects[j];
    if (j == k || other.support != o.support) continue;
    const double dx = o.center.x - other.center.x, dy = o.center.y - other.center.y;
    if (std::hypot(dx, dy) < nearest)
      nearest = std::hypot(dx, dy), away_deg = std::atan2(dy, dx) * 180 / std::numbers::pi;
  }
  return away_deg + uniform(rng, -60, 60);
}

// The body of an upright cylinder or cone made `height` tall, its foot where it was.
void set_body_height(SyntheticObject& o, double height) {
  const double base = o.center.z - 0.5 * o.dimensions_m[1];
  o.dimensions_m[1] = height;
  o.center.z = base + 0.5 * height;
}

// A cylinder made a bottle of the same height: a body of 55-75 % of it, a shoulder
// narrowing to the neck, the neck (2 cm at least: the body gives way) and a cap 3 mm
// wider.
void make_bottle(SyntheticObject& o, std::mt19937_64& rng) {
  constexpr double kLeastNeck_m = 0.02;
  const double r = o.dimensions_m[0], total = o.dimensions_m[1];
  const double drawn = total * uniform(rng, 0.55, 0.75),
               shoulder = total * uniform(rng, 0.06, 0.15);
  const double neck_r = std::min(uniform(rng, 0.011, 0.018), 0.5 * r),
               cap = uniform(rng, 0.015, 0.02);
  const double body = std::min(drawn, total - shoulder - cap - kLeastNeck_m);
  const double neck = total - body - shoulder - cap;
  set_body_height(o, body);
  const double top = 0.5 * body;
  o.details.push_back({ShapeKind::cone, {r, shoulder}, neck_r, {0, 0, top + 0.5 * shoulder}});
  o.details.push_back(
      {ShapeKind::cylinder, {neck_r, neck}, 0, {0, 0, top + shoulder + 0.5 * neck}});
  o.details.push_back(
      {ShapeKind::cylinder, {neck_r + 0.003, cap}, 0, {0, 0, top + shoulder + neck + 0.5 * cap}});
}

// everyday_share of the cylinders become mugs or bottles, of the cones narrowing down
// 5-14 cm tall cups with a handle, unless another object stands on them. Drawn from its
// own stream after the stacks, so the scene is otherwise the one without them.
void add_everyday_objects(const SyntheticSceneParams& params, SyntheticScene& s) {
  if (params.everyday_share <= 0) return;
  std::mt19937_64 rng(mix_seed(params.seed, 0xe7e1));
  for (std::size_t k = 0; k < s.objects.size(); ++k) {
    SyntheticObject& o = s.objects[k];
    const bool cup = o.kind == ShapeKind::cone && o.apex_down && o.dimensions_m[1] >= 0.05 &&
                     o.dimensions_m[1] <= 0.14;
    if ((o.kind != ShapeKind::cylinder && !cup) || uniform(rng, 0, 1) >= params.everyday_share ||
        o.lying)
      continue;
    const bool carries = std::any_of(
        s.objects.begin(), s.objects.end(),
        [&](const SyntheticObject& other) { return other.on_object == static_cast<int>(k); });
    if (carries) continue;
    const double r = o.dimensions_m[0], h = o.dimensions_m[1];
    if (cup) {
      const double narrow = o.narrow_radius_m;  // at the foot: the cone is apex down
      o.yaw_deg = handle_yaw(s, k, rng);
      add_handle(
          o, h, [=](double z) { return narrow + (r - narrow) * (z / h + 0.5); }, rng);
    } else if (uniform(rng, 0, 1) < 0.5 && h >= 0.15) {
      make_bottle(o, rng);
    } else {  // a mug (a cylinder too short for a bottle too)
      const double mug = uniform(rng, 0.07, 0.12);
      set_body_height(o, mug);
      o.yaw_deg = handle_yaw(s, k, rng);
      add_handle(
          o, mug, [=](double) { return r; }, rng);
    }
  }
}

// Whether a cylinder may be laid on its side: plain, standing on the table or a
// furniture top (not a shelf board, whose clearance is tight), whole in view, nothing
// on it, not on another, touching none and across no edge.
bool may_lie(const SyntheticScene& s, std::size_t k) {
  const SyntheticObject& o = s.objects[k];
  const auto index = static_cast<int>(k);
  const bool on_support_top =
      o.support == 0 ||
      (o.support > 0 &&
       s.furniture[static_cast<std::size_t>(o.support - 1)].role == SyntheticBlock::Role::support);
  const bool bound =
      std::any_of(s.objects.begin(), s.objects.end(), [&](const SyntheticObject& other) {
        return other.on_object == index || other.touching == index;
      });
  return o.kind == ShapeKind::cylinder && o.details.empty() && on_support_top && !o.cut &&
         o.touching < 0 && o.on_object < 0 && !o.overhang && !bound;
}

// Whether `lying`, replacing object k, stays on its support's top `kClear_m` from its
// edges, clear of every other object on it (their extents along the line between
// centres apart: both footprints are symmetric and convex), and in view.
bool lying_fits(const SyntheticSceneParams& params, const SyntheticScene& s, std::size_t k,
                const SyntheticObject& lying) {
  constexpr double kClear_m = 0.01;
  Vec3 top_center{0, 0, 0}, top_half{s.table_half_x_m, s.table_half_y_m, 0};
  if (lying.support > 0) {
    const SyntheticBlock& b = s.furniture[static_cast<std::size_t>(lying.support - 1)];
    top_center = b.center, top_half = b.size_m * 0.5;
  }
  const Vec3 rel = lying.center - top_center;
  if (std::abs(rel.x) + extent_along(lying, {1, 0, 0}) > top_half.x - kClear_m ||
      std::abs(rel.y) + extent_along(lying, {0, 1, 0}) > top_half.y - kClear_m)
    return false;
  std::vector<PixelRect> others;
  for (std::size_t j = 0; j < s.objects.size(); ++j) {
    if (j == k) continue;
    const SyntheticObject& other = s.objects[j];
    others.push_back(object_rect(s, other));
    if (other.support != lying.support) continue;
    const Vec3 between{other.center.x - lying.center.x, other.center.y - lying.center.y, 0};
    const double apart = norm(between);
    const Vec3 u = apart > 0 ? between * (1 / apart) : Vec3{1, 0, 0};
    if (apart < extent_along(lying, u) + extent_along(other, u) + kClear_m) return false;
  }
  return whole_in_view(s, object_rect(s, lying), others, params.max_view_overlap);
}

// lying_share of the cylinders that may lie (may_lie) rest on their side, on the spot
// they stood on, along the first of kYawDraws random yaws where they fit (lying_fits);
// else they stand. From a stream of its own, so the scene is otherwise the one without.
void add_lying_objects(const SyntheticSceneParams& params, SyntheticScene& s) {
  if (params.lying_share <= 0) return;
  constexpr int kYawDraws = 8;
  std::mt19937_64 rng(mix_seed(params.seed, 0x1a1d));
  for (std::size_t k = 0; k < s.objects.size(); ++k) {
    if (s.objects[k].kind != ShapeKind::cylinder || uniform(rng, 0, 1) >= params.lying_share ||
        !may_lie(s, k))
      continue;
    SyntheticObject lying = s.objects[k];
    lying.lying = true;
    lying.center.z += center_height(lying) - center_height(s.objects[k]);
    for (int draw = 0; draw < kYawDraws; ++draw) {
      lying.yaw_deg = uniform(rng, 0, 360);
      if (!lying_fits(params, s, k, lying)) continue;
      s.objects[k] = lying;
      break;
    }
  }
}

// The room's extra elements (back_chair_chance, cabinet_chance, pole_chance), drawn last
// from a stream of their own so the scene's other draws stay; appended to the furniture
// after every other block (the objects' support indices stay).
void add_room_extras(const SyntheticSceneParams& params, SyntheticScene& s) {
  std::mt19937_64 rng(mix_seed(params.seed, 0xe7a5));
  const bool chair = uniform(rng, 0, 1) < params.back_chair_chance;
  const bool cabinet = uniform(rng, 0, 1) < params.cabinet_chance;
  const bool pole = uniform(rng, 0, 1) < params.pole_chance;
  if (chair) add_back_chair(s, rng);
  if (cabinet) add_cabinet(s, rng);
  if (pole) add_pole(s, rng);
}

std::optional<SyntheticScene> try_layout(const SyntheticSceneParams& params, std::mt19937_64& rng,
                                         int& placed_count) {
  SyntheticScene s;
  s.seed = params.seed;
  s.camera = params.camera;
  s.table_half_x_m = uniform(rng, 0.6, 0.8);
  s.table_half_y_m = uniform(rng, 0.35, 0.5);
  s.floor_depth_m = uniform(rng, params.table_height_min_m, params.table_height_max_m);
  s.wall_y_m = s.table_half_y_m + uniform(rng, 0.2, 0.8);
  s.camera_tilt_deg = uniform(rng, params.camera_tilt_min_deg, params.camera_tilt_max_deg);
  if (params.camera_roll_max_deg > 0)
    s.camera_roll_deg = uniform(rng, -params.camera_roll_max_deg, params.camera_roll_max_deg);
  const double distance = uniform(rng, params.camera_distance_min_m, params.camera_distance_max_m);
  const Vec3 aim{uniform(rng, -0.1, 0.1), uniform(rng, -0.05, 0.05), 0};
  s.camera_position = aim - camera_axes(s.camera_tilt_deg).z * distance;
  s.camera_position.z = std::max(s.camera_position.z, params.min_camera_height_m);

  // Furniture: legs, a second support on one side, tall furniture on the other.
  if (params.table_legs) {
    const double leg = 0.05, inset = 0.06;
    const double height = s.floor_depth_m - s.table_thickness_m;
    for (double sx : {-1.0, 1.0})
      for (double sy : {-1.0, 1.0})
        s.furniture.push_back({{sx * (s.table_half_x_m - inset), sy * (s.table_half_y_m - inset),
                                -s.table_thickness_m - height * 0.5},
                               {leg, leg, height},
                               SyntheticBlock::Role::leg});
  }
  const double side = uniform_side(params, rng);
  if (params.side_support_objects > 0) {
    const Vec3 size{uniform(rng, 0.35, 0.5), uniform(rng, 0.35, 0.5), uniform(rng, 0.35, 0.55)};
    const double x = side * (s.table_half_x_m + uniform(rng, 0.15, 0.4) + size.x * 0.5);
    s.furniture.push_back({{x, uniform(rng, -0.2, 0.1), -s.floor_depth_m + size.z * 0.5},
                           size,
                           SyntheticBlock::Role::support});
  }
  if (params.tall_furniture) {
    const Vec3 size{uniform(rng, 0.4, 0.6), uniform(rng, 0.35, 0.5), uniform(rng, 1.6, 2.0)};
    const double x = -side * (s.table_half_x_m + uniform(rng, 0.1, 0.4) + size.x * 0.5);
    s.furniture.push_back({{x, uniform(rng, -0.2, 0.1), -s.floor_depth_m + size.z * 0.5},
                           size,
                           SyntheticBlock::Role::tall});
  }

  add_room_furniture(params, s, rng);

  auto palette = kPalette;
  std::shuffle(palette.begin(), palette.end(), rng);

  std::vector<PixelRect> rects;
  const double margin_px = 8;
  const double width = s.camera.width, height = s.camera.height;
  auto clip = [&](PixelRect r) {
    return PixelRect{std::max(r.u0, 0.0), std::max(r.v0, 0.0), std::min(r.u1, width - 1),
                     std::min(r.v1, height - 1)};
  };
  // Objects on the table first, then those on the second support (skipped when it
  // has no room for them in view).
  int support_index = 0;
  for (std::size_t k = 0; k < s.furniture.size(); ++k)
    if (s.furniture[k].role == SyntheticBlock::Role::support) support_index = static_cast<int>(k) + 1;
  const int total = params.object_count + (support_index > 0 ? params.side_support_objects : 0);
  for (int i = 0; i < total; ++i) {
    const bool on_side = i >= params.object_count;
    SyntheticObject obj;
    obj.kind = params.kinds[std::uniform_int_distribution<std::size_t>(0, params.kinds.size() - 1)(rng)];
    obj.dimensions_m = random_dimensions(obj.kind, rng);
    if (params.varied_cones && obj.kind == ShapeKind::cone) vary_cone(obj, rng);
    obj.yaw_deg = uniform(rng, 0, 360);
    obj.color = palette[static_cast<std::size_t>(i) % palette.size()];
    const double speed = uniform(rng, 0, params.max_speed_m_per_frame);
    const double heading = uniform(rng, 0, 2 * std::numbers::pi);
    obj.velocity_m_per_frame = {speed * std::cos(heading), speed * std::sin(heading), 0};
    obj.spin_deg_per_frame = uniform(rng, -params.max_spin_deg_per_frame, params.max_spin_deg_per_frame);
    if (params.cut_share > 0 && !on_side) obj.cut = uniform(rng, 0, 1) < params.cut_share;
    // Touching the object placed before it, or across a table edge (table objects only).
    const bool after_table_object = !s.objects.empty() && s.objects.back().support == 0 &&
                                    !s.objects.back().cut;
    if (params.touching_share > 0 && !on_side && !obj.cut && after_table_object &&
        uniform(rng, 0, 1) < params.touching_share)
      obj.touching = static_cast<int>(s.objects.size()) - 1;
    if (params.overhang_share > 0 && !on_side && !obj.cut && obj.touching < 0)
      obj.overhang = uniform(rng, 0, 1) < params.overhang_share;
    const double f = footprint_radius(obj);
    // The support's top rectangle and height in the table frame.
    double cx = aim.x, cy = aim.y, hx = s.table_half_x_m, hy = s.table_half_y_m, top = 0;
    double spread_x = obj.cut ? 0.7 : 0.4, spread_y = obj.cut ? 0.45 : 0.3;
    if (on_side) {
      const SyntheticBlock& b = s.furniture[static_cast<std::size_t>(support_index - 1)];
      cx = b.center.x, cy = b.center.y, hx = b.size_m.x * 0.5, hy = b.size_m.y * 0.5;
      top = b.center.z + b.size_m.z * 0.5;
      spread_x = hx, spread_y = hy;
      obj.support = support_index;
    }
    bool placed = false;
    // An object meant to be cut that finds no place across the border is placed whole.
    for (int attempt = 0; attempt < 2 * kPlacementAttempts && !placed; ++attempt) {
      if (attempt == kPlacementAttempts) {
        if (!obj.cut) break;
        obj.cut = false;
        spread_x = 0.4, spread_y = 0.3;
      }
      // Placed as drawn, or touching / across an edge; a feature that finds no place in
      // half the attempts is dropped (the object placed as any other).
      if (attempt == kPlacementAttempts / 2) obj.touching = -1, obj.overhang = false;
      bool free_placed = true;
      if (obj.touching >= 0) {
        free_placed = false;
        place_touching(obj, s.objects[static_cast<std::size_t>(obj.touching)], rng);
      } else if (obj.overhang) {
        free_placed = false;
        if (!place_overhanging(obj, s, rng)) continue;
      } else {
        obj.center = {cx + uniform(rng, -spread_x, spread_x), cy + uniform(rng, -spread_y, spread_y),
                      top + center_height(obj)};
      }
      const double ox = on_side ? obj.center.x - cx : obj.center.x;
      const double oy = on_side ? obj.center.y - cy : obj.center.y;
      if (free_placed && (std::abs(ox) + f + 0.02 > hx || std::abs(oy) + f + 0.02 > hy)) continue;
      if (obj.touching >= 0 && (std::abs(ox) + extent_along(obj, {1, 0, 0}) + 0.02 > hx ||
                                std::abs(oy) + extent_along(obj, {0, 1, 0}) + 0.02 > hy))
        continue;
      bool clear = true;
      for (std::size_t k = 0; k < s.objects.size(); ++k) {
        if (static_cast<int>(k) == obj.touching) continue;  // meant to touch it
        const SyntheticObject& other = s.objects[k];
        const double gap = std::hypot(obj.center.x - other.center.x, obj.center.y - other.center.y);
        if (gap < f + footprint_radius(other) + 0.02) clear = false;
      }
      if (!clear) continue;
      PixelRect r = object_rect(s, obj);
      const bool inside = r.u0 >= margin_px && r.v0 >= margin_px &&
                          r.u1 <= width - 1 - margin_px && r.v1 <= height - 1 - margin_px;
      if (obj.cut) {
        // Across the border, with a third of its image box or more inside.
        const PixelRect c = clip(r);
        if (inside || c.empty() || c.area() < r.area() / 3) continue;
        r = c;
      } else if (!inside) {
        continue;
      }
      for (const PixelRect& other : rects)
        if (overlap_area(r, other) > params.max_view_overlap * std::min(r.area(), other.area()))
          clear = false;
      if (!clear) continue;
      rects.push_back(r);
      placed = true;
    }
    if (!placed && on_side) continue;
    if (!placed) {
      placed_count = i;
      return std::nullopt;
    }
    s.objects.push_back(std::move(obj));
  }
  placed_count = params.object_count;
  add_floor_objects(params, s, rng, rects);
  add_shelf_objects(params, s, rects);
  // Dark objects last, so the layout is the same with or without them.
  if (params.dark_share > 0)
    for (SyntheticObject& o : s.objects)
      if (uniform(rng, 0, 1) < params.dark_share) darken(o, uniform(rng, 0.15, 0.35));
  add_lying_objects(params, s);
  add_room_extras(params, s);
  add_stacked_objects(params, s);
  add_everyday_objects(params, s);

  if (params.occluder) {
    // Crosses the line of sight to the aim point, a bit under half-way from the camera.
    const Vec3 on_sight = s.camera_position + camera_axes(s.camera_tilt_deg).z * (0.45 * distance);
    SyntheticOccluder occ;
    occ.center = {on_sight.x - 0.35, on_sight.y, on_sight.z + 0.1};
    occ.velocity_m_per_frame = {params.occluder_speed_m_per_frame, 0, 0};
    s.occluder = occ;
  }
  return s;
}

}  // namespace

SyntheticSceneParams world_scene_params(std::uint64_t seed) {
  SyntheticSceneParams p;
  p.seed = seed;
  p.camera_distance_min_m = 0.5;
  p.camera_distance_max_m = 3.0;
  p.camera_tilt_min_deg = 0;
  p.camera_tilt_max_deg = 60;
  p.table_legs = true;
  p.side_support_objects = 2;
  p.tall_furniture = true;
  p.varied_cones = true;
  p.cut_share = 0.25;
  return p;
}

SyntheticSceneParams room_scene_params(std::uint64_t seed) {
  SyntheticSceneParams p = world_scene_params(seed);
  p.table_height_min_m = 0.4;
  p.table_height_max_m = 1.1;
  p.camera_roll_max_deg = 5;
  p.chair_chance = 0.5;
  p.shelf_chance = 0.5;
  p.floor_objects = 2;
  p.touching_share = 0.25;
  p.overhang_share = 0.15;
  p.dark_share = 0.15;
  p.shelf_objects = 2;
  p.back_chair_chance = 1.0 / 3;
  p.cabinet_chance = 0.5;
  p.pole_chance = 0.2;
  return p;
}

SyntheticObject resting_object(ShapeKind kind, std::vector<double> dimensions_m, double x_m,
                               double y_m, double yaw_deg) {
  SyntheticObject o;
  o.kind = kind;
  o.dimensions_m = std::move(dimensions_m);
  o.yaw_deg = yaw_deg;
  o.center = {x_m, y_m, center_height(o)};
  return o;
}

SyntheticScene scene_at_frame(const SyntheticScene& scene, int frame_index) {
  SyntheticScene s = scene;
  const double k = frame_index;
  for (SyntheticObject& o : s.objects) {
    o.center = o.center + o.velocity_m_per_frame * k;
    o.yaw_deg = std::fmod(o.yaw_deg + o.spin_deg_per_frame * k, 360.0);
  }
  if (s.occluder) s.occluder->center = s.occluder->center + s.occluder->velocity_m_per_frame * k;
  return s;
}

SyntheticFrame render_scene(const SyntheticScene& base, const SensorNoiseParams& noise,
                            int frame_index) {
  const SyntheticScene s = scene_at_frame(base, frame_index);
  const CameraIntrinsics& cam = s.camera;
  const CameraAxes axes = camera_axes(s.camera_tilt_deg, s.camera_roll_deg);
  synthetic_pixels::Draws draws{std::mt19937_64(mix_seed(s.seed, static_cast<std::uint64_t>(frame_index)))};
  const double jitter = noise.enabled ? noise.lateral_sigma_px : 0.0;

  // Image rectangles (grown by the jitter) where each object can appear.
  std::vector<PixelRect> rects;
  for (const SyntheticObject& o : s.objects) {
    PixelRect r = object_rect(s, o);
    const double grow = 2 + 5 * jitter;
    rects.push_back({r.u0 - grow, r.v0 - grow, r.u1 + grow, r.v1 + grow});
  }
  PixelRect occluder_rect;
  if (s.occluder) {
    occluder_rect = project_box(s, s.occluder->center, s.occluder->size_m * 0.5);
    const double grow = 2 + 5 * jitter;
    occluder_rect = {occluder_rect.u0 - grow, occluder_rect.v0 - grow, occluder_rect.u1 + grow,
                     occluder_rect.v1 + grow};
  }

  // Pass 1: the exact surface each (jittered) pixel ray hits.
  const Vec3 table_half{s.table_half_x_m, s.table_half_y_m, s.table_thickness_m * 0.5};
  const Vec3 table_center{0, 0, -s.table_thickness_m * 0.5};
  const auto hits = synthetic_pixels::cast_pixels(
      cam, jitter, draws, [&](int u, int v, double ray_x, double ray_y) {
        // Camera ray with unit z, so the ray parameter t is the camera depth.
        const Vec3 dir = axes.x * ray_x + axes.y * ray_y + axes.z;
        const Vec3 o = s.camera_position;
        LocalHit best;
        int label = kLabelNothing;
        auto take = [&](const LocalHit& hit, int l) {
          if (hit.t < best.t) best = hit, label = l;
        };
        take(hit_box(o - table_center, dir, table_half), kLabelTable);
        if (dir.z < 0) take({(-s.floor_depth_m - o.z) / dir.z, {0, 0, 1}}, kLabelFloor);
        if (dir.y > 0) take({(s.wall_y_m - o.y) / dir.y, {0, -1, 0}}, kLabelWall);
        for (const SyntheticBlock& b : s.furniture)
          take(hit_box(o - b.center, dir, b.size_m * 0.5), block_label(b.role));
        for (std::size_t i = 0; i < s.objects.size(); ++i) {
          const PixelRect& r = rects[i];
          if (u < r.u0 || u > r.u1 || v < r.v0 || v > r.v1) continue;
          take(hit_object(s.objects[i], o, dir), static_cast<int>(i));
        }
        if (s.occluder && u >= occluder_rect.u0 && u <= occluder_rect.u1 &&
            v >= occluder_rect.v0 && v <= occluder_rect.v1)
          take(hit_box(o - s.occluder->center, dir, s.occluder->size_m * 0.5), kLabelOccluder);
        if (label == kLabelNothing || !(best.t > kMinT) || best.t == kInf) return synthetic_pixels::SurfaceHit{};
        return synthetic_pixels::SurfaceHit{best.t, std::abs(dot(best.normal, normalized(dir))), label};
      });

  // Pass 2: sensor model per pixel, then colour.
  SyntheticFrame out;
  out.frame.index = frame_index;
  out.frame.timestamp_s = frame_index / kFrameRateHz;
  synthetic_pixels::sense_pixels(
      hits, cam, noise, draws,
      [&](int label) -> synthetic_pixels::Rgb {
        if (label >= 0) return s.objects[static_cast<std::size_t>(label)].color;
        if (label == kLabelTable) return {165, 120, 80};
        if (label == kLabelWall) return {205, 200, 185};
        if (label == kLabelOccluder) return {205, 155, 125};
        if (label == kLabelLeg) return {120, 85, 55};
        if (label == kLabelFurniture) return {150, 150, 160};
        if (label == kLabelChair) return {95, 60, 40};
        if (label == kLabelShelf) return {215, 205, 180};
        if (label == kLabelBackChair) return {70, 70, 80};
        if (label == kLabelCabinet) return {190, 185, 175};
        if (label == kLabelPole) return {135, 135, 140};
        return {90, 90, 100};  // floor
      },
      out.frame, out.labels, dark_return(s));
  out.truth = ground_truth(s, &out.frame, &out.labels);
  // Nearer than the sensor's range, a surface returns nothing: an object running into
  // that blind zone is cut as at the image's border.
  for (const synthetic_pixels::PixelHit& px : hits)
    if (px.surface.label >= 0 && px.surface.depth < noise.min_range_m)
      out.truth.objects[static_cast<std::size_t>(px.surface.label)].partial = true;
  return out;
}

PhysicalScene ground_truth(const SyntheticScene& scene, const Frame* frame,
                           const std::vector<int>* labels) {
  PhysicalScene truth;
  Plane table;
  table.normal = table_to_camera_direction(scene, kUp);
  table.d = -dot(table.normal, table_to_camera_point(scene, {0, 0, 0}));
  truth.support = table;
  // Every support: the table, the floor, each furniture top that holds objects.
  auto plane_at = [&](double z) {
    return Plane{table.normal, -dot(table.normal, table_to_camera_point(scene, {0, 0, z}))};
  };
  truth.supports.push_back({"table", table, 0});
  truth.supports.push_back({"floor", plane_at(-scene.floor_depth_m), 0});
  std::vector<std::string> support_ids(scene.furniture.size() + 1, "table");
  for (std::size_t k = 0; k < scene.furniture.size(); ++k) {
    const SyntheticBlock& b = scene.furniture[k];
    const bool holds = std::any_of(scene.objects.begin(), scene.objects.end(), [&](const SyntheticObject& o) {
      return o.support == static_cast<int>(k) + 1;
    });
    if (b.role != SyntheticBlock::Role::support && !(b.role == SyntheticBlock::Role::shelf && holds)) continue;
    support_ids[k + 1] = "f" + std::to_string(k + 1);
    truth.supports.push_back({support_ids[k + 1], plane_at(b.center.z + b.size_m.z * 0.5), 0});
  }

  std::vector<int> counts(scene.objects.size(), 0);
  // Cut by the image border: some ray of the outermost rows or columns hits it (its
  // image box may cross the border while its silhouette does not: a torus's corner).
  std::vector<char> at_edge(scene.objects.size(), 0);
  const bool labelled = frame && labels && labels->size() == frame->points.size();
  if (labelled) {
    const std::size_t w = static_cast<std::size_t>(std::max(1, frame->width));
    const std::size_t h = labels->size() / w;
    for (std::size_t i = 0; i < labels->size(); ++i) {
      const int l = (*labels)[i];
      if (l < 0 || static_cast<std::size_t>(l) >= counts.size()) continue;
      if (std::isfinite(frame->points[i].z)) ++counts[static_cast<std::size_t>(l)];
      const std::size_t x = i % w, y = i / w;
      if (x == 0 || y == 0 || x + 1 == w || y + 1 == h) at_edge[static_cast<std::size_t>(l)] = 1;
    }
  }
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SyntheticObject& o = scene.objects[i];
    PhysicalPrimitive prim;
    prim.kind = o.kind;
    prim.dimensions_m = o.dimensions_m;
    prim.center = table_to_camera_point(scene, o.center);
    const Vec3 axis = o.lying       ? rotate_z({1, 0, 0}, deg_to_rad(o.yaw_deg))
                      : o.apex_down ? kUp * -1.0
                                    : kUp;
    prim.axis = table_to_camera_direction(scene, axis);
    prim.narrow_radius_m = o.kind == ShapeKind::cone ? o.narrow_radius_m : 0.0;
    prim.fit = 1.0;
    PhysicalObject obj;
    obj.support_id = o.support < 0 ? "floor" : support_ids[static_cast<std::size_t>(o.support)];
    obj.partial = labelled ? at_edge[i] != 0 : o.cut;
    obj.id = "o";  // not "o" + ...: GCC 12 warns falsely (-Wrestrict, bug 105329)
    obj.id += std::to_string(i + 1);
    if (o.on_object >= 0) {
      obj.on_object = "o";
      obj.on_object += std::to_string(o.on_object + 1);
    }
    obj.primitives.push_back(prim);
    obj.point_count = counts[i];
    obj.fit = 1.0;
    truth.objects.push_back(std::move(obj));
  }
  return truth;
}

}  // namespace annex
