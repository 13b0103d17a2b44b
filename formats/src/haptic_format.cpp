#include "annex/formats/haptic_format.h"

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

constexpr std::string_view kHeader = "annex-haptic";

// Votes run from 0 to C (100 unless the runtime is told otherwise): a minimum above
// 1000 cannot be met by any sensible C and is a typo.
std::optional<std::string> check_min_vote(double v) {
  if (!(v >= 0) || v > 1000)
    return "min_vote must be a vote from 0 to 1000 (votes run from 0 to C, 100 by default), "
           "got " + format_number(v);
  return std::nullopt;
}
constexpr int kVersion = 1;
constexpr std::string_view kTopKeys[] = {"object", "exclude"};
// Keys of an exclude block: its shape, then size ranges by dimension name.
constexpr std::string_view kExcludeKeys[] = {
    "shape", "prop_height", "radius", "height", "major_radius", "minor_radius",
    "size_x", "size_y", "size_z", "end"};
constexpr std::string_view kRangeKeys[] = {"min", "max"};
constexpr std::string_view kObjectKeys[] = {"mesh",     "model_scale", "annexable", "priority",
                                             "min_vote", "primitive",   "end"};
constexpr std::string_view kPrimitiveKeys[] = {"priority", "position", "rotation", "end"};
constexpr std::string_view kDimensionKeys[] = {"priority", "scale"};
constexpr std::string_view kShapeNames[] = {"sphere", "cylinder", "cone", "torus", "box",
                                            "plane"};

std::string shape_list() {
  std::string out;
  for (std::string_view s : kShapeNames) {
    if (!out.empty()) out += ", ";
    out += s;
  }
  return out;
}

std::string in_quotes(std::string_view s) {
  std::string out(1, '\'');
  out += s;
  out += '\'';
  return out;
}

// Keys already given in one block, with the line (or column) of their first use.
class SeenKeys {
 public:
  std::optional<int> find(std::string_view key) const {
    for (const auto& [k, where] : keys_)
      if (k == key) return where;
    return std::nullopt;
  }
  void add(std::string key, int where) { keys_.emplace_back(std::move(key), where); }

 private:
  std::vector<std::pair<std::string, int>> keys_;
};

struct OpenObject {
  VirtualObject object;
  int line = 0;
  SeenKeys keys;
  std::map<std::string, int, std::less<>> primitive_lines;
};

struct OpenPrimitive {
  Primitive primitive;
  int line = 0;
  SeenKeys keys;
  std::vector<bool> have;           // per dimension index
  std::vector<Token> value_tokens;  // per dimension index, for located errors
};

std::string describe(const OpenPrimitive& p) {
  return std::string(shape_name(p.primitive.kind)) + " '" + p.primitive.name + "'";
}

Error duplicate_key(std::string_view origin, const Token& key, std::string_view block,
                    int first_line) {
  return error_at(origin, key,
                  "duplicate key '" + key.text + "' in " + std::string(block) + " (first at line " +
                      std::to_string(first_line) + ")");
}

Error unknown_key(std::string_view origin, const Token& key, std::string_view block,
                  std::span<const std::string_view> keys) {
  return error_at(
      origin, key,
      "unknown key " + shown(key) + " " + std::string(block) + suggestion(key.text, keys));
}

// An exclude rule being read, with the token of each range's dimension for errors
// found at its `end` (a dimension that its shape does not have).
struct OpenExclude {
  ExcludeRule rule;
  int line = 0;
  SeenKeys keys;
  std::vector<Token> dimension_tokens;
};

// Why a range's dimension does not apply to the rule's shape, if it does not.
std::optional<std::string> check_range_dimension(const ExcludeRule& rule,
                                                 const std::string& dimension) {
  if (dimension == kPropHeight) return std::nullopt;
  if (!rule.shape)
    return "'" + dimension + "' needs a shape in exclude rule '" + rule.name +
           "'; with any shape only 'prop_height' applies";
  if (dimension_index(*rule.shape, dimension) >= 0) return std::nullopt;
  std::string names;
  for (std::string_view n : dimension_names(*rule.shape)) names += std::string(n) + ", ";
  return "'" + dimension + "' is not a dimension of a " + std::string(shape_name(*rule.shape)) +
         " (exclude rule '" + rule.name + "' accepts " + names + "prop_height)";
}

