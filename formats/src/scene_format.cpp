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
// Version 2 adds support ids (several supports), an object's `on` and `partial`, and
// a cone's narrow_radius; version 3 adds `on_object` (an object standing on another
// object's top). Older files still read. The writer uses the lowest version the scene
// needs, so older readers keep reading the files that need nothing newer.
constexpr int kVersion = 3;
constexpr std::string_view kTopKeys[] = {"support", "object"};
constexpr std::string_view kObjectKeys[] = {"points", "fit",   "sphere", "cylinder", "cone",     "torus",
                                            "box",    "plane", "end",    "on",       "partial", "on_object"};
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
  Token on;         // the `on` value, checked against the supports at the end
  Token on_object;  // the `on_object` value, checked against the objects at the end
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
  Token narrow_token;
  std::vector<std::string_view> keys(names.begin(), names.end());
  keys.insert(keys.end(), std::begin(kPrimitiveKeys), std::end(kPrimitiveKeys));
  std::map<std::string, int, std::less<>> seen;
  const std::string block =
      "in " + std::string(shape_name(kind)) + " at column " + std::to_string(shape_tok.column);
  while (!r.at_end()) {
    const Token& key = r.take();
    const int dim = key.quoted ? -1 : dimension_index(kind, key.text);
    const bool narrow = !key.quoted && kind == ShapeKind::cone && key.text == "narrow_radius";
    const bool x_axis = !key.quoted && kind == ShapeKind::plane && key.text == "x_axis";
    const bool known =
        dim >= 0 || narrow || x_axis ||
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
    } else if (narrow) {
      auto v = r.positive(key.text);
      if (!v) return v.error();
      p.narrow_radius_m = *v;
      narrow_token = r.last();
    } else if (x_axis) {
      auto a = read_direction(r, origin, "x_axis");
      if (!a) return a.error();
      p.x_axis = *a;
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
  if (p.narrow_radius_m > 0 && p.narrow_radius_m >= p.dimensions_m[0])
    return error_at(origin, narrow_token,
                    "cone narrow_radius must be less than its radius (the wide end)");
  return p;
}

