#include "annex/authoring/editor_document.h"

#include <cmath>
#include <cstdlib>
#include <iterator>
#include <type_traits>
#include <utility>

#include "annex/authoring/fit.h"
#include "annex/authoring/rank.h"
#include "annex/formats/file_io.h"
#include "annex/formats/haptic_format.h"

namespace annex::authoring {

namespace fs = std::filesystem;

fs::path state_dir() {
  if (const char* d = std::getenv("ANNEX_AUTHOR_STATE_DIR"); d != nullptr && *d != '\0') return d;
  if (const char* d = std::getenv("XDG_STATE_HOME"); d != nullptr && *d != '\0')
    return fs::path(d) / "annex-author";
  if (const char* h = std::getenv("HOME"); h != nullptr && *h != '\0')
    return fs::path(h) / ".local" / "state" / "annex-author";
  return fs::temp_directory_path() / "annex-author";
}

fs::path autosave_path_for(const fs::path& spec_path) {
  return fs::path(spec_path.string() + ".autosave");
}

bool has_recovery(const fs::path& spec_path) {
  std::error_code ec;
  const fs::path side = autosave_path_for(spec_path);
  if (!fs::is_regular_file(side, ec)) return false;
  if (!fs::exists(spec_path, ec)) return true;
  if (fs::last_write_time(side, ec) < fs::last_write_time(spec_path, ec)) return false;
  auto a = read_text_file(side);
  auto b = read_text_file(spec_path);
  return a && b && *a != *b;
}

bool has_untitled_recovery() {
  std::error_code ec;
  return fs::is_regular_file(state_dir() / "untitled.haptic.autosave", ec);
}

std::string unique_primitive_name(const VirtualObject& object, std::string_view base) {
  auto taken = [&](const std::string& n) {
    for (const Primitive& p : object.primitives)
      if (p.name == n) return true;
    return false;
  };
  std::string name(base);
  for (int i = 2; taken(name); ++i) name = std::string(base) + "_" + std::to_string(i);
  return name;
}

std::string unique_object_name(const HapticSpec& spec, std::string_view base) {
  auto taken = [&](const std::string& n) {
    for (const VirtualObject& o : spec.objects)
      if (o.name == n) return true;
    return false;
  };
  std::string name(base.empty() ? "object" : base);
  const std::string stem = name;
  for (int i = 2; taken(name); ++i) name = stem + "_" + std::to_string(i);
  return name;
}

std::string EditorDocument::title() const {
  return (path_.empty() ? std::string("untitled") : path_.filename().string()) +
         (dirty() ? " *" : "");
}

// A mesh path as a spec stores it: relative to the spec's folder when the mesh is in
// that folder's tree or beside it (samples/specs/x.haptic -> ../models/m.obj), so the
// two move together; absolute when the relative path would climb further out of the
// user's tree (../../../usr/share/...), which breaks as soon as the spec moves.
static std::string stored_mesh_path(const fs::path& abs, const fs::path& spec_dir) {
  const fs::path rel = abs.lexically_relative(spec_dir);
  int ups = 0;
  for (const fs::path& part : rel)
    if (part == "..") ++ups;
  return rel.empty() || ups > 1 ? abs.generic_string() : rel.generic_string();
}

fs::path EditorDocument::resolve_mesh_path(const std::string& mesh) const {
  fs::path p(mesh);
  std::error_code ec;
  if (p.is_relative()) p = (path_.empty() ? fs::current_path(ec) : path_.parent_path()) / p;
  return p.lexically_normal();
}

std::string EditorDocument::mesh_reference(const fs::path& file) const {
  std::error_code ec;
  const fs::path abs = fs::absolute(file, ec).lexically_normal();
  if (path_.empty()) return abs.generic_string();
  return stored_mesh_path(abs, path_.parent_path());
}

const MeshData* EditorDocument::source_mesh_for(int object) const {
  if (object < 0 || object >= static_cast<int>(spec_.objects.size())) return nullptr;
  const std::string& m = spec_.objects[object].mesh;
  if (m.empty()) return nullptr;
  auto it = meshes_.find(resolve_mesh_path(m).string());
  return it == meshes_.end() ? nullptr : it->second.get();
}

const MeshData* EditorDocument::mesh_for(int object) const {
  const MeshData* source = source_mesh_for(object);
  const double scale = source != nullptr ? spec_.objects[object].model_scale : 1.0;
  if (source == nullptr || scale == 1.0) return source;
  const auto key = std::make_pair(resolve_mesh_path(spec_.objects[object].mesh).string(), scale);
  auto it = scaled_.find(key);
  if (it == scaled_.end()) {
    MeshData scaled = *source;
    for (float& v : scaled.positions) v = static_cast<float>(v * scale);
    update_bounds(scaled);
    // A slider drag makes many scales: drop the copies no object uses any more (those
    // in use stay, so pointers handed out for them stay valid).
    for (auto e = scaled_.begin(); e != scaled_.end();) {
      bool used = false;
      for (const VirtualObject& v : spec_.objects)
        used = used || (!v.mesh.empty() && v.model_scale == e->first.second &&
                        resolve_mesh_path(v.mesh).string() == e->first.first);
      e = used ? std::next(e) : scaled_.erase(e);
    }
    it = scaled_.emplace(key, std::make_shared<const MeshData>(std::move(scaled))).first;
  }
  return it->second.get();
}

Status EditorDocument::load_mesh(const std::string& mesh) {
  const std::string key = resolve_mesh_path(mesh).string();
  if (meshes_.count(key) != 0) return Ok{};
  auto data = authoring::load_mesh(key);
  if (!data) return data.error();
  meshes_[key] = std::make_shared<const MeshData>(std::move(data).value());
  return Ok{};
}

void EditorDocument::load_meshes() {
  for (const VirtualObject& o : spec_.objects) {
    if (o.mesh.empty()) continue;
    if (Status s = load_mesh(o.mesh); !s)
      warnings_.push_back(s.error().format() + " (object '" + o.name + "' shows primitives only)");
  }
}

namespace {

// When this program started (its libraries were loaded): temporary files of a spec
// written before it are not a save of this editor in progress.
const fs::file_time_type kProgramStart = fs::file_time_type::clock::now();

}  // namespace

void EditorDocument::remove_stale_temporaries_of(const fs::path& spec_path) {
  // The spec's and its autosave sidecar's (autosaves are written the same way).
  for (const fs::path& target : {spec_path, autosave_path_for(spec_path)})
    for (const fs::path& p : remove_stale_temporaries(target, kProgramStart))
      log_.push_back("removed '" + p.string() +
                     "', the temporary file of an interrupted save (it never replaced the " +
                     (target == spec_path ? "spec" : "autosave") + ")");
}

std::vector<std::string> EditorDocument::take_log() {
  return std::exchange(log_, {});
}

Result<EditorDocument> EditorDocument::open(const fs::path& path, bool recover) {
  std::error_code ec;
  const fs::path abs = fs::absolute(path, ec).lexically_normal();
  std::vector<Diagnostic> diags;
  auto saved = read_haptic_file(abs, &diags);
  EditorDocument doc;
  doc.path_ = abs;
  if (recover) {
    std::vector<Diagnostic> rdiags;
    auto rec = read_haptic_file(autosave_path_for(abs), &rdiags);
    if (!rec) return rec.error();
    doc.spec_ = std::move(rec).value();
    // A spec that never reached disk has nothing saved: everything is unsaved.
    if (saved) doc.saved_ = std::move(saved).value();
  } else {
    if (!saved) return saved.error();
    doc.spec_ = std::move(saved).value();
    doc.saved_ = doc.spec_;
  }
  for (const Diagnostic& d : diags) doc.warnings_.push_back(d.format());
  doc.remove_stale_temporaries_of(abs);
  doc.load_meshes();
  if (!doc.spec_.objects.empty()) doc.selection_ = {0, -1};
  return doc;
}

namespace {

bool valid_index(int i, std::size_t n) {
  return i >= 0 && i < static_cast<int>(n);
}

Error edit_error(std::string message) {
  return Error{std::move(message), {}};
}

bool unit_interval(double w) {
  return std::isfinite(w) && w >= 0 && w <= 1;
}

// Identifies edits that may join one undo step while it is open (a slider drag).
std::string merge_key(const Command& c) {
  return std::visit(
      [&](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        const std::string type = std::to_string(c.index());
        if constexpr (std::is_same_v<T, cmd::SetPose> || std::is_same_v<T, cmd::ReplacePrimitive> ||
                      std::is_same_v<T, cmd::RenamePrimitive>)
          return type + "/" + std::to_string(x.object) + "/" + std::to_string(x.primitive);
        else if constexpr (std::is_same_v<T, cmd::SetDimension> ||
                           std::is_same_v<T, cmd::SetScaleLimits>)
          return type + "/" + std::to_string(x.object) + "/" + std::to_string(x.primitive) + "/" +
                 std::to_string(x.dimension);
        else if constexpr (std::is_same_v<T, cmd::SetWeight>)
          return type + "/" + std::to_string(static_cast<int>(x.level)) + "/" +
                 std::to_string(x.object) + "/" + std::to_string(x.primitive) + "/" +
                 std::to_string(x.dimension);
        else if constexpr (std::is_same_v<T, cmd::RenameObject> ||
                           std::is_same_v<T, cmd::SetModelScale>)
          return type + "/" + std::to_string(x.object);
        else
          return {};
      },
      c);
}

}  // namespace

Status EditorDocument::apply(const Command& command) {
  if (const auto* s = std::get_if<cmd::Select>(&command)) {
    const Selection& sel = s->selection;
    if (sel.object != -1 && !valid_index(sel.object, spec_.objects.size()))
      return edit_error("no object " + std::to_string(sel.object));
    if (sel.primitive != -1 &&
        (sel.object == -1 ||
         !valid_index(sel.primitive, spec_.objects[sel.object].primitives.size())))
      return edit_error("no primitive " + std::to_string(sel.primitive));
    selection_ = sel;
    return Ok{};
  }
  if (std::holds_alternative<cmd::EndEdit>(command)) {
    if (!history_.empty()) history_.back().open = false;
    return Ok{};
  }
  if (std::holds_alternative<cmd::Undo>(command)) {
    if (!can_undo()) return Ok{};
    UndoStep& step = history_[--undo_pos_];
    step.open = false;
    spec_ = step.before;
    selection_ = step.selection_before;
    mark_changed();
    return Ok{};
  }
  if (std::holds_alternative<cmd::Redo>(command)) {
    if (!can_redo()) return Ok{};
    const UndoStep& step = history_[undo_pos_++];
    spec_ = step.after;
    selection_ = step.selection_after;
    mark_changed();
    return Ok{};
  }
  return apply_edit(command);
}

Status EditorDocument::apply_edit(const Command& command) {
  HapticSpec next = spec_;
  Selection sel = selection_;
  auto& objects = next.objects;
  auto object_at = [&](int o) -> VirtualObject* {
    return valid_index(o, objects.size()) ? &objects[o] : nullptr;
  };
  auto primitive_at = [&](int o, int p) -> Primitive* {
    VirtualObject* obj = object_at(o);
    return obj != nullptr && valid_index(p, obj->primitives.size()) ? &obj->primitives[p] : nullptr;
  };
  auto dimension_at = [&](int o, int p, int d) -> Dimension* {
    Primitive* prim = primitive_at(o, p);
    return prim != nullptr && valid_index(d, prim->dimensions.size()) ? &prim->dimensions[d]
                                                                      : nullptr;
  };
  const std::string bad_object = "no such object";
  const std::string bad_primitive = "no such primitive";
  const std::string bad_dimension = "no such dimension";

  Status status = std::visit(
      [&](const auto& c) -> Status {
        using T = std::decay_t<decltype(c)>;
        if constexpr (std::is_same_v<T, cmd::ImportMesh>) {
          if (Status s = load_mesh(c.mesh); !s) return s;
          VirtualObject o;
          o.name =
              unique_object_name(next, c.name.empty() ? fs::path(c.mesh).stem().string() : c.name);
          o.mesh = c.mesh;
          // The unit the file states, metres unless it says otherwise (docs/editor.md).
          if (const auto it = meshes_.find(resolve_mesh_path(c.mesh).string());
              it != meshes_.end() && it->second->units.stated)
            o.model_scale = it->second->units.metres_per_unit;
          objects.push_back(std::move(o));
          sel = {static_cast<int>(objects.size()) - 1, -1};
        } else if constexpr (std::is_same_v<T, cmd::AddObject>) {
          VirtualObject o;
          o.name = unique_object_name(next, c.name);
          objects.push_back(std::move(o));
          sel = {static_cast<int>(objects.size()) - 1, -1};
        } else if constexpr (std::is_same_v<T, cmd::RemoveObject>) {
          if (!object_at(c.object)) return edit_error(bad_object);
          objects.erase(objects.begin() + c.object);
          sel = objects.empty()
                    ? Selection{}
                    : Selection{std::min(c.object, static_cast<int>(objects.size()) - 1), -1};
        } else if constexpr (std::is_same_v<T, cmd::RenameObject>) {
          VirtualObject* o = object_at(c.object);
          if (!o) return edit_error(bad_object);
          if (c.name.empty()) return edit_error("an object needs a name");
          o->name = c.name;
        } else if constexpr (std::is_same_v<T, cmd::SetAnnexable>) {
          VirtualObject* o = object_at(c.object);
          if (!o) return edit_error(bad_object);
          o->annexable = c.annexable;
        } else if constexpr (std::is_same_v<T, cmd::AddPrimitive>) {
          VirtualObject* o = object_at(c.object);
          if (!o) return edit_error(bad_object);
          Primitive p;
          if (c.initial) {
            p = *c.initial;
          } else {
            p = make_primitive(
                c.kind, unique_primitive_name(*o, c.name.empty() ? shape_name(c.kind) : c.name));
            // A new primitive wraps the whole mesh, ready to be moved and sized.
            if (const MeshData* mesh = mesh_for(c.object)) {
              const std::vector<Vec3> pts = mesh_points(*mesh);
              if (auto fit = fit_primitive(pts, c.kind)) p = with_fit(std::move(p), *fit);
            }
          }
          o->primitives.push_back(std::move(p));
          sel = {c.object, static_cast<int>(o->primitives.size()) - 1};
        } else if constexpr (std::is_same_v<T, cmd::RemovePrimitive>) {
          if (!primitive_at(c.object, c.primitive)) return edit_error(bad_primitive);
          auto& prims = objects[c.object].primitives;
          prims.erase(prims.begin() + c.primitive);
          sel = {c.object,
                 prims.empty() ? -1 : std::min(c.primitive, static_cast<int>(prims.size()) - 1)};
        } else if constexpr (std::is_same_v<T, cmd::DuplicatePrimitive>) {
          Primitive* p = primitive_at(c.object, c.primitive);
          if (!p) return edit_error(bad_primitive);
          Primitive copy = *p;
          copy.name = unique_primitive_name(objects[c.object], p->name);
          auto& prims = objects[c.object].primitives;
          prims.insert(prims.begin() + c.primitive + 1, std::move(copy));
          sel = {c.object, c.primitive + 1};
        } else if constexpr (std::is_same_v<T, cmd::RenamePrimitive>) {
          Primitive* p = primitive_at(c.object, c.primitive);
          if (!p) return edit_error(bad_primitive);
          if (c.name.empty()) return edit_error("a primitive needs a name");
          p->name = c.name;
        } else if constexpr (std::is_same_v<T, cmd::SetKind>) {
          Primitive* p = primitive_at(c.object, c.primitive);
          if (!p) return edit_error(bad_primitive);
          if (p->kind == c.kind) return Ok{};
          double mean = 0;
          for (const Dimension& d : p->dimensions) mean += d.value_m;
          mean = p->dimensions.empty() ? 0.1 : mean / static_cast<double>(p->dimensions.size());
          Primitive q = make_primitive(c.kind, p->name);
          q.pose = p->pose;
          q.weight = p->weight;
          for (Dimension& d : q.dimensions) d.value_m = mean;
          *p = std::move(q);
        } else if constexpr (std::is_same_v<T, cmd::SetPose>) {
          Primitive* p = primitive_at(c.object, c.primitive);
          if (!p) return edit_error(bad_primitive);
          p->pose = c.pose;
          p->pose.rotation = normalized(c.pose.rotation);
        } else if constexpr (std::is_same_v<T, cmd::SetDimension>) {
          Dimension* d = dimension_at(c.object, c.primitive, c.dimension);
          if (!d) return edit_error(bad_dimension);
          if (!std::isfinite(c.value_m) || c.value_m <= 0)
            return edit_error("a dimension must be greater than 0 m");
          d->value_m = c.value_m;
        } else if constexpr (std::is_same_v<T, cmd::SetScaleLimits>) {
          Dimension* d = dimension_at(c.object, c.primitive, c.dimension);
          if (!d) return edit_error(bad_dimension);
          if (!std::isfinite(c.min_scale) || !std::isfinite(c.max_scale) || c.min_scale <= 0 ||
              c.min_scale > c.max_scale)
            return edit_error("scale limits need 0 < min <= max");
          d->min_scale = c.min_scale;
          d->max_scale = c.max_scale;
        } else if constexpr (std::is_same_v<T, cmd::SetWeight>) {
          if (!unit_interval(c.weight)) return edit_error("a priority weight must be in [0, 1]");
          if (c.level == WeightLevel::object) {
            VirtualObject* o = object_at(c.object);
            if (!o) return edit_error(bad_object);
            o->priority = c.weight;
          } else if (c.level == WeightLevel::primitive) {
            Primitive* p = primitive_at(c.object, c.primitive);
            if (!p) return edit_error(bad_primitive);
            p->weight = c.weight;
          } else {
            Dimension* d = dimension_at(c.object, c.primitive, c.dimension);
            if (!d) return edit_error(bad_dimension);
            d->weight = c.weight;
          }
        } else if constexpr (std::is_same_v<T, cmd::SetRank>) {
          // The order is checked before it indexes anything (fuzz_script found a
          // ranking of fewer items than the object has written out of bounds).
          if (c.level == WeightLevel::object) {
            if (!is_permutation_of_n(c.order, static_cast<int>(objects.size())))
              return edit_error("a ranking must list every object once");
            const std::vector<double> w = weights_from_order(c.order);
            for (std::size_t i = 0; i < w.size(); ++i) objects[i].priority = w[i];
          } else if (c.level == WeightLevel::primitive) {
            VirtualObject* o = object_at(c.object);
            if (!o) return edit_error(bad_object);
            if (!is_permutation_of_n(c.order, static_cast<int>(o->primitives.size())))
              return edit_error("a ranking must list every primitive of the object once");
            const std::vector<double> w = weights_from_order(c.order);
            for (std::size_t i = 0; i < w.size(); ++i) o->primitives[i].weight = w[i];
          } else {
            Primitive* p = primitive_at(c.object, c.primitive);
            if (!p) return edit_error(bad_primitive);
            if (!is_permutation_of_n(c.order, static_cast<int>(p->dimensions.size())))
              return edit_error("a ranking must list every dimension of the primitive once");
            const std::vector<double> w = weights_from_order(c.order);
            for (std::size_t i = 0; i < w.size(); ++i) p->dimensions[i].weight = w[i];
          }
        } else if constexpr (std::is_same_v<T, cmd::ReplacePrimitive>) {
          Primitive* p = primitive_at(c.object, c.primitive);
          if (!p) return edit_error(bad_primitive);
          if (static_cast<int>(c.value.dimensions.size()) != dimension_count(c.value.kind))
            return edit_error("wrong number of dimensions for " +
                              std::string(shape_name(c.value.kind)));
          *p = c.value;
          p->pose.rotation = normalized(p->pose.rotation);
        } else if constexpr (std::is_same_v<T, cmd::SetModelScale>) {
          VirtualObject* o = object_at(c.object);
          if (!o) return edit_error(bad_object);
          if (!std::isfinite(c.model_scale) || c.model_scale <= 0)
            return edit_error("model_scale must be a positive number (metres per mesh unit)");
          // The primitives stay on the mesh: sizes and positions scale with it.
          const double r = c.model_scale / o->model_scale;
          for (Primitive& p : o->primitives) {
            p.pose.position = p.pose.position * r;
            for (Dimension& d : p.dimensions) d.value_m *= r;
          }
          o->model_scale = c.model_scale;
        }
        return Ok{};
      },
      command);
  if (!status) return status;
  if (next == spec_ && sel == selection_) return Ok{};

  const std::string key = merge_key(command);
  if (!key.empty() && undo_pos_ == history_.size() && !history_.empty() && history_.back().open &&
      history_.back().merge_key == key) {
    history_.back().after = next;
    history_.back().selection_after = sel;
  } else {
    history_.resize(undo_pos_);
    if (!history_.empty()) history_.back().open = false;
    history_.push_back({command_label(command), spec_, next, selection_, sel, key, !key.empty()});
    undo_pos_ = history_.size();
  }
  spec_ = std::move(next);
  selection_ = sel;
  mark_changed();
  return Ok{};
}

std::string EditorDocument::undo_label() const {
  return can_undo() ? history_[undo_pos_ - 1].label : std::string();
}
std::string EditorDocument::redo_label() const {
  return can_redo() ? history_[undo_pos_].label : std::string();
}

Status EditorDocument::validate() const {
  return validate_haptic(spec_, path_.empty() ? std::string("<untitled>") : path_.string());
}

Status EditorDocument::save() {
  if (path_.empty()) return Error{"the document has no file yet: use Save As", {}};
  return save_as(path_);
}

namespace {

// Rewrites mesh paths from one spec folder to another, so the files they name stay the same.
void rebase_meshes(HapticSpec& spec, const fs::path& from_dir, const fs::path& to_dir) {
  for (VirtualObject& o : spec.objects) {
    if (o.mesh.empty()) continue;
    fs::path abs(o.mesh);
    if (abs.is_relative()) abs = from_dir / abs;
    o.mesh = stored_mesh_path(abs.lexically_normal(), to_dir);
  }
}

}  // namespace

Status EditorDocument::save_as(const fs::path& path) {
  std::error_code ec;
  const fs::path abs = fs::absolute(path, ec).lexically_normal();
  const fs::path old_dir = path_.empty() ? fs::current_path(ec) : path_.parent_path();
  const fs::path new_dir = abs.parent_path();
  // Mesh paths are stored relative to the spec, so a spec and its meshes move together.
  HapticSpec out = spec_;
  rebase_meshes(out, old_dir, new_dir);
  if (Status v = validate_haptic(out, abs.string()); !v) return v;
  remove_stale_temporaries_of(abs);
  if (Status s = write_haptic_file(abs, out); !s) return s;
  remove_autosave();  // the old sidecar (untitled or the previous name)
  path_ = abs;
  spec_ = out;
  saved_ = out;
  // Undo must not bring back paths relative to the old folder.
  for (UndoStep& step : history_) {
    rebase_meshes(step.before, old_dir, new_dir);
    rebase_meshes(step.after, old_dir, new_dir);
  }
  remove_autosave();
  mark_changed();
  return Ok{};
}

Result<EditorDocument> EditorDocument::recover_untitled() {
  auto rec = read_haptic_file(state_dir() / "untitled.haptic.autosave");
  if (!rec) return rec.error();
  EditorDocument doc;
  doc.spec_ = std::move(rec).value();
  doc.load_meshes();
  if (!doc.spec_.objects.empty()) doc.selection_ = {0, -1};
  return doc;
}

fs::path EditorDocument::autosave_path() const {
  return path_.empty() ? state_dir() / "untitled.haptic.autosave" : autosave_path_for(path_);
}

Status EditorDocument::write_autosave() const {
  if (!dirty()) return Ok{};
  std::error_code ec;
  fs::create_directories(autosave_path().parent_path(), ec);
  HapticSpec out = spec_;
  if (path_.empty())  // an untitled autosave has no folder to be relative to
    for (VirtualObject& o : out.objects)
      if (!o.mesh.empty()) o.mesh = resolve_mesh_path(o.mesh).generic_string();
  return write_file_atomically(autosave_path(), write_haptic(out));
}

void EditorDocument::remove_autosave() const {
  std::error_code ec;
  fs::remove(autosave_path(), ec);
}

}  // namespace annex::authoring