std::optional<std::string> check_range_bounds(const SizeRange& r) {
  if (!r.min_m && !r.max_m) return "a size range needs 'min' or 'max' (or both)";
  for (const auto& b : {r.min_m, r.max_m})
    if (b && !(std::isfinite(*b) && *b >= 0))
      return "size range bounds must be finite metres >= 0, found " + format_number(*b);
  if (r.min_m && r.max_m && *r.min_m > *r.max_m)
    return "size range minimum " + format_number(*r.min_m) + " is larger than maximum " +
           format_number(*r.max_m);
  return std::nullopt;
}

std::string empty_rule_message(const ExcludeRule& rule) {
  return "exclude rule '" + rule.name +
         "' names neither a shape nor a size range: it would exclude every prop";
}

// `DIMENSION [min X] [max Y]` after the dimension name was taken.
Status parse_range(LineReader& r, std::string_view origin, const Token& dim, SizeRange& range) {
  range = SizeRange{dim.text, std::nullopt, std::nullopt};
  SeenKeys seen;
  while (!r.at_end()) {
    const Token& key = r.take();
    const std::string block = "size range '" + dim.text + "'";
    if (key.quoted || (key.text != "min" && key.text != "max"))
      return unknown_key(origin, key, "in " + block, kRangeKeys);
    if (auto first = seen.find(key.text))
      return error_at(origin, key,
                      "duplicate key '" + key.text + "' in " + block + " (first at column " +
                          std::to_string(*first) + ")");
    seen.add(key.text, key.column);
    auto v = r.number(key.text);
    if (!v) return v.error();
    if (!(*v >= 0))
      return error_at(origin, r.last(),
                      "size range bounds must be finite metres >= 0, found " + format_number(*v));
    (key.text == "min" ? range.min_m : range.max_m) = *v;
    if (range.min_m && range.max_m && *range.min_m > *range.max_m)
      return error_at(origin, r.last(), *check_range_bounds(range));
  }
  if (!range.min_m && !range.max_m)
    return r.missing("expected 'min METRES' and/or 'max METRES' after '" + dim.text + "'");
  return Ok{};
}

// Parses `name value [priority w] [scale min max]` after the dimension name was taken.
Status parse_dimension(LineReader& r, std::string_view origin, const std::string& name,
                       Dimension& dim) {
  auto value = r.positive(name);
  if (!value) return value.error();
  dim = Dimension{};
  dim.value_m = *value;
  SeenKeys seen;
  while (!r.at_end()) {
    const Token& key = r.take();
    const std::string block = "dimension '" + name + "'";
    if (key.quoted || (key.text != "priority" && key.text != "scale"))
      return unknown_key(origin, key, "in " + block, kDimensionKeys);
    if (auto first = seen.find(key.text))
      return error_at(origin, key,
                      "duplicate key '" + key.text + "' in " + block + " (first at column " +
                          std::to_string(*first) + ")");
    seen.add(key.text, key.column);
    if (key.text == "priority") {
      auto w = r.unit_interval("priority");
      if (!w) return w.error();
      dim.weight = *w;
    } else {
      auto min = r.number("scale");
      if (!min) return min.error();
      if (auto msg = check_scale_min(*min)) return error_at(origin, r.last(), *msg);
      auto max = r.number("scale");
      if (!max) return max.error();
      if (auto msg = check_scale_order(*min, *max)) return error_at(origin, r.last(), *msg);
      dim.min_scale = *min;
      dim.max_scale = *max;
    }
  }
  return Ok{};
}

Status parse_rotation(LineReader& r, std::string_view origin, Quat& q) {
  double c[4];
  for (double& v : c) {
    auto n = r.number("rotation");
    if (!n) return n.error();
    v = *n;
  }
  const double norm = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + c[3] * c[3]);
  if (!(std::abs(norm - 1) <= kNormTolerance))
    return error_at(
        origin, r.last().line, r.last().column,
        "rotation must be a unit quaternion w x y z, found norm " + format_number(norm));
  q = Quat{c[0], c[1], c[2], c[3]};
  if (std::abs(norm - 1) > kNormExact) q = normalized(q);
  return Ok{};
}

// Checks that a block closing with `end` has nothing after it.
Status parse_end(LineReader& r) {
  return r.expect_end("end");
}

