// Triangle meshes of the primitives, for drawing haptic models and scanned props.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "annex/runtime/renderer.h"

namespace annex {
namespace {

constexpr double kPi = std::numbers::pi;

void add_vertex(MeshData& m, Vec3 p, Vec3 n) {
  m.positions.insert(m.positions.end(),
                     {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
  n = normalized(n);
  m.normals.insert(m.normals.end(),
                   {static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z)});
  m.colors.insert(m.colors.end(), {kDefaultMeshGrey[0], kDefaultMeshGrey[1], kDefaultMeshGrey[2]});
}

std::uint32_t next_index(const MeshData& m) {
  return static_cast<std::uint32_t>(m.vertex_count());
}

void add_quad_grid(MeshData& m, std::uint32_t base, int rows, int cols) {
  // (rows + 1) x (cols + 1) vertices, row-major.
  for (int i = 0; i < rows; ++i)
    for (int k = 0; k < cols; ++k) {
      const std::uint32_t a = base + i * (cols + 1) + k, b = a + 1;
      const std::uint32_t c = a + (cols + 1), d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
}

// One ring of a surface of revolution: radius, height, and the normal's radial and
// axial parts.
struct Ring {
  double radius, z, n_radial, n_z;
};

void add_lathe(MeshData& m, const std::vector<Ring>& rings, int segments) {
  const std::uint32_t base = next_index(m);
  for (const Ring& r : rings)
    for (int k = 0; k <= segments; ++k) {  // the seam is duplicated so normals stay smooth
      const double a = 2 * kPi * k / segments;
      const double c = std::cos(a), s = std::sin(a);
      add_vertex(m, {r.radius * c, r.radius * s, r.z}, {r.n_radial * c, r.n_radial * s, r.n_z});
    }
  add_quad_grid(m, base, static_cast<int>(rings.size()) - 1, segments);
}

void add_disc(MeshData& m, double radius, double z, bool up, int segments) {
  const std::uint32_t centre = next_index(m);
  const Vec3 n{0, 0, up ? 1.0 : -1.0};
  add_vertex(m, {0, 0, z}, n);
  for (int k = 0; k < segments; ++k) {
    const double a = 2 * kPi * k / segments;
    add_vertex(m, {radius * std::cos(a), radius * std::sin(a), z}, n);
  }
  for (int k = 0; k < segments; ++k) {
    const std::uint32_t a = centre + 1 + k, b = centre + 1 + (k + 1) % segments;
    if (up)
      m.indices.insert(m.indices.end(), {centre, a, b});
    else
      m.indices.insert(m.indices.end(), {centre, b, a});
  }
}

void add_box(MeshData& m, Vec3 half) {
  // Each face: its normal and two in-plane axes, so the four corners are n +- u +- v.
  const Vec3 faces[6][3] = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                            {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
                            {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}}};
  const auto scaled = [&](Vec3 v) { return Vec3{v.x * half.x, v.y * half.y, v.z * half.z}; };
  for (const auto& f : faces) {
    const std::uint32_t base = next_index(m);
    for (int j = 0; j <= 1; ++j)
      for (int i = 0; i <= 1; ++i)
        add_vertex(m, scaled(f[0] + f[1] * (i ? 1.0 : -1.0) + f[2] * (j ? 1.0 : -1.0)), f[0]);
    m.indices.insert(m.indices.end(), {base, base + 1, base + 3, base, base + 3, base + 2});
  }
}

}  // namespace

MeshData primitive_mesh(ShapeKind kind, const std::vector<double>& d, int segments) {
  if (static_cast<int>(d.size()) != dimension_count(kind))
    throw std::invalid_argument("primitive_mesh: " + std::to_string(d.size()) +
                                " dimensions given for a " + std::string(shape_name(kind)));
  segments = std::max(segments, 3);
  MeshData m;
  switch (kind) {
    case ShapeKind::sphere: {
      const int stacks = std::max(2, segments / 2);
      std::vector<Ring> rings;
      for (int i = 0; i <= stacks; ++i) {
        const double t = kPi * i / stacks;
        rings.push_back({d[0] * std::sin(t), -d[0] * std::cos(t), std::sin(t), -std::cos(t)});
      }
      add_lathe(m, rings, segments);
      break;
    }
    case ShapeKind::cylinder: {
      const double r = d[0], h = d[1] / 2;
      add_lathe(m, {{r, -h, 1, 0}, {r, h, 1, 0}}, segments);
      add_disc(m, r, -h, false, segments);
      add_disc(m, r, h, true, segments);
      break;
    }
    case ShapeKind::cone: {
      const double r = d[0], h = d[1];
      const Vec3 n = normalized(Vec3{h, 0, r});  // the side's normal in the (radial, z) plane
      add_lathe(m, {{r, -h / 2, n.x, n.z}, {0, h / 2, n.x, n.z}}, segments);
      add_disc(m, r, -h / 2, false, segments);
      break;
    }
    case ShapeKind::torus: {
      const double major = d[0], minor = d[1];
      const int tube = std::max(3, segments / 2);
      const std::uint32_t base = next_index(m);
      for (int j = 0; j <= tube; ++j) {
        const double v = 2 * kPi * j / tube;
        for (int k = 0; k <= segments; ++k) {
          const double u = 2 * kPi * k / segments;
          const Vec3 n{std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v)};
          add_vertex(m, Vec3{major * std::cos(u), major * std::sin(u), 0} + n * minor, n);
        }
      }
      add_quad_grid(m, base, tube, segments);
      break;
    }
    case ShapeKind::box:
      add_box(m, {d[0] / 2, d[1] / 2, d[2] / 2});
      break;
    case ShapeKind::plane:  // a 2 mm thick sheet, so it shades from both sides
      add_box(m, {d[0] / 2, d[1] / 2, 0.001});
      break;
  }
  update_bounds(m);
  return m;
}

Affine world_from_physical(const PhysicalPrimitive& p) {
  if (p.kind == ShapeKind::plane) return affine_from_pose(Pose{p.center, plane_frame(p, false)});
  return affine_from_pose(Pose{p.center, rotation_from_z(p.axis)});
}

}  // namespace annex