// A stack that leads back to where it started (a on b, b on a) is no stack: the
// message naming the loop, or nothing. Objects naming no declared object end a walk.
std::optional<std::string> stacking_cycle(const PhysicalScene& scene, const std::string& start) {
  std::map<std::string_view, const PhysicalObject*> by_id;
  for (const PhysicalObject& o : scene.objects) by_id.emplace(o.id, &o);
  std::string path = start;
  std::string_view at = start;
  for (std::size_t step = 0; step <= scene.objects.size(); ++step) {
    const auto it = by_id.find(at);
    if (it == by_id.end() || it->second->on_object.empty()) return std::nullopt;
    at = it->second->on_object;
    path += " on " + std::string(at);
    if (at == start) return "objects stand on each other in a loop (" + path + ")";
  }
  return std::nullopt;  // a loop not through `start`: reported from one of its members
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
  int version = 1;
  std::map<std::string, int, std::less<>> support_lines;
  std::vector<OpenObject> placed;  // objects with an `on`, checked at the end
  bool have_header = false;
  Line line;

  for (;;) {
    auto more = lexer.next(line);
    if (!more) return more.error();
    if (!*more) break;
    LineReader r(line, origin);
    const Token& key = r.take();

    if (!have_header) {
      // Version 2 or 3 when the file says so, else the version-1 header (and its errors).
      version = 1;
      if (line.tokens.size() > 1 && (line.tokens[1].text == "2" || line.tokens[1].text == "3"))
        version = line.tokens[1].text == "2" ? 2 : 3;
      if (auto st = read_header(r, key, kHeader, version); !st) {
        Error e = st.error();
        const std::string one = "this reader knows version 1";
        if (auto at = e.message.find(one); at != std::string::npos)
          e.message.replace(at, one.size(), "this reader knows versions 1 to 3");
        return e;
      }
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
        if (!o.object.support_id.empty() || !o.object.on_object.empty()) placed.push_back(o);
        scene.objects.push_back(std::move(o.object));
        obj.reset();
        continue;
      }
      if (version < 2 && (key.text == "on" || key.text == "partial"))
        return error_at(origin, key,
                        "'" + key.text + "' in object '" + o.object.id +
                            "' needs the header 'annex-scene 2'");
      if (version < 3 && key.text == "on_object")
        return error_at(origin, key,
                        "'on_object' in object '" + o.object.id + "' needs the header 'annex-scene 3'");
      if (version >= 2 && (key.text == "on" || key.text == "partial" || key.text == "on_object")) {
        if (auto it = o.keys.find(key.text); it != o.keys.end())
          return error_at(origin, key,
                          "duplicate key '" + key.text + "' in object '" + o.object.id +
                              "' (first at line " + std::to_string(it->second) + ")");
        o.keys.emplace(key.text, key.line);
        if (key.text == "on") {
          auto id = r.identifier("support id", "on");
          if (!id) return id.error();
          o.object.support_id = *id;
          o.on = r.last();
        } else if (key.text == "on_object") {
          auto id = r.identifier("object id", "on_object");
          if (!id) return id.error();
          if (*id == o.object.id)
            return error_at(origin, r.last(), "object '" + o.object.id + "' cannot stand on itself");
          o.object.on_object = *id;
          o.on_object = r.last();
        } else {
          o.object.partial = true;
        }
        if (auto st = r.expect_end(key.text); !st) return st.error();
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
    if (!key.quoted && key.text == "support" && version >= 2) {
      // `support ID nx ny nz d [points N]`, once per id; the first is the primary.
      auto id = r.identifier("support id", "support");
      if (!id) return id.error();
      const Token id_tok = r.last();
      if (auto it = support_lines.find(*id); it != support_lines.end())
        return error_at(origin, id_tok,
                        "duplicate support id '" + *id + "' (first at line " +
                            std::to_string(it->second) + ")");
      if (scene.supports.size() >= kMaxObjects)
        return error_at(origin, key, "more than " + std::to_string(kMaxObjects) + " supports");
      support_lines.emplace(*id, key.line);
      auto n = read_direction(r, origin, "support");
      if (!n) return n.error();
      auto d = r.number("support");
      if (!d) return d.error();
      SupportSurface surface{*id, Plane{*n, *d}, 0};
      if (!r.at_end()) {
        const Token& k = r.take();
        if (k.quoted || k.text != "points")
          return error_at(origin, k, "unknown key " + shown(k) + " in support '" + *id +
                                         "'; expected 'points' or the end of the line");
        auto count = r.non_negative_int("points");
        if (!count) return count.error();
        surface.point_count = *count;
      }
      if (auto st = r.expect_end("support"); !st) return st.error();
      if (scene.supports.empty()) scene.support = surface.plane;
      scene.supports.push_back(std::move(surface));
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
  for (const OpenObject& o : placed) {
    if (!o.object.support_id.empty() && !support_lines.contains(o.object.support_id))
      return error_at(origin, o.on,
                      "object '" + o.object.id + "' is on support '" + o.object.support_id +
                          "', which the file does not declare");
    if (!o.object.on_object.empty() && !object_lines.contains(o.object.on_object))
      return error_at(origin, o.on_object,
                      "object '" + o.object.id + "' stands on object '" + o.object.on_object +
                          "', which the file does not declare");
  }
  for (const OpenObject& o : placed)
    if (auto cycle = stacking_cycle(scene, o.object.id))
      return error_at(origin, o.on_object, *cycle);
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
  std::map<std::string_view, std::size_t> support_ids;
  for (std::size_t k = 0; k < scene.supports.size(); ++k) {
    const SupportSurface& sp = scene.supports[k];
    const std::string where = base + ": support '" + sp.id + "'";
    if (!is_identifier(sp.id)) return fail(where, invalid_name_message("support id", "'" + sp.id + "'"));
    if (!support_ids.emplace(sp.id, k).second) return fail(where, "duplicate support id '" + sp.id + "'");
    if (!direction_ok(sp.plane.normal)) return fail(where, "support must be a non-zero vector");
    if (auto msg = check_finite(sp.plane.d, "support")) return fail(where, *msg);
    if (sp.point_count < 0) return fail(where, "points must be 0 or more");
  }
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
    if (!o.support_id.empty() && !support_ids.contains(o.support_id))
      return fail(where, "object '" + o.id + "' is on support '" + o.support_id +
                             "', which the scene does not hold");
    if (o.on_object == o.id) return fail(where, "object '" + o.id + "' cannot stand on itself");
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
      if (!(p.narrow_radius_m >= 0) || (p.narrow_radius_m > 0 && (p.kind != ShapeKind::cone ||
                                                                   p.narrow_radius_m >= p.dimensions_m[0])))
        return fail(where, "narrow_radius must be 0, or for a cone less than its radius");
      const bool no_x_axis = p.x_axis.x == 0 && p.x_axis.y == 0 && p.x_axis.z == 0;
      if (!no_x_axis && (p.kind != ShapeKind::plane || !direction_ok(p.x_axis)))
        return fail(where, "x_axis must be zero, or for a plane a non-zero vector");
    }
  }
  for (const PhysicalObject& o : scene.objects) {
    if (o.on_object.empty()) continue;
    const std::string where = base + ": object '" + o.id + "'";
    if (!ids.contains(o.on_object))
      return fail(where, "object '" + o.id + "' stands on object '" + o.on_object +
                             "', which the scene does not hold");
    if (auto cycle = stacking_cycle(scene, o.id)) return fail(where, *cycle);
  }
  return Ok{};
}

std::string write_scene(const PhysicalScene& scene) {
  bool v2 = !scene.supports.empty(), v3 = false;
  for (const PhysicalObject& o : scene.objects) {
    v2 = v2 || !o.support_id.empty() || o.partial;
    v3 = v3 || !o.on_object.empty();
    for (const PhysicalPrimitive& p : o.primitives)
      v2 = v2 || p.narrow_radius_m > 0 || p.kind == ShapeKind::plane;
  }
  v2 = v2 || v3;
  std::string out = std::string(kHeader) + " " + std::to_string(v3 ? kVersion : v2 ? 2 : 1) + "\n";
  if (v2) {
    for (const SupportSurface& sp : scene.supports) {
      out += "support " + sp.id + " ";
      write_vec3(out, sp.plane.normal);
      out += " " + format_number(sp.plane.d) + " points " + std::to_string(sp.point_count) + "\n";
    }
    if (scene.supports.empty() && scene.support) {
      out += "support s1 ";
      write_vec3(out, scene.support->normal);
      out += " " + format_number(scene.support->d) + "\n";
    }
  } else if (scene.support) {
    out += "support ";
    write_vec3(out, scene.support->normal);
    out += " " + format_number(scene.support->d) + "\n";
  }
  for (const PhysicalObject& o : scene.objects) {
    out += "\nobject " + o.id + "\n";
    if (!o.support_id.empty()) out += "  on " + o.support_id + "\n";
    if (!o.on_object.empty()) out += "  on_object " + o.on_object + "\n";
    if (o.partial) out += "  partial\n";
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
      if (p.narrow_radius_m > 0) out += " narrow_radius " + format_number(p.narrow_radius_m);
      out += " center ";
      write_vec3(out, p.center);
      out += " axis ";
      write_vec3(out, p.axis);
      if (p.kind == ShapeKind::plane && norm(p.x_axis) > 0) {
        out += " x_axis ";
        write_vec3(out, p.x_axis);
      }
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