Status finish_primitive(OpenPrimitive& p, const Token& end, std::string_view origin,
                        std::vector<Diagnostic>* warnings) {
  const auto names = dimension_names(p.primitive.kind);
  for (std::size_t i = 0; i < names.size(); ++i)
    if (!p.have[i])
      return error_at(origin, end,
                      describe(p) + " is missing dimension '" + std::string(names[i]) + "'");
  if (p.primitive.kind == ShapeKind::torus)
    if (auto msg =
            check_torus(p.primitive.dimensions[0].value_m, p.primitive.dimensions[1].value_m))
      return error_at(origin, p.value_tokens[1], *msg);
  bool all_zero = true;
  for (const Dimension& d : p.primitive.dimensions) all_zero = all_zero && d.weight == 0;
  if (all_zero && warnings)
    warnings->push_back(
        Diagnostic{"all dimension priorities of " + describe(p) + " are 0: only the shape counts",
                   Location{std::string(origin), p.line, 1}});
  return Ok{};
}

}  // namespace

Result<HapticSpec> parse_haptic(std::string_view text, std::string_view origin,
                                std::vector<Diagnostic>* warnings) {
  Lexer lexer(text, origin);
  if (auto st = lexer.check_size(kMaxTextFileBytes); !st) return st.error();

  HapticSpec spec;
  std::map<std::string, int, std::less<>> object_lines;
  std::optional<OpenObject> obj;
  std::optional<OpenPrimitive> prim;
  std::optional<OpenExclude> excl;
  std::map<std::string, int, std::less<>> rule_lines;
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

    if (prim) {
      OpenPrimitive& p = *prim;
      const std::string block = "in " + describe(p);
      if (!key.quoted && key.text == "end") {
        if (auto st = parse_end(r); !st) return st.error();
        if (auto st = finish_primitive(p, key, origin, warnings); !st) return st.error();
        obj->object.primitives.push_back(std::move(p.primitive));
        prim.reset();
        continue;
      }
      if (!key.quoted && (key.text == "primitive" || key.text == "object"))
        return error_at(origin, key,
                        "missing 'end' for " + describe(p) + " (opened at line " +
                            std::to_string(p.line) + ") before '" + key.text + "'");
      const int dim = key.quoted ? -1 : dimension_index(p.primitive.kind, key.text);
      const bool known =
          dim >= 0 || (!key.quoted && (key.text == "priority" || key.text == "position" ||
                                       key.text == "rotation"));
      if (!known) {
        std::vector<std::string_view> keys(std::begin(kPrimitiveKeys), std::end(kPrimitiveKeys));
        const auto names = dimension_names(p.primitive.kind);
        keys.insert(keys.end() - 1, names.begin(), names.end());
        return unknown_key(origin, key, block, keys);
      }
      if (auto first = p.keys.find(key.text))
        return duplicate_key(origin, key, describe(p), *first);
      p.keys.add(key.text, key.line);
      if (dim >= 0) {
        auto& d = p.primitive.dimensions[static_cast<std::size_t>(dim)];
        if (auto st = parse_dimension(r, origin, key.text, d); !st) return st.error();
        p.have[static_cast<std::size_t>(dim)] = true;
        // The value token is the one right after the key.
        p.value_tokens[static_cast<std::size_t>(dim)] = line.tokens[1];
        continue;
      }
      if (key.text == "priority") {
        auto w = r.unit_interval("priority");
        if (!w) return w.error();
        p.primitive.weight = *w;
      } else if (key.text == "position") {
        double c[3];
        for (double& v : c) {
          auto n = r.number("position");
          if (!n) return n.error();
          v = *n;
        }
        p.primitive.pose.position = Vec3{c[0], c[1], c[2]};
      } else {
        if (auto st = parse_rotation(r, origin, p.primitive.pose.rotation); !st) return st.error();
      }
      if (auto st = r.expect_end(key.text); !st) return st.error();
      continue;
    }

    if (excl) {
      OpenExclude& e = *excl;
      const std::string block = "in exclude rule '" + e.rule.name + "'";
      if (key.quoted) return unknown_key(origin, key, block, kExcludeKeys);
      if (key.text == "end") {
        if (auto st = parse_end(r); !st) return st.error();
        for (size_t i = 0; i < e.rule.ranges.size(); ++i)
          if (auto msg = check_range_dimension(e.rule, e.rule.ranges[i].dimension))
            return error_at(origin, e.dimension_tokens[i], *msg);
        if (!e.rule.shape && e.rule.ranges.empty())
          return error_at(origin, key, empty_rule_message(e.rule));
        spec.exclude.push_back(std::move(e.rule));
        excl.reset();
        continue;
      }
      if (key.text == "object" || key.text == "exclude" || key.text == "primitive")
        return error_at(origin, key,
                        "missing 'end' for exclude rule '" + e.rule.name + "' (opened at line " +
                            std::to_string(e.line) + ") before '" + key.text + "'");
      const bool known =
          std::find(std::begin(kExcludeKeys), std::end(kExcludeKeys), key.text) !=
          std::end(kExcludeKeys);
      if (!known) return unknown_key(origin, key, block, kExcludeKeys);
      if (auto first = e.keys.find(key.text))
        return duplicate_key(origin, key, "exclude rule '" + e.rule.name + "'", *first);
      e.keys.add(key.text, key.line);
      if (key.text == "shape") {
        if (r.at_end())
          return r.missing("expected a shape or 'any' after 'shape' (one of: " + shape_list() +
                           ", any)");
        const Token& v = r.take();
        if (v.quoted || v.text != "any") {
          const auto kind = v.quoted ? std::nullopt : shape_from_name(v.text);
          if (!kind)
            return error_at(origin, v,
                            "unknown shape " + shown(v) + suggestion(v.text, kShapeNames) +
                                " (or 'any')");
          e.rule.shape = *kind;
        }
        if (auto st = r.expect_end("shape " + v.text); !st) return st.error();
        continue;
      }
      SizeRange range;
      if (auto st = parse_range(r, origin, key, range); !st) return st.error();
      e.rule.ranges.push_back(std::move(range));
      e.dimension_tokens.push_back(key);
      continue;
    }

    if (obj) {
      OpenObject& o = *obj;
      const std::string block = "in object '" + o.object.name + "'";
      if (key.quoted) return unknown_key(origin, key, block, kObjectKeys);
      if (key.text == "end") {
        if (auto st = parse_end(r); !st) return st.error();
        if (o.object.annexable && o.object.primitives.empty())
          return error_at(origin, key,
                          "annexable object '" + o.object.name +
                              "' has no primitive; add one or set 'annexable no'");
        spec.objects.push_back(std::move(o.object));
        obj.reset();
        continue;
      }
      if (key.text == "object")
        return error_at(origin, key,
                        "missing 'end' for object '" + o.object.name + "' (opened at line " +
                            std::to_string(o.line) + ") before 'object'");
      if (key.text == "primitive") {
        auto name = r.identifier("primitive name", "primitive");
        if (!name) return name.error();
        const Token name_tok = r.last();
        if (r.at_end())
          return r.missing("expected a shape after 'primitive " + *name +
                           "' (one of: " + shape_list() + ")");
        const Token& shape_tok = r.take();
        const auto kind = shape_tok.quoted ? std::nullopt : shape_from_name(shape_tok.text);
        if (!kind)
          return error_at(
              origin, shape_tok,
              "unknown shape " + shown(shape_tok) + suggestion(shape_tok.text, kShapeNames));
        if (auto st = r.expect_end("primitive " + *name + " " + shape_tok.text); !st)
          return st.error();
        if (auto it = o.primitive_lines.find(*name); it != o.primitive_lines.end())
          return error_at(origin, name_tok,
                          "duplicate primitive name '" + *name + "' in object '" + o.object.name +
                              "' (first at line " + std::to_string(it->second) + ")");
        if (o.object.primitives.size() >= kMaxPrimitivesPerObject)
          return error_at(origin, key,
                          "object '" + o.object.name + "' has more than " +
                              std::to_string(kMaxPrimitivesPerObject) + " primitives");
        o.primitive_lines.emplace(*name, key.line);
        OpenPrimitive p;
        p.primitive = make_primitive(*kind, *name);
        p.line = key.line;
        p.have.assign(p.primitive.dimensions.size(), false);
        p.value_tokens.assign(p.primitive.dimensions.size(), Token{});
        prim = std::move(p);
        continue;
      }
      const bool known = key.text == "mesh" || key.text == "annexable" || key.text == "priority" ||
                         key.text == "min_vote" || key.text == "model_scale";
      if (!known) return unknown_key(origin, key, block, kObjectKeys);
      if (auto first = o.keys.find(key.text))
        return duplicate_key(origin, key, "object '" + o.object.name + "'", *first);
      o.keys.add(key.text, key.line);
      if (key.text == "mesh") {
        if (r.at_end()) return r.missing("expected a path after 'mesh'");
        const Token& path = r.take();
        if (path.text.empty())
          return error_at(origin, path, "expected a non-empty path after 'mesh'");
        o.object.mesh = path.text;
      } else if (key.text == "annexable") {
        if (r.at_end()) return r.missing("expected 'yes' or 'no' after 'annexable'");
        const Token& v = r.take();
        if (v.quoted || (v.text != "yes" && v.text != "no"))
          return error_at(origin, v, "expected 'yes' or 'no' after 'annexable', found " + shown(v));
        o.object.annexable = v.text == "yes";
      } else if (key.text == "model_scale") {
        auto v = r.positive("model_scale");
        if (!v) return v.error();
        o.object.model_scale = *v;
      } else if (key.text == "min_vote") {
        auto v = r.number("min_vote");
        if (!v) return v.error();
        if (auto msg = check_min_vote(*v)) return error_at(origin, r.last(), *msg);
        o.object.min_vote = *v;
      } else {
        auto w = r.unit_interval("priority");
        if (!w) return w.error();
        o.object.priority = *w;
      }
      if (auto st = r.expect_end(key.text); !st) return st.error();
      continue;
    }

    // Top level.
    if (!key.quoted && key.text == "object") {
      auto name = r.identifier("object name", "object");
      if (!name) return name.error();
      const Token name_tok = r.last();
      if (auto st = r.expect_end("object " + *name); !st) return st.error();
      if (auto it = object_lines.find(*name); it != object_lines.end())
        return error_at(origin, name_tok,
                        "duplicate object name '" + *name + "' (first at line " +
                            std::to_string(it->second) + ")");
      if (spec.objects.size() >= kMaxObjects)
        return error_at(origin, key,
                        "more than " + std::to_string(kMaxObjects) + " objects in one file");
      object_lines.emplace(*name, key.line);
      OpenObject o;
      o.object.name = *name;
      o.line = key.line;
      obj = std::move(o);
      continue;
    }
    if (!key.quoted && key.text == "exclude") {
      auto name = r.identifier("exclude rule name", "exclude");
      if (!name) return name.error();
      const Token name_tok = r.last();
      if (auto st = r.expect_end("exclude " + *name); !st) return st.error();
      if (auto it = rule_lines.find(*name); it != rule_lines.end())
        return error_at(origin, name_tok,
                        "duplicate exclude rule name '" + *name + "' (first at line " +
                            std::to_string(it->second) + ")");
      if (spec.exclude.size() >= kMaxObjects)
        return error_at(origin, key,
                        "more than " + std::to_string(kMaxObjects) + " exclude rules in one file");
      rule_lines.emplace(*name, key.line);
      OpenExclude e;
      e.rule.name = *name;
      e.line = key.line;
      excl = std::move(e);
      continue;
    }
    if (!key.quoted && key.text == "end")
      return error_at(origin, key, "stray 'end' at top level; no object is open");
    return unknown_key(origin, key, "at top level", kTopKeys);
  }

  const Location eof = lexer.end_location();
  if (!have_header) return Error{"empty input; expected the header 'annex-haptic 1'", eof};
  if (prim)
    return Error{"missing 'end' for " + describe(*prim) + " (opened at line " +
                     std::to_string(prim->line) + ") at the end of the input",
                 eof};
  if (obj)
    return Error{"missing 'end' for object '" + obj->object.name + "' (opened at line " +
                     std::to_string(obj->line) + ") at the end of the input",
                 eof};
  if (excl)
    return Error{"missing 'end' for exclude rule '" + excl->rule.name + "' (opened at line " +
                     std::to_string(excl->line) + ") at the end of the input",
                 eof};
  return spec;
}

