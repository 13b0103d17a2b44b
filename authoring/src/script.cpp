#include "annex/authoring/script.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <iterator>

#include "annex/authoring/fit.h"
#include "annex/formats/haptic_format.h"

namespace annex::authoring {

bool parse_double(std::string_view text, double& out) {
  if (text.empty()) return false;
  if (text.front() == '+') text.remove_prefix(1);
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc() && ptr == end && std::isfinite(out);
}

Result<std::vector<ScriptLine>> parse_script(std::string_view text, std::string_view origin) {
  std::vector<ScriptLine> lines;
  int line_no = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t eol = std::min(text.find('\n', pos), text.size());
    std::string_view raw = text.substr(pos, eol - pos);
    ++line_no;
    ScriptLine line{line_no, {}};
    std::size_t i = 0;
    while (i < raw.size()) {
      const char ch = raw[i];
      if (ch == ' ' || ch == '\t' || ch == '\r') {
        ++i;
      } else if (ch == '#') {
        break;
      } else if (ch == '"') {
        const std::size_t close = raw.find('"', i + 1);
        if (close == std::string_view::npos)
          return Error{"unterminated quoted string",
                       {std::string(origin), line_no, static_cast<int>(i) + 1}};
        line.words.emplace_back(raw.substr(i + 1, close - i - 1));
        i = close + 1;
      } else {
        std::size_t j = i;
        while (j < raw.size() && raw[j] != ' ' && raw[j] != '\t' && raw[j] != '\r' && raw[j] != '#')
          ++j;
        line.words.emplace_back(raw.substr(i, j - i));
        i = j;
      }
    }
    if (!line.words.empty()) lines.push_back(std::move(line));
    if (eol == text.size()) break;
    pos = eol + 1;
  }
  return lines;
}

namespace {

struct Ctx {
  EditorDocument& doc;
  const ScriptLine& line;
  std::string_view origin;

  Error fail(const std::string& message) const {
    return Error{message, {std::string(origin), line.line, 0}};
  }
  const std::vector<std::string>& w() const { return line.words; }

  Result<double> number(std::size_t i) const {
    double v = 0;
    if (i >= w().size()) return fail("'" + w()[0] + "' needs more arguments");
    if (!parse_double(w()[i], v)) return fail("expected a number, got '" + w()[i] + "'");
    return v;
  }
  Status need(std::size_t n, std::string_view usage) const {
    if (w().size() != n) return fail("usage: " + std::string(usage));
    return Ok{};
  }
  Status run(Command c) const {
    if (Status s = doc.apply(c); !s) return fail(s.error().message);
    doc.apply(cmd::EndEdit{});  // one script line, one undo step
    return Ok{};
  }
  Result<int> find_object(const std::string& name) const {
    const auto& objs = doc.spec().objects;
    for (std::size_t i = 0; i < objs.size(); ++i)
      if (objs[i].name == name) return static_cast<int>(i);
    double idx = 0;
    if (parse_double(name, idx) && idx >= 0 && idx < static_cast<double>(objs.size()) &&
        idx == std::floor(idx))
      return static_cast<int>(idx);
    return fail("no object named '" + name + "'");
  }
  Result<int> find_primitive(int object, const std::string& name) const {
    const auto& prims = doc.spec().objects[object].primitives;
    for (std::size_t i = 0; i < prims.size(); ++i)
      if (prims[i].name == name) return static_cast<int>(i);
    double idx = 0;
    if (parse_double(name, idx) && idx >= 0 && idx < static_cast<double>(prims.size()) &&
        idx == std::floor(idx))
      return static_cast<int>(idx);
    return fail("object '" + doc.spec().objects[object].name + "' has no primitive named '" + name +
                "'");
  }
  Result<ShapeKind> kind(const std::string& name) const {
    if (auto k = shape_from_name(name)) return *k;
    return fail("unknown shape '" + name + "' (sphere, cylinder, cone, torus, box, plane)");
  }
  Result<int> selected_object() const {
    if (doc.selection().object < 0)
      return fail("'" + w()[0] + "' needs a selected object (select NAME)");
    return doc.selection().object;
  }
  Result<Selection> selected_primitive() const {
    const Selection s = doc.selection();
    if (s.object < 0 || s.primitive < 0)
      return fail("'" + w()[0] + "' needs a selected primitive (select OBJECT PRIMITIVE)");
    return s;
  }
  Result<int> dimension(const Selection& s, const std::string& name) const {
    const Primitive& p = doc.spec().objects[s.object].primitives[s.primitive];
    const int d = dimension_index(p.kind, name);
    if (d < 0) return fail(std::string(shape_name(p.kind)) + " has no dimension '" + name + "'");
    return d;
  }
};

}  // namespace

