#include "annex/formats/scene_format.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <utility>

#include "annex/formats/file_io.h"
#include "annex/formats/text_lexer.h"

namespace annex {
namespace {
using namespace detail;

constexpr std::string_view kHeader = "annex-scene";
constexpr int kVersion = 1;
constexpr std::string_view kTopKeys[] = {"support", "object"};
constexpr std::string_view kObjectKeys[] = {"points", "fit",   "sphere", "cylinder",
                                            "cone",   "torus", "box",    "end"};
constexpr std::string_view kPrimitiveKeys[] = {"center", "axis", "fit"};

Result<Vec3> read_vec3(LineReader& r, std::string_view key) {
  double c[3];
  for (double& v : c) {
    auto n = r.number(key);
    if (!n) return n.error();
    v = *n;
  }
  return Vec3{c[0], c[1], c[2]};
}

// A direction: any non-zero vector, normalised unless already unit (within kNormExact,
// kept bit for bit so that written scenes read back identically).
Result<Vec3> read_direction(LineReader& r, std::string_view origin, std::string_view key) {
  auto v = read_vec3(r, key);
  if (!v) return v;
  const double n = norm(*v);
  if (std::abs(n - 1) <= kNormExact) return v;
  // Divide by the largest component first so tiny and huge vectors neither underflow
  // nor overflow: the result is unit to rounding and is kept as is when read back.
  const double m = std::max({std::abs(v->x), std::abs(v->y), std::abs(v->z)});
  if (!(m > 0)) return error_at(origin, r.last(), std::string(key) + " must be a non-zero vector");
  return normalized(Vec3{v->x / m, v->y / m, v->z / m});
}

struct OpenObject {
  PhysicalObject object;
  int line = 0;
  std::map<std::string, int, std::less<>> keys;
};

// `shape name value ... [center x y z] [axis x y z] [fit f]`, the shape already taken.
Result<PhysicalPrimitive> parse_primitive(LineReader& r, std::string_view origin,
                                          const Token& shape_tok, ShapeKind kind) {
  PhysicalPrimitive p;
  p.kind = kind;
  const auto names = dimension_names(kind);
  p.dimensions_m.assign(names.size(), 0.0);
  std::vector<Token> value_tokens(names.size());
  std::vector<std::string_view> keys(names.begin(), names.end());
  keys.insert(keys.end(), std::begin(kPrimitiveKeys), std::end(kPrimitiveKeys));
  std::map<std::string, int, std::less<>> seen;
  const std::string block =
      "in " + std::string(shape_name(kind)) + " at column " + std::to_string(shape_tok.column);
  while (!r.at_end()) {
    const Token& key = r.take();
    const int dim = key.quoted ? -1 : dimension_index(kind, key.text);
    const bool known =
        dim >= 0 ||
        (!key.quoted && (key.text == "center" || key.text == "axis" || key.text == "fit"));
    if (!known)
      return error_at(origin, key,
                      "unknown key " + shown(key) + " " + block + suggestion(key.text, keys));
    if (auto it = seen.find(key.text); it != seen.end())
      return error_at(origin, key,
                      "duplicate key '" + key.text + "' " + block + " (first at column " +
                          std::to_string(it->second) + ")");
    seen.emplace(key.text, key.column);
    if (dim >= 0) {
      auto v = r.positive(key.text);
      if (!v) return v.error();
      p.dimensions_m[static_cast<std::size_t>(dim)] = *v;
      value_tokens[static_cast<std::size_t>(dim)] = r.last();
    } else if (key.text == "center") {
      auto c = read_vec3(r, "center");
      if (!c) return c.error();
      p.center = *c;
    } else if (key.text == "axis") {
      auto a = read_direction(r, origin, "axis");
      if (!a) return a.error();
      p.axis = *a;
    } else {
      auto f = r.unit_interval("fit");
      if (!f) return f.error();
      p.fit = *f;
    }
  }
  for (std::size_t i = 0; i < names.size(); ++i)
    if (!seen.contains(std::string(names[i])))
      return error_at(
          origin, shape_tok,
          std::string(shape_name(kind)) + " is missing dimension '" + std::string(names[i]) + "'");
  if (kind == ShapeKind::torus)
    if (auto msg = check_torus(p.dimensions_m[0], p.dimensions_m[1]))
      return error_at(origin, value_tokens[1], *msg);
  return p;
}

void write_vec3(std::string& out, const Vec3& v) {
  out += format_number(v.x) + " " + format_number(v.y) + " " + format_number(v.z);
}

}  // namespace

Result<PhysicalScene> parse_scene(std::string_view text, std::string_view origin,
                                  std::vector<Diagnostic>* warnings) {
  (void)warnings;  // no scene rule warns yet; kept for symmetry with parse_haptic
  Lexer lexer(text, origin);
  if (auto st = lexer.check_size(kMaxTextFileBytes); !st) return st.error();

  PhysicalScene scene;
  std::map<std::string, int, std::less<>> object_lines;
  std::optional<OpenObject> obj;
  int support_line = 0;
  bool have_header = false;
  Line line;

  for (;;) {
    auto more = lexer.next(line);
    if (!more) return more.error();
    if (!*more) break;
    LineReader r(line, origin);
    const Token& key = r.take();

    if (!have_header) {
      if (auto st = read_header(r, key, kHeader, kVersion); !st) return st.error();
      have_header = true;
      continue;
    }

    if (obj) {
      OpenObject& o = *obj;
      const std::string block = "in object '" + o.object.id + "'";
      if (key.quoted)
        return error_at(
            origin, key,
            "unknown key " + shown(key) + " " + block + suggestion(key.text, kObjectKeys));
      if (key.text == "end") {
        if (auto st = r.expect_end("end"); !st) return st.error();
        scene.objects.push_back(std::move(o.object));
        obj.reset();
        continue;
      }
      if (key.text == "object" || key.text == "support")
        return error_at(origin, key,
                        "missing 'end' for object '" + o.object.id + "' (opened at line " +
                            std::to_string(o.line) + ") before '" + key.text + "'");
      if (auto kind = shape_from_name(key.text)) {
        if (o.object.primitives.size() >= kMaxPrimitivesPerObject)
          return error_at(origin, key,
                          "object '" + o.object.id + "' has more than " +
                              std::to_string(kMaxPrimitivesPerObject) + " primitives");
        auto p = parse_primitive(r, origin, key, *kind);
        if (!p) return p.error();
        o.object.primitives.push_back(std::move(*p));
        continue;
      }
      if (key.text != "points" && key.text != "fit")
        return error_at(
            origin, key,
            "unknown key " + shown(key) + " " + block + suggestion(key.text, kObjectKeys));
      if (auto it = o.keys.find(key.text); it != o.keys.end())
        return error_at(origin, key,
                        "duplicate key '" + key.text + "' in object '" + o.object.id +
                            "' (first at line " + std::to_string(it->second) + ")");
      o.keys.emplace(key.text, key.line);
      if (key.text == "points") {
        auto n = r.non_negative_int("points");
        if (!n) return n.error();
        o.object.point_count = *n;
      } else {
        auto f = r.unit_interval("fit");
        if (!f) return f.error();
        o.object.fit = *f;
      }
      if (auto st = r.expect_end(key.text); !st) return st.error();
      continue;
    }

    // Top level.
    if (!key.quoted && key.text == "object") {
      auto id = r.identifier("object id", "object");
      if (!id) return id.error();
      const Token id_tok = r.last();
      if (auto st = r.expect_end("object " + *id); !st) return st.error();
      if (auto it = object_lines.find(*id); it != object_lines.end())
        return error_at(
            origin, id_tok,
            "duplicate object id '" + *id + "' (first at line " + std::to_string(it->second) + ")");
      if (scene.objects.size() >= kMaxObjects)
        return error_at(origin, key,
                        "more than " + std::to_string(kMaxObjects) + " objects in one file");
      object_lines.emplace(*id, key.line);
      OpenObject o;
      o.object.id = *id;
      o.line = key.line;
      obj = std::move(o);
      continue;
    }
    if (!key.quoted && key.text == "support") {
      if (support_line > 0)
        return error_at(origin, key,
                        "duplicate key 'support' at top level (first at line " +
                            std::to_string(support_line) + ")");
      support_line = key.line;
      auto n = read_direction(r, origin, "support");
      if (!n) return n.error();
      auto d = r.number("support");
      if (!d) return d.error();
      if (auto st = r.expect_end("support"); !st) return st.error();
      scene.support = Plane{*n, *d};
      continue;
    }
    if (!key.quoted && key.text == "end")
      return error_at(origin, key, "stray 'end' at top level; no object is open");
    return error_at(origin, key,
                    "unknown key " + shown(key) + " at top level" + suggestion(key.text, kTopKeys));
  }

  const Location eof = lexer.end_location();
  if (!have_header) return Error{"empty input; expected the header 'annex-scene 1'", eof};
  if (obj)
    return Error{"missing 'end' for object '" + obj->object.id + "' (opened at line " +
                     std::to_string(obj->line) + ") at the end of the input",
                 eof};
  return scene;
}

Status validate_scene(const PhysicalScene& scene, std::string_view origin) {
  const std::string base(origin);
  const auto fail = [](std::string where, std::string message) {
    return Error{std::move(message), Location{std::move(where), 0, 0}};
  };
  const auto direction_ok = [](const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) &&
           (v.x != 0 || v.y != 0 || v.z != 0);
  };
  if (scene.support) {
    if (!direction_ok(scene.support->normal))
      return fail(base, "support must be a non-zero vector");
    if (auto msg = check_finite(scene.support->d, "support")) return fail(base, *msg);
  }
  if (scene.objects.size() > kMaxObjects)
    return fail(base, "more than " + std::to_string(kMaxObjects) + " objects in one file");
  std::map<std::string_view, std::size_t> ids;
  for (std::size_t oi = 0; oi < scene.objects.size(); ++oi) {
    const PhysicalObject& o = scene.objects[oi];
    std::string where = base + ": object '";
    where += o.id;
    where += '\'';
    if (!is_identifier(o.id))
      return fail(where, invalid_name_message("object id", "'" + o.id + "'"));
    if (!ids.emplace(o.id, oi).second) return fail(where, "duplicate object id '" + o.id + "'");
    if (o.point_count < 0)
      return fail(where, "points must be 0 or more, found " + std::to_string(o.point_count));
    if (auto msg = check_unit_interval(o.fit, "fit")) return fail(where, *msg);
    if (o.primitives.size() > kMaxPrimitivesPerObject)
      return fail(where, "object '" + o.id + "' has more than " +
                             std::to_string(kMaxPrimitivesPerObject) + " primitives");
    for (const PhysicalPrimitive& p : o.primitives) {
      if (!shape_from_name(shape_name(p.kind))) return fail(where, "unknown shape");
      const std::string shape(shape_name(p.kind));
      const auto names = dimension_names(p.kind);
      if (p.dimensions_m.size() < names.size())
        return fail(where, shape + " is missing dimension '" +
                               std::string(names[p.dimensions_m.size()]) + "'");
      if (p.dimensions_m.size() > names.size())
        return fail(where, shape + " has " + std::to_string(p.dimensions_m.size()) +
                               " dimensions; a " + shape + " has " + std::to_string(names.size()));
      for (std::size_t i = 0; i < names.size(); ++i)
        if (auto msg = check_positive(p.dimensions_m[i], names[i])) return fail(where, *msg);
      if (p.kind == ShapeKind::torus)
        if (auto msg = check_torus(p.dimensions_m[0], p.dimensions_m[1])) return fail(where, *msg);
      for (double v : {p.center.x, p.center.y, p.center.z})
        if (auto msg = check_finite(v, "center")) return fail(where, *msg);
      if (!direction_ok(p.axis)) return fail(where, "axis must be a non-zero vector");
      if (auto msg = check_unit_interval(p.fit, "fit")) return fail(where, *msg);
    }
  }
  return Ok{};
}