Status validate_haptic(const HapticSpec& spec, std::string_view origin) {
  const std::string base(origin);
  const auto fail = [](std::string where, std::string message) {
    return Error{std::move(message), Location{std::move(where), 0, 0}};
  };
  if (spec.objects.size() > kMaxObjects)
    return fail(base, "more than " + std::to_string(kMaxObjects) + " objects in one file");
  std::map<std::string_view, std::size_t> object_index;
  for (std::size_t oi = 0; oi < spec.objects.size(); ++oi) {
    const VirtualObject& o = spec.objects[oi];
    const std::string where = base + ": object " + in_quotes(o.name);
    if (!is_identifier(o.name))
      return fail(where, invalid_name_message("object name", in_quotes(o.name)));
    if (!object_index.emplace(o.name, oi).second)
      return fail(where, "duplicate object name '" + o.name + "'");
    if (has_control_char(o.mesh)) return fail(where, "mesh path contains a control character");
    if (auto msg = check_positive(o.model_scale, "model_scale")) return fail(where, *msg);
    if (auto msg = check_unit_interval(o.priority, "priority")) return fail(where, *msg);
    if (auto msg = check_min_vote(o.min_vote)) return fail(where, *msg);
    if (o.primitives.size() > kMaxPrimitivesPerObject)
      return fail(where, "object '" + o.name + "' has more than " +
                             std::to_string(kMaxPrimitivesPerObject) + " primitives");
    if (o.annexable && o.primitives.empty())
      return fail(where, "annexable object '" + o.name +
                             "' has no primitive; add one or set 'annexable no'");
    std::map<std::string_view, std::size_t> primitive_index;
    for (std::size_t pi = 0; pi < o.primitives.size(); ++pi) {
      const Primitive& p = o.primitives[pi];
      const std::string pwhere = where + " primitive " + in_quotes(p.name);
      if (!is_identifier(p.name))
        return fail(pwhere, invalid_name_message("primitive name", in_quotes(p.name)));
      if (!primitive_index.emplace(p.name, pi).second)
        return fail(pwhere, "duplicate primitive name '" + p.name + "' in object '" + o.name + "'");
      if (!shape_from_name(shape_name(p.kind)))
        return fail(pwhere, "unknown shape; expected one of: " + shape_list());
      const std::string desc = std::string(shape_name(p.kind)) + " '" + p.name + "'";
      const auto names = dimension_names(p.kind);
      if (p.dimensions.size() < names.size())
        return fail(pwhere, desc + " is missing dimension '" +
                                std::string(names[p.dimensions.size()]) + "'");
      if (p.dimensions.size() > names.size())
        return fail(pwhere, desc + " has " + std::to_string(p.dimensions.size()) +
                                " dimensions; a " + std::string(shape_name(p.kind)) + " has " +
                                std::to_string(names.size()));
      if (auto msg = check_unit_interval(p.weight, "priority")) return fail(pwhere, *msg);
      for (double v : {p.pose.position.x, p.pose.position.y, p.pose.position.z})
        if (auto msg = check_finite(v, "position")) return fail(pwhere, *msg);
      const Quat& q = p.pose.rotation;
      for (double v : {q.w, q.x, q.y, q.z})
        if (auto msg = check_finite(v, "rotation")) return fail(pwhere, *msg);
      const double qn = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
      if (!(std::abs(qn - 1) <= kNormTolerance))
        return fail(pwhere,
                    "rotation must be a unit quaternion w x y z, found norm " + format_number(qn));
      for (std::size_t di = 0; di < names.size(); ++di) {
        const Dimension& d = p.dimensions[di];
        const std::string dname(names[di]);
        if (auto msg = check_positive(d.value_m, dname)) return fail(pwhere, *msg);
        if (auto msg = check_unit_interval(d.weight, "priority"))
          return fail(pwhere, *msg + " (dimension '" + dname + "')");
        if (auto msg = check_scale_min(d.min_scale))
          return fail(pwhere, *msg + " (dimension '" + dname + "')");
        if (auto msg = check_scale_order(d.min_scale, d.max_scale))
          return fail(pwhere, *msg + " (dimension '" + dname + "')");
      }
      if (p.kind == ShapeKind::torus)
        if (auto msg = check_torus(p.dimensions[0].value_m, p.dimensions[1].value_m))
          return fail(pwhere, *msg);
    }
  }
  if (spec.exclude.size() > kMaxObjects)
    return fail(base, "more than " + std::to_string(kMaxObjects) + " exclude rules in one file");
  std::map<std::string_view, std::size_t> rule_index;
  for (std::size_t ri = 0; ri < spec.exclude.size(); ++ri) {
    const ExcludeRule& rule = spec.exclude[ri];
    const std::string where = base + ": exclude rule " + in_quotes(rule.name);
    if (!is_identifier(rule.name))
      return fail(where, invalid_name_message("exclude rule name", in_quotes(rule.name)));
    if (!rule_index.emplace(rule.name, ri).second)
      return fail(where, "duplicate exclude rule name '" + rule.name + "'");
    if (rule.shape && !shape_from_name(shape_name(*rule.shape)))
      return fail(where, "unknown shape; expected one of: " + shape_list() + ", any");
    if (!rule.shape && rule.ranges.empty()) return fail(where, empty_rule_message(rule));
    std::map<std::string_view, int> seen;
    for (const SizeRange& range : rule.ranges) {
      if (!seen.emplace(range.dimension, 0).second)
        return fail(where, "duplicate key '" + range.dimension + "' in exclude rule '" +
                               rule.name + "'");
      if (auto msg = check_range_dimension(rule, range.dimension)) return fail(where, *msg);
      if (auto msg = check_range_bounds(range))
        return fail(where, *msg + " (dimension '" + range.dimension + "')");
    }
  }
  return Ok{};
}

