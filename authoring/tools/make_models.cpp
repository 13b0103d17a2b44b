// annex-make-models: writes the sample visual models of samples/models (OBJ + MTL)
// from lathe and extrude generators, so the samples are the project's own work.
//   annex-make-models OUT_DIR                 all six samples
//   annex-make-models --dense N OUT.obj       a lathed vase of about N triangles (benchmarks)
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace {

constexpr double kPi = 3.14159265358979323846;

struct V3 {
  double x = 0, y = 0, z = 0;
};
V3 operator+(V3 a, V3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
V3 operator-(V3 a, V3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
V3 operator*(V3 a, double s) {
  return {a.x * s, a.y * s, a.z * s};
}
V3 unit(V3 a) {
  const double n = std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
  return n > 0 ? a * (1 / n) : V3{0, 1, 0};
}

struct Material {
  std::string name;
  double r, g, b;
  double shininess = 32;
};

struct Part {
  std::string material;
  std::vector<V3> positions, normals;
  std::vector<int> tris;  // 0-based within the part
};

struct Model {
  std::vector<Material> materials;
  std::vector<Part> parts;
  Part& part(const std::string& material) {
    parts.push_back({material, {}, {}, {}});
    return parts.back();
  }
};

// A profile point (radius, height) of a solid of revolution about +Y.
struct RY {
  double r, y;
};

// Revolves a profile; a point repeated twice makes a sharp crease there.
void lathe(Part& part, const std::vector<RY>& profile, int segments) {
  const int n = static_cast<int>(profile.size());
  auto edge_normal = [&](int a, int b, RY& out) {
    const double dr = profile[b].r - profile[a].r, dy = profile[b].y - profile[a].y;
    const double len = std::hypot(dr, dy);
    if (len < 1e-12) return false;
    out = {dy / len, -dr / len};
    return true;
  };
  const int base = static_cast<int>(part.positions.size());
  for (int i = 0; i < n; ++i) {
    RY nrm{0, 0}, e{0, 0};
    if (i > 0 && edge_normal(i - 1, i, e)) nrm = {nrm.r + e.r, nrm.y + e.y};
    if (i + 1 < n && edge_normal(i, i + 1, e)) nrm = {nrm.r + e.r, nrm.y + e.y};
    const double len = std::hypot(nrm.r, nrm.y);
    if (len > 0) nrm = {nrm.r / len, nrm.y / len};
    for (int j = 0; j <= segments; ++j) {
      const double t = 2 * kPi * j / segments;
      const double c = std::cos(t), s = std::sin(t);
      part.positions.push_back({profile[i].r * c, profile[i].y, profile[i].r * s});
      part.normals.push_back(unit({nrm.r * c, nrm.y, nrm.r * s}));
    }
  }
  const int ring = segments + 1;
  for (int i = 0; i + 1 < n; ++i) {
    if (std::hypot(profile[i + 1].r - profile[i].r, profile[i + 1].y - profile[i].y) < 1e-12)
      continue;  // crease: no faces between the two copies
    for (int j = 0; j < segments; ++j) {
      const int a = base + i * ring + j, b = a + 1, c = a + ring, d = c + 1;
      // Counter-clockwise seen from outside (theta runs from +X towards +Z).
      part.tris.insert(part.tris.end(), {a, b, c, b, d, c});
    }
  }
}

// Smooth transition from (r0, y0) to (r1, y1), ends excluded from the start.
void ease(std::vector<RY>& p, RY from, RY to, int steps) {
  for (int i = 1; i <= steps; ++i) {
    const double t = static_cast<double>(i) / steps;
    const double s = t * t * (3 - 2 * t);
    p.push_back({from.r + (to.r - from.r) * s, from.y + (to.y - from.y) * t});
  }
}

// Quarter-circle fillet around centre (cr, cy) of radius rad from angle a0 to a1 (degrees).
void arc(std::vector<RY>& p, double cr, double cy, double rad, double a0, double a1, int steps) {
  for (int i = 0; i <= steps; ++i) {
    const double a = (a0 + (a1 - a0) * i / steps) * kPi / 180;
    p.push_back({cr + rad * std::cos(a), cy + rad * std::sin(a)});
  }
}

// Extrudes a closed convex-ish outline in the XY plane from z0 to z1, with caps.
void extrude(Part& part, const std::vector<V3>& outline, double z0, double z1, bool smooth) {
  const int n = static_cast<int>(outline.size());
  auto side_normal = [&](int a, int b) {
    const V3 d = outline[(b + n) % n] - outline[(a + n) % n];
    return unit({d.y, -d.x, 0});
  };
  // Sides.
  for (int i = 0; i < n; ++i) {
    const int base = static_cast<int>(part.positions.size());
    const V3 p0 = outline[i], p1 = outline[(i + 1) % n];
    V3 n0 = side_normal(i, i + 1), n1 = n0;
    if (smooth) {
      n0 = unit(side_normal(i - 1, i) + side_normal(i, i + 1));
      n1 = unit(side_normal(i, i + 1) + side_normal(i + 1, i + 2));
    }
    part.positions.insert(part.positions.end(),
                          {{p0.x, p0.y, z0}, {p1.x, p1.y, z0}, {p0.x, p0.y, z1}, {p1.x, p1.y, z1}});
    part.normals.insert(part.normals.end(), {n0, n1, n0, n1});
    part.tris.insert(part.tris.end(), {base, base + 1, base + 2, base + 1, base + 3, base + 2});
  }
  // Caps: fans around the centroid.
  V3 c;
  for (const V3& p : outline) c = c + p;
  c = c * (1.0 / n);
  for (int cap = 0; cap < 2; ++cap) {
    const double z = cap == 0 ? z0 : z1;
    const V3 nrm{0, 0, cap == 0 ? -1.0 : 1.0};
    const int base = static_cast<int>(part.positions.size());
    part.positions.push_back({c.x, c.y, z});
    part.normals.push_back(nrm);
    for (const V3& p : outline) {
      part.positions.push_back({p.x, p.y, z});
      part.normals.push_back(nrm);
    }
    for (int i = 0; i < n; ++i) {
      const int a = base + 1 + i, b = base + 1 + (i + 1) % n;
      if (cap == 0)
        part.tris.insert(part.tris.end(), {base, b, a});
      else
        part.tris.insert(part.tris.end(), {base, a, b});
    }
  }
}

// A tube of radius `tube` swept along a circular arc in the XY plane.
void swept_arc(Part& part, V3 center, double radius, double tube, double a0_deg, double a1_deg,
               int steps, int sides) {
  const int base = static_cast<int>(part.positions.size());
  for (int i = 0; i <= steps; ++i) {
    const double a = (a0_deg + (a1_deg - a0_deg) * i / steps) * kPi / 180;
    const V3 dir{std::cos(a), std::sin(a), 0};
    const V3 spine = center + dir * radius;
    for (int j = 0; j <= sides; ++j) {
      const double b = 2 * kPi * j / sides;
      const V3 n = unit(dir * std::cos(b) + V3{0, 0, 1} * std::sin(b));
      part.positions.push_back(spine + n * tube);
      part.normals.push_back(n);
    }
  }
  const int ring = sides + 1;
  for (int i = 0; i < steps; ++i)
    for (int j = 0; j < sides; ++j) {
      const int a = base + i * ring + j, b = a + 1, c = a + ring, d = c + 1;
      part.tris.insert(part.tris.end(), {a, c, b, b, c, d});
    }
}

std::vector<V3> ellipse(double rx, double ry, V3 c, int n) {
  std::vector<V3> out;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * kPi * i / n;
    out.push_back({c.x + rx * std::cos(t), c.y + ry * std::sin(t), 0});
  }
  return out;
}

std::vector<V3> rounded_rect(double x0, double y0, double x1, double y1, double rad, int steps) {
  std::vector<V3> out;
  const V3 corners[4] = {
      {x1 - rad, y0 + rad}, {x1 - rad, y1 - rad}, {x0 + rad, y1 - rad}, {x0 + rad, y0 + rad}};
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i <= steps; ++i) {
      const double a = (-90 + 90 * k + 90.0 * i / steps) * kPi / 180;
      out.push_back({corners[k].x + rad * std::cos(a), corners[k].y + rad * std::sin(a), 0});
    }
  return out;
}

// ---- the six samples (metres, Y up, resting on y = 0) ----

Model champagne_bottle() {
  Model m;
  m.materials = {{"glass", 0.08, 0.30, 0.14, 90},
                 {"foil", 0.85, 0.68, 0.25, 60},
                 {"label", 0.93, 0.89, 0.78, 8}};
  // Punted base: the centre is pushed up, the rim rests on y = 0.
  std::vector<RY> glass{{0, 0.018}, {0.025, 0.006}, {0.034, 0.0}};
  arc(glass, 0.039, 0.006, 0.006, -90, 0, 6);
  glass.push_back({0.045, 0.19});
  ease(glass, {0.045, 0.19}, {0.0155, 0.272}, 14);
  glass.push_back({0.0150, 0.30});
  glass.push_back({0, 0.30});
  lathe(m.part("glass"), glass, 72);
  std::vector<RY> foil{{0.0196, 0.245}};
  ease(foil, {0.0196, 0.245}, {0.0160, 0.272}, 6);
  foil.push_back({0.0158, 0.298});
  arc(foil, 0.0148, 0.298, 0.001, 0, 90, 3);
  foil.push_back({0, 0.299});
  // The foil starts where the glass neck is this wide: lift it off the glass a little.
  for (RY& p : foil) p.r = p.r > 0 ? p.r + 0.0012 : 0;
  lathe(m.part("foil"), foil, 72);
  lathe(m.part("label"), {{0.0456, 0.07}, {0.0456, 0.07}, {0.0456, 0.14}, {0.0456, 0.14}}, 72);
  return m;
}

Model lightsaber() {
  Model m;
  m.materials = {{"metal", 0.62, 0.63, 0.67, 80},
                 {"grip", 0.08, 0.08, 0.09, 10},
                 {"blade", 0.55, 0.9, 1.0, 4}};
  std::vector<RY> hilt{{0, 0},         {0.016, 0},    {0.016, 0},    {0.018, 0.004}, {0.018, 0.235},
                       {0.018, 0.235}, {0.022, 0.24}, {0.022, 0.27}, {0.022, 0.27},  {0.013, 0.27},
                       {0.013, 0.27},  {0.013, 0.28}, {0, 0.28}};
  lathe(m.part("metal"), hilt, 64);
  for (int k = 0; k < 6; ++k) {
    const double y = 0.05 + k * 0.022;
    std::vector<RY> ring;
    arc(ring, 0.018, y + 0.007, 0.007, -90, 90, 8);
    for (RY& p : ring) p.r = 0.018 + (p.r - 0.018) * 0.5;
    lathe(m.part("grip"), ring, 64);
  }
  std::vector<RY> blade{{0.011, 0.28}};
  blade.push_back({0.011, 1.10});
  arc(blade, 0, 1.10, 0.011, 0, 90, 10);
  lathe(m.part("blade"), blade, 48);
  return m;
}

Model lamp() {
  Model m;
  m.materials = {{"ceramic", 0.16, 0.32, 0.66, 70},
                 {"brass", 0.78, 0.62, 0.30, 60},
                 {"shade", 0.96, 0.91, 0.76, 6}};
  std::vector<RY> body;
  arc(body, 0, 0.095, 0.095, -90, 90, 36);  // spherical body, sitting on y = 0
  lathe(m.part("ceramic"), body, 72);
  lathe(m.part("brass"),
        {{0.03, 0.18},
         {0.03, 0.18},
         {0.03, 0.195},
         {0.012, 0.2},
         {0.012, 0.34},
         {0.012, 0.34},
         {0.0, 0.34}},
        48);
  // Open shade: outer wall up, then the inner wall down (1 mm thick).
  std::vector<RY> shade{{0.15, 0.25},  {0.15, 0.25},  {0.085, 0.40}, {0.085, 0.40}, {0.083, 0.40},
                        {0.083, 0.40}, {0.148, 0.25}, {0.148, 0.25}, {0.15, 0.25}};
  lathe(m.part("shade"), shade, 72);
  return m;
}

Model mug() {
  Model m;
  m.materials = {{"glaze", 0.80, 0.24, 0.20, 60}, {"inside", 0.95, 0.93, 0.88, 30}};
  std::vector<RY> outer{{0, 0.0}, {0.036, 0.0}};
  arc(outer, 0.036, 0.006, 0.006, -90, 0, 5);
  outer.push_back({0.042, 0.098});
  arc(outer, 0.040, 0.098, 0.002, 0, 180, 6);
  lathe(m.part("glaze"), outer, 72);
  std::vector<RY> inner{{0.038, 0.098}, {0.038, 0.012}};
  arc(inner, 0.032, 0.012, 0.006, 0, -90, 5);
  inner.push_back({0, 0.006});
  lathe(m.part("inside"), inner, 72);
  swept_arc(m.part("glaze"), {0.044, 0.05, 0}, 0.028, 0.0065, -80, 80, 24, 16);
  return m;
}

Model pingpong_paddle() {
  Model m;
  m.materials = {{"wood", 0.80, 0.62, 0.40, 12},
                 {"rubber_red", 0.78, 0.08, 0.08, 20},
                 {"rubber_black", 0.05, 0.05, 0.05, 20}};
  const V3 center{0, 0.165, 0};
  extrude(m.part("wood"), ellipse(0.076, 0.080, center, 72), -0.003, 0.003, true);
  extrude(m.part("rubber_red"), ellipse(0.074, 0.078, center, 72), 0.003, 0.0055, true);
  extrude(m.part("rubber_black"), ellipse(0.074, 0.078, center, 72), -0.0055, -0.003, true);
  extrude(m.part("wood"), rounded_rect(-0.0135, 0.0, 0.0135, 0.095, 0.006, 6), -0.011, 0.011, true);
  return m;
}

Model torch() {
  Model m;
  m.materials = {{"aluminium", 0.20, 0.22, 0.26, 70},
                 {"rubber", 0.06, 0.06, 0.06, 10},
                 {"lens", 1.0, 0.95, 0.70, 100}};
  std::vector<RY> body{{0, 0}, {0.016, 0}};
  arc(body, 0.016, 0.003, 0.003, -90, 0, 4);
  body.push_back({0.019, 0.165});
  ease(body, {0.019, 0.165}, {0.030, 0.215}, 10);
  body.push_back({0.030, 0.215});
  body.push_back({0.031, 0.218});
  body.push_back({0.031, 0.235});
  body.push_back({0.031, 0.235});
  body.push_back({0.027, 0.235});
  body.push_back({0.027, 0.235});
  body.push_back({0.027, 0.231});
  lathe(m.part("aluminium"), body, 72);
  for (int k = 0; k < 5; ++k) {
    const double y = 0.03 + k * 0.024;
    lathe(m.part("rubber"), {{0.0194, y}, {0.0194, y}, {0.0194, y + 0.012}, {0.0194, y + 0.012}},
          72);
  }
  lathe(m.part("lens"), {{0.027, 0.231}, {0.0, 0.232}}, 72);
  return m;
}

// Dense lathed vase for the frame-time benchmark: rings x segments x 2 ~ N triangles.
Model dense_vase(long triangles) {
  Model m;
  m.materials = {{"clay", 0.75, 0.5, 0.35, 30}};
  const int segments = 512;
  const int rings = static_cast<int>(std::max(2L, triangles / (2L * segments)));
  std::vector<RY> p;
  for (int i = 0; i <= rings; ++i) {
    const double t = static_cast<double>(i) / rings;
    p.push_back({0.06 + 0.035 * std::sin(t * 2.5 * kPi) * (1 - 0.5 * t), 0.3 * t});
  }
  lathe(m.part("clay"), p, segments);
  return m;
}

bool write_model(const Model& m, const std::filesystem::path& obj_path) {
  const std::string stem = obj_path.stem().string();
  const std::filesystem::path mtl_path = obj_path.parent_path() / (stem + ".mtl");
  std::ofstream mtl(mtl_path);
  mtl << "# " << stem << ": written by annex-make-models\n";
  for (const Material& mat : m.materials)
    mtl << "\nnewmtl " << mat.name << "\nKa 0 0 0\nKd " << mat.r << " " << mat.g << " " << mat.b
        << "\nKs 0.3 0.3 0.3\nNs " << mat.shininess << "\nd 1\nillum 2\n";
  std::ofstream obj(obj_path);
  obj << "# " << stem << ": written by annex-make-models (metres, +Y up)\nmtllib " << stem
      << ".mtl\n";
  char buf[128];
  int offset = 1;
  long tri_count = 0;
  for (std::size_t k = 0; k < m.parts.size(); ++k) {
    const Part& part = m.parts[k];
    obj << "o " << part.material << "_" << k << "\nusemtl " << part.material << "\n";
    for (const V3& v : part.positions) {
      std::snprintf(buf, sizeof buf, "v %.5f %.5f %.5f\n", v.x, v.y, v.z);
      obj << buf;
    }
    for (const V3& n : part.normals) {
      std::snprintf(buf, sizeof buf, "vn %.4f %.4f %.4f\n", n.x, n.y, n.z);
      obj << buf;
    }
    for (std::size_t t = 0; t < part.tris.size(); t += 3) {
      const int a = part.tris[t] + offset, b = part.tris[t + 1] + offset,
                c = part.tris[t + 2] + offset;
      obj << "f " << a << "//" << a << " " << b << "//" << b << " " << c << "//" << c << "\n";
      ++tri_count;
    }
    offset += static_cast<int>(part.positions.size());
  }
  std::cout << obj_path.string() << ": " << tri_count << " triangles\n";
  return static_cast<bool>(obj) && static_cast<bool>(mtl);
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() == 3 && args[0] == "--dense") {
    const long n = std::strtol(args[1].c_str(), nullptr, 10);
    if (n <= 0) {
      std::cerr << "annex-make-models: error: --dense needs a positive triangle count\n";
      return 2;
    }
    return write_model(dense_vase(n), args[2]) ? 0 : 1;
  }
  if (args.size() != 1 || args[0].starts_with("-")) {
    std::cerr << "usage: annex-make-models OUT_DIR | annex-make-models --dense TRIANGLES OUT.obj\n";
    return 2;
  }
  const std::filesystem::path dir = args[0];
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  bool ok = true;
  ok &= write_model(champagne_bottle(), dir / "champagne_bottle.obj");
  ok &= write_model(lightsaber(), dir / "lightsaber.obj");
  ok &= write_model(lamp(), dir / "lamp.obj");
  ok &= write_model(mug(), dir / "mug.obj");
  ok &= write_model(pingpong_paddle(), dir / "pingpong_paddle.obj");
  ok &= write_model(torch(), dir / "torch.obj");
  return ok ? 0 : 1;
}