std::optional<double> metres_per_unit(std::string_view unit) {
  if (unit == "mm") return 0.001;
  if (unit == "cm") return 0.01;
  if (unit == "m") return 1.0;
  if (unit == "in") return 0.0254;
  if (unit == "ft") return 0.3048;
  return std::nullopt;
}

double model_height_units(const MeshData& mesh) { return mesh.max.y - mesh.min.y; }

std::string describe_model_size(const EditorDocument& doc, int object) {
  const VirtualObject& o = doc.spec().objects.at(static_cast<std::size_t>(object));
  char buf[256];
  std::snprintf(buf, sizeof buf, "model %s: model_scale %g", o.name.c_str(), o.model_scale);
  std::string out = buf;
  const MeshData* source = doc.source_mesh_for(object);
  const MeshData* scaled = doc.mesh_for(object);
  if (source == nullptr || scaled == nullptr) return out + "; no mesh loaded";
  const Vec3 size = scaled->max - scaled->min;
  std::snprintf(buf, sizeof buf, "; size %.3f x %.3f x %.3f m (x, y up, z); units: ", size.x,
                size.y, size.z);
  return out + buf + source->units.note;
}

namespace {

#define ANNEX_TRY(var, expr)            \
  auto var##_r = (expr);                \
  if (!var##_r) return var##_r.error(); \
  auto var = *var##_r

Status run_set(const Ctx& c) {
  const auto& w = c.w();
  if (w.size() < 3) return c.fail("usage: set KEY VALUE...");
  const std::string& key = w[1];
  if (key == "annexable") {
    ANNEX_TRY(o, c.selected_object());
    if (w[2] != "on" && w[2] != "off" && w[2] != "true" && w[2] != "false")
      return c.fail("set annexable takes on or off");
    return c.run(cmd::SetAnnexable{o, w[2] == "on" || w[2] == "true"});
  }
  if (key == "priority" || (key == "weight" && c.doc.selection().primitive < 0)) {
    ANNEX_TRY(o, c.selected_object());
    ANNEX_TRY(v, c.number(2));
    return c.run(cmd::SetWeight{WeightLevel::object, o, -1, -1, v});
  }
  if (key == "name") {
    if (c.doc.selection().primitive < 0) {
      ANNEX_TRY(o, c.selected_object());
      return c.run(cmd::RenameObject{o, w[2]});
    }
    const Selection s = c.doc.selection();
    return c.run(cmd::RenamePrimitive{s.object, s.primitive, w[2]});
  }
  if (key == "model_scale" || key == "model_units" || key == "model_height") {
    ANNEX_TRY(o, c.selected_object());
    if (Status st = c.need(3, "set " + key + (key == "model_units" ? " mm|cm|m|in|ft" : " VALUE"));
        !st)
      return st;
    double scale = 0;
    if (key == "model_units") {
      const auto metres = metres_per_unit(w[2]);
      if (!metres) return c.fail("unknown unit '" + w[2] + "' (mm, cm, m, in, ft)");
      scale = *metres;
    } else {
      ANNEX_TRY(v, c.number(2));
      if (!(v > 0)) return c.fail(key + " must be positive, got '" + w[2] + "'");
      scale = v;
      if (key == "model_height") {
        const MeshData* mesh = c.doc.source_mesh_for(o);
        if (mesh == nullptr) return c.fail("set model_height needs the object's mesh, and it has none loaded");
        const double h = model_height_units(*mesh);
        if (!(h > 0)) return c.fail("the object's mesh is flat along its up axis (+Y)");
        scale = v / h;
      }
    }
    return c.run(cmd::SetModelScale{o, scale});
  }
  ANNEX_TRY(s, c.selected_primitive());
  const Primitive& prim = c.doc.spec().objects[s.object].primitives[s.primitive];
  if (key == "weight") {
    ANNEX_TRY(v, c.number(2));
    return c.run(cmd::SetWeight{WeightLevel::primitive, s.object, s.primitive, -1, v});
  }
  if (key == "position" || key == "axis") {
    if (Status st = c.need(5, "set " + key + " X Y Z"); !st) return st;
    ANNEX_TRY(x, c.number(2));
    ANNEX_TRY(y, c.number(3));
    ANNEX_TRY(z, c.number(4));
    Pose pose = prim.pose;
    if (key == "position")
      pose.position = {x, y, z};
    else if (norm({x, y, z}) <= 0)
      return c.fail("an axis cannot be zero");
    else
      pose.rotation = rotation_from_z({x, y, z});
    return c.run(cmd::SetPose{s.object, s.primitive, pose});
  }
  if (key == "rotation") {
    if (Status st = c.need(6, "set rotation W X Y Z"); !st) return st;
    ANNEX_TRY(qw, c.number(2));
    ANNEX_TRY(qx, c.number(3));
    ANNEX_TRY(qy, c.number(4));
    ANNEX_TRY(qz, c.number(5));
    Pose pose = prim.pose;
    pose.rotation = {qw, qx, qy, qz};
    return c.run(cmd::SetPose{s.object, s.primitive, pose});
  }
  if (key == "dim_weight") {
    if (Status st = c.need(4, "set dim_weight DIMENSION W"); !st) return st;
    ANNEX_TRY(d, c.dimension(s, w[2]));
    ANNEX_TRY(v, c.number(3));
    return c.run(cmd::SetWeight{WeightLevel::dimension, s.object, s.primitive, d, v});
  }
  if (key == "limits") {
    if (Status st = c.need(5, "set limits DIMENSION MIN MAX"); !st) return st;
    ANNEX_TRY(d, c.dimension(s, w[2]));
    ANNEX_TRY(lo, c.number(3));
    ANNEX_TRY(hi, c.number(4));
    return c.run(cmd::SetScaleLimits{s.object, s.primitive, d, lo, hi});
  }
  if (key == "kind") {
    ANNEX_TRY(k, c.kind(w[2]));
    return c.run(cmd::SetKind{s.object, s.primitive, k});
  }
  // set DIMENSION VALUE
  if (dimension_index(prim.kind, key) >= 0) {
    if (Status st = c.need(3, "set " + key + " METRES"); !st) return st;
    ANNEX_TRY(v, c.number(2));
    return c.run(cmd::SetDimension{s.object, s.primitive, dimension_index(prim.kind, key), v});
  }
  return c.fail("unknown key '" + key +
                "' (annexable, priority, weight, name, model_scale, model_units, model_height, "
                "position, axis, rotation, kind, a dimension name, dim_weight, limits)");
}

Status run_rank(const Ctx& c) {
  const auto& w = c.w();
  if (w.size() < 2) return c.fail("usage: rank objects|primitives|dimensions NAME...");
  std::vector<int> order;
  if (w[1] == "objects") {
    for (std::size_t i = 2; i < w.size(); ++i) {
      ANNEX_TRY(o, c.find_object(w[i]));
      order.push_back(o);
    }
    return c.run(cmd::SetRank{WeightLevel::object, -1, -1, order});
  }
  if (w[1] == "primitives") {
    ANNEX_TRY(o, c.selected_object());
    for (std::size_t i = 2; i < w.size(); ++i) {
      ANNEX_TRY(p, c.find_primitive(o, w[i]));
      order.push_back(p);
    }
    return c.run(cmd::SetRank{WeightLevel::primitive, o, -1, order});
  }
  if (w[1] == "dimensions") {
    ANNEX_TRY(s, c.selected_primitive());
    for (std::size_t i = 2; i < w.size(); ++i) {
      ANNEX_TRY(d, c.dimension(s, w[i]));
      order.push_back(d);
    }
    return c.run(cmd::SetRank{WeightLevel::dimension, s.object, s.primitive, order});
  }
  return c.fail("rank what? objects, primitives or dimensions");
}

Status run_fit(const Ctx& c) {
  const auto& w = c.w();
  ANNEX_TRY(s, c.selected_primitive());
  Primitive prim = c.doc.spec().objects[s.object].primitives[s.primitive];
  const MeshData* mesh = c.doc.mesh_for(s.object);
  if (mesh == nullptr) return c.fail("fit needs the object's mesh, and it has none loaded");
  std::size_t i = 1;
  if (i < w.size() && w[i] != "box") {
    ANNEX_TRY(k, c.kind(w[i]));
    if (k != prim.kind) {
      Primitive q = make_primitive(k, prim.name);
      q.weight = prim.weight;
      prim = q;
    }
    ++i;
  }
  Box3 box;
  bool use_box = false;
  if (i < w.size()) {
    if (w[i] != "box" || w.size() != i + 7)
      return c.fail("usage: fit [KIND] [box X0 Y0 Z0 X1 Y1 Z1]");
    double v[6];
    for (int k = 0; k < 6; ++k) {
      ANNEX_TRY(x, c.number(i + 1 + k));
      v[k] = x;
    }
    box = {{std::min(v[0], v[3]), std::min(v[1], v[4]), std::min(v[2], v[5])},
           {std::max(v[0], v[3]), std::max(v[1], v[4]), std::max(v[2], v[5])}};
    use_box = true;
  }
  const std::vector<Vec3> pts = mesh_points(*mesh, use_box ? &box : nullptr);
  auto fit = fit_primitive(pts, prim.kind);
  if (!fit) return c.fail(fit.error().message);
  return c.run(cmd::ReplacePrimitive{s.object, s.primitive, with_fit(prim, *fit)});
}

}  // namespace

Result<ScriptResult> run_document_command(EditorDocument& doc, const ScriptLine& line,
                                          std::string_view origin) {
  const Ctx c{doc, line, origin};
  const auto& w = line.words;
  const std::string& verb = w.at(0);
  ScriptResult out;
  out.handled = true;
  Status st = Ok{};
  if (verb == "new") {
    doc = EditorDocument{};
  } else if (verb == "open" || verb == "recover") {
    if (Status n = c.need(2, verb + " FILE.haptic"); !n) return n.error();
    auto opened = EditorDocument::open(w[1], verb == "recover");
    if (!opened) return c.fail(opened.error().format());
    doc = std::move(opened).value();
    for (const std::string& warning : doc.warnings()) out.output += warning + "\n";
    for (const std::string& note : doc.take_log()) out.output += note + "\n";
  } else if (verb == "import") {
    if (w.size() != 2 && w.size() != 3) return c.fail("usage: import MESH [NAME]");
    st = c.run(cmd::ImportMesh{doc.mesh_reference(w[1]), w.size() == 3 ? w[2] : ""});
  } else if (verb == "add_object") {
    if (Status n = c.need(2, "add_object NAME"); !n) return n.error();
    st = c.run(cmd::AddObject{w[1]});
  } else if (verb == "select") {
    if (w.size() == 2 && w[1] == "none") {
      st = c.run(cmd::Select{{}});
    } else {
      if (w.size() != 2 && w.size() != 3)
        return c.fail("usage: select OBJECT [PRIMITIVE] | select none");
      ANNEX_TRY(o, c.find_object(w[1]));
      int p = -1;
      if (w.size() == 3) {
        ANNEX_TRY(found, c.find_primitive(o, w[2]));
        p = found;
      }
      st = c.run(cmd::Select{{o, p}});
    }
  } else if (verb == "add") {
    if (w.size() != 2 && w.size() != 3) return c.fail("usage: add KIND [NAME]");
    ANNEX_TRY(o, c.selected_object());
    ANNEX_TRY(k, c.kind(w[1]));
    st = c.run(cmd::AddPrimitive{o, k, std::nullopt, w.size() == 3 ? w[2] : ""});
  } else if (verb == "remove") {
    const Selection s = doc.selection();
    if (s.object < 0) return c.fail("remove needs a selection");
    st = s.primitive >= 0 ? c.run(cmd::RemovePrimitive{s.object, s.primitive})
                          : c.run(cmd::RemoveObject{s.object});
  } else if (verb == "duplicate") {
    ANNEX_TRY(s, c.selected_primitive());
    st = c.run(cmd::DuplicatePrimitive{s.object, s.primitive});
  } else if (verb == "set") {
    st = run_set(c);
  } else if (verb == "rank") {
    st = run_rank(c);
  } else if (verb == "fit") {
    st = run_fit(c);
  } else if (verb == "undo") {
    st = c.run(cmd::Undo{});
  } else if (verb == "redo") {
    st = c.run(cmd::Redo{});
  } else if (verb == "save") {
    if (w.size() > 2) return c.fail("usage: save [FILE.haptic]");
    st = w.size() == 2 ? doc.save_as(w[1]) : doc.save();
    for (const std::string& note : doc.take_log()) out.output += note + "\n";
    if (!st) return c.fail("cannot save: " + st.error().format());
  } else if (verb == "autosave") {
    st = doc.write_autosave();
  } else if (verb == "validate") {
    if (Status v = doc.validate(); !v) return c.fail(v.error().format());
    out.output = "valid\n";
  } else if (verb == "print") {
    out.output = write_haptic(doc.spec());
  } else if (verb == "model") {
    ANNEX_TRY(o, c.selected_object());
    out.output = describe_model_size(doc, o) + "\n";
  } else {
    out.handled = false;
  }
  if (!st) return st.error();
  return out;
}

}  // namespace annex::authoring
