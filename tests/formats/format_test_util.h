#pragma once
// Helpers shared by the format tests: golden files and a seeded generator of valid
// models and scenes for the round-trip property tests.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "annex/common/haptic_model.h"
#include "annex/common/physical_scene.h"

namespace annex::test {

inline std::filesystem::path data_path(const std::string& name) {
  return std::filesystem::path(ANNEX_FORMATS_DATA) / name;
}

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Random values that exercise the number writer: short decimals, full-precision
// doubles, tiny and huge magnitudes.
class Gen {
 public:
  explicit Gen(unsigned seed) : rng_(seed) {}

  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  bool coin() { return integer(0, 1) == 1; }

  double positive() {
    switch (integer(0, 3)) {
      case 0:
        return integer(1, 999) / 1000.0;
      case 1:
        return std::uniform_real_distribution<double>(1e-4, 2.0)(rng_);
      case 2:
        return std::ldexp(std::uniform_real_distribution<double>(0.5, 1.0)(rng_), integer(-60, 60));
      default:
        return integer(1, 100000);
    }
  }
  double signed_value() { return coin() ? positive() : -positive(); }
  double any() { return integer(0, 5) == 0 ? 0.0 : signed_value(); }
  double unit() {
    switch (integer(0, 3)) {
      case 0:
        return 0.0;
      case 1:
        return 1.0;
      case 2:
        return integer(0, 100) / 100.0;
      default:
        return std::uniform_real_distribution<double>(0.0, 1.0)(rng_);
    }
  }

  std::string name() {
    static constexpr char kFirst[] = "abcxyzABCXYZ_";
    static constexpr char kRest[] = "abcdefghijklmnopqrstuvwxyz0123456789_.-ABCZ";
    std::string s(1, kFirst[integer(0, sizeof kFirst - 2)]);
    const int n = integer(0, 12);
    for (int i = 0; i < n; ++i) s += kRest[integer(0, sizeof kRest - 2)];
    return s;
  }

  std::string path() {
    static const std::string kChars[] = {"a",  "b",  "/",        ".", " ", "#",
                                         "\"", "\\", "\xC3\xA9", "_", "z", "\t"};
    std::string s;
    const int n = integer(1, 16);
    for (int i = 0; i < n; ++i) {
      std::string c = kChars[integer(0, 10)];  // never the tab: control characters are refused
      s += c;
    }
    return s;
  }

  Vec3 direction() {
    for (;;) {
      Vec3 v{signed_value(), signed_value(), signed_value()};
      if (integer(0, 3) == 0) v = Vec3{0, 0, coin() ? 1.0 : -1.0};
      const double n = norm(v);
      if (n > 1e-12 && std::isfinite(n)) return normalized(v);
    }
  }

  Quat rotation() {
    if (integer(0, 3) == 0) return Quat{};
    std::normal_distribution<double> nd;
    const Quat q{nd(rng_), nd(rng_), nd(rng_), nd(rng_)};
    return normalized(q);
  }

  std::mt19937& rng() { return rng_; }

 private:
  std::mt19937 rng_;
};

inline HapticSpec random_spec(Gen& g) {
  HapticSpec spec;
  const int objects = g.integer(0, 5);
  for (int oi = 0; oi < objects; ++oi) {
    VirtualObject o;
    o.name = g.name() + "_o" + std::to_string(oi);  // unique by construction
    if (g.coin()) o.mesh = g.path();
    if (g.coin()) o.model_scale = g.positive();
    o.annexable = g.integer(0, 4) != 0;
    o.priority = g.unit();
    const int prims = o.annexable ? g.integer(1, 4) : g.integer(0, 2);
    for (int pi = 0; pi < prims; ++pi) {
      const ShapeKind kind = kAllShapes[g.integer(0, 5)];
      Primitive p = make_primitive(kind, g.name() + "_p" + std::to_string(pi));
      p.weight = g.unit();
      p.pose.position = Vec3{g.any(), g.any(), g.any()};
      p.pose.rotation = g.rotation();
      for (Dimension& d : p.dimensions) {
        d.value_m = g.positive();
        d.weight = g.unit();
        d.min_scale = g.positive();
        d.max_scale = g.coin() ? d.min_scale : d.min_scale + g.positive();
      }
      if (kind == ShapeKind::torus && p.dimensions[1].value_m >= p.dimensions[0].value_m)
        p.dimensions[1].value_m = p.dimensions[0].value_m / 2;
      o.primitives.push_back(p);
    }
    spec.objects.push_back(o);
  }
  return spec;
}

inline PhysicalScene random_scene(Gen& g) {
  PhysicalScene scene;
  if (g.coin()) scene.support = Plane{g.direction(), g.any()};
  const int objects = g.integer(0, 5);
  for (int oi = 0; oi < objects; ++oi) {
    PhysicalObject o;
    o.id = g.name() + "_" + std::to_string(oi);
    o.point_count = g.integer(0, 200000);
    o.fit = g.unit();
    const int prims = g.integer(0, 3);
    for (int pi = 0; pi < prims; ++pi) {
      PhysicalPrimitive p;
      p.kind = kSolidShapes[g.integer(0, 4)];  // planes make a version-2 scene (ScenePlane tests)
      for (int d = 0; d < dimension_count(p.kind); ++d) p.dimensions_m.push_back(g.positive());
      if (p.kind == ShapeKind::torus && p.dimensions_m[1] >= p.dimensions_m[0])
        p.dimensions_m[1] = p.dimensions_m[0] / 2;
      p.center = Vec3{g.any(), g.any(), g.any()};
      p.axis = g.direction();
      p.fit = g.unit();
      o.primitives.push_back(p);
    }
    scene.objects.push_back(o);
  }
  return scene;
}

// One rule of a reader, with the exact message and where it points (toml++'s
// parsing_should_fail): the table rows of the InvalidInputs tests.
struct BadInput {
  const char* name;
  std::string text;
  int line;
  int column;
  std::string message;
};

// Every case must fail with its message at its line and column of `origin`.
template <typename Parse>
void expect_located_errors(const std::vector<BadInput>& cases, Parse parse,
                           const std::string& origin) {
  for (const BadInput& c : cases) {
    SCOPED_TRACE(c.name);
    auto r = parse(c.text, origin);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, c.message);
    EXPECT_EQ(r.error().location.origin, origin);
    EXPECT_EQ(r.error().location.line, c.line);
    EXPECT_EQ(r.error().location.column, c.column);
  }
}

}  // namespace annex::test