std::string write_scene(const PhysicalScene& scene) {
  std::string out = std::string(kHeader) + " " + std::to_string(kVersion) + "\n";
  if (scene.support) {
    out += "support ";
    write_vec3(out, scene.support->normal);
    out += " " + format_number(scene.support->d) + "\n";
  }
  for (const PhysicalObject& o : scene.objects) {
    out += "\nobject " + o.id + "\n";
    out += "  points " + std::to_string(o.point_count) + "\n";
    out += "  fit " + format_number(o.fit) + "\n";
    for (const PhysicalPrimitive& p : o.primitives) {
      out += "  " + std::string(shape_name(p.kind));
      const auto names = dimension_names(p.kind);
      for (std::size_t i = 0; i < names.size() && i < p.dimensions_m.size(); ++i) {
        out += ' ';
        out += names[i];
        out += ' ';
        out += format_number(p.dimensions_m[i]);
      }
      out += " center ";
      write_vec3(out, p.center);
      out += " axis ";
      write_vec3(out, p.axis);
      out += " fit " + format_number(p.fit) + "\n";
    }
    out += "end\n";
  }
  return out;
}

Result<PhysicalScene> read_scene_file(const std::filesystem::path& path,
                                      std::vector<Diagnostic>* warnings) {
  auto text = read_text_file(path);
  if (!text) return text.error();
  return parse_scene(*text, path.string(), warnings);
}

Status write_scene_file(const std::filesystem::path& path, const PhysicalScene& scene) {
  // Refuse to write what could not be read back.
  if (auto st = validate_scene(scene, path.string()); !st) return st;
  return write_file_atomically(path, write_scene(scene));
}

}  // namespace annex