std::string write_haptic(const HapticSpec& spec) {
  std::string out = std::string(kHeader) + " " + std::to_string(kVersion) + "\n";
  for (const VirtualObject& o : spec.objects) {
    out += "\nobject " + o.name + "\n";
    if (!o.mesh.empty()) out += "  mesh " + quote_if_needed(o.mesh) + "\n";
    if (o.model_scale != 1) out += "  model_scale " + format_number(o.model_scale) + "\n";
    out += std::string("  annexable ") + (o.annexable ? "yes" : "no") + "\n";
    out += "  priority " + format_number(o.priority) + "\n";
    if (o.min_vote != 0) out += "  min_vote " + format_number(o.min_vote) + "\n";
    for (const Primitive& p : o.primitives) {
      out += "  primitive " + p.name + " " + std::string(shape_name(p.kind)) + "\n";
      out += "    priority " + format_number(p.weight) + "\n";
      const Vec3& t = p.pose.position;
      out += "    position " + format_number(t.x) + " " + format_number(t.y) + " " +
             format_number(t.z) + "\n";
      const Quat& q = p.pose.rotation;
      out += "    rotation " + format_number(q.w) + " " + format_number(q.x) + " " +
             format_number(q.y) + " " + format_number(q.z) + "\n";
      const auto names = dimension_names(p.kind);
      for (std::size_t i = 0; i < names.size() && i < p.dimensions.size(); ++i) {
        const Dimension& d = p.dimensions[i];
        out += "    " + std::string(names[i]) + " " + format_number(d.value_m) + " priority " +
               format_number(d.weight) + " scale " + format_number(d.min_scale) + " " +
               format_number(d.max_scale) + "\n";
      }
      out += "  end\n";
    }
    out += "end\n";
  }
  for (const ExcludeRule& rule : spec.exclude) {
    out += "\nexclude " + rule.name + "\n";
    out += "  shape " + (rule.shape ? std::string(shape_name(*rule.shape)) : std::string("any")) +
           "\n";
    for (const SizeRange& range : rule.ranges) {
      out += "  " + range.dimension;
      if (range.min_m) out += " min " + format_number(*range.min_m);
      if (range.max_m) out += " max " + format_number(*range.max_m);
      out += "\n";
    }
    out += "end\n";
  }
  return out;
}

Result<HapticSpec> read_haptic_file(const std::filesystem::path& path,
                                    std::vector<Diagnostic>* warnings) {
  auto text = read_text_file(path);
  if (!text) return text.error();
  return parse_haptic(*text, path.string(), warnings);
}

Status write_haptic_file(const std::filesystem::path& path, const HapticSpec& spec) {
  // Refuse to write what could not be read back.
  if (auto st = validate_haptic(spec, path.string()); !st) return st;
  return write_file_atomically(path, write_haptic(spec));
}

}  // namespace annex
