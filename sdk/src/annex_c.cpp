// The C API (annex/annex.h) over the C++ library: handles own C++ values, every entry
// point catches what C++ may throw and turns Results into statuses and annex_errors.
#include "annex/annex.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <map>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "annex/common/object_finder.h"
#include "annex/formats/haptic_format.h"
#include "annex/formats/scene_format.h"
#include "annex/runtime/annex_session.h"
#include "annex/runtime/match_report.h"
#include "annex/runtime/params_validation.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/scanner.h"

struct annex_error {
  annex_status status = ANNEX_INTERNAL_ERROR;
  std::string message;  // formatted
  std::string origin;
  int line = 0;
  int column = 0;
};

struct annex_spec {
  annex::HapticSpec spec;
  std::vector<std::string> warnings;
};

struct annex_frame {
  annex::Frame frame;
};

struct annex_scanner {
  annex::ScanParams params;
};

struct annex_scene {
  annex::PhysicalScene scene;
  // A scan's flat surfaces for virtual panels (ScanResult::surfaces), apart from the
  // objects; empty for a loaded scene and for annex_scene_with_surfaces' result.
  std::vector<annex::PhysicalObject> surfaces;
};

struct annex_match {
  annex::HapticSpec spec;  // names outlive the spec handle
  annex::PhysicalScene scene;
  annex::MatchResult result;
  std::vector<std::optional<size_t>> voter_row;  // spec index -> row of result.table
  std::vector<std::vector<std::string>> explanations;  // [row][physical]
  std::string report;
};

struct annex_session {
  explicit annex_session(annex::AnnexSession s) : session(std::move(s)) {}
  annex::AnnexSession session;
  int pushes = 0;
  std::vector<annex::AnnexedObject> objects;  // after the last push
  std::vector<annex_object> objects_c;        // pointing into `objects`
  struct Event {
    annex_event_kind kind;
    std::string virtual_name, physical_id;
    int frame;
  };
  std::vector<Event> events;
  std::optional<std::string> scan_error;
  annex_frame_info info{};
};

namespace {

using annex::Error;

annex_status fail(annex_error** out, annex_status status, const Error& e) {
  if (out) {
    auto* err = new (std::nothrow) annex_error;
    if (err) {
      err->status = status;
      err->origin = e.location.origin;
      err->line = e.location.line;
      err->column = e.location.column;
      err->message = e.location.origin.empty() ? "error: " + e.message : e.format();
    }
    *out = err;
  }
  return status;
}

annex_status fail(annex_error** out, annex_status status, const std::string& message) {
  return fail(out, status, Error{message, {}});
}

annex_status ok(annex_error** out) {
  if (out) *out = nullptr;
  return ANNEX_OK;
}

// A file read's error: a place in the file is a parse error, none an I/O error.
annex_status file_status(const Error& e) {
  return e.location.line > 0 ? ANNEX_PARSE_ERROR : ANNEX_IO_ERROR;
}

// Runs body, turning exceptions into ANNEX_INTERNAL_ERROR (nothing C++ crosses the ABI).
template <typename F>
annex_status guarded(annex_error** error, F body) {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    return fail(error, ANNEX_INTERNAL_ERROR, "out of memory");
  } catch (const std::exception& e) {
    return fail(error, ANNEX_INTERNAL_ERROR, std::string("internal error: ") + e.what());
  } catch (...) {
    return fail(error, ANNEX_INTERNAL_ERROR, "internal error");
  }
}

annex_status null_argument(annex_error** error, const char* function, const char* what) {
  return fail(error, ANNEX_INVALID_ARGUMENT,
              std::string(function) + ": " + what + " must not be NULL");
}

annex::ScanParams scan_params_from(const annex_scan_params& c) {
  annex::ScanParams p;
  p.camera_tilt_deg = c.camera_tilt_deg;
  p.max_plane_angle_deg = c.max_plane_angle_deg;
  p.min_height_m = c.min_height_m;
  p.max_height_m = c.max_height_m;
  p.max_depth_m = c.max_depth_m;
  p.cluster_tolerance_m = c.cluster_tolerance_m;
  p.min_cluster_points = c.min_cluster_points;
  p.threads = c.threads;
  return p;
}

annex::CameraIntrinsics intrinsics_from(const annex_intrinsics& k) {
  return {k.width, k.height, k.fx, k.fy, k.cx, k.cy};
}

// width x height must be a sane, non-overflowing pixel count.
annex_status check_size(annex_error** error, const char* function, int width, int height) {
  if (width < 1 || height < 1 || static_cast<long long>(width) * height > (1LL << 28))
    return fail(error, ANNEX_INVALID_ARGUMENT,
                std::string(function) + ": a frame of " + std::to_string(width) + " x " +
                    std::to_string(height) + " pixels (want 1 to 2^28 pixels)");
  return ANNEX_OK;
}

// The two-call array protocol (annex.h): `n` items of `what`, written by write(out) when
// the buffer holds them; a sizing call (capacity 0, no buffer) only sets *count.
template <typename T, typename Write>
annex_status two_call_copy(size_t n, T* out, size_t capacity, size_t* count, annex_error** error,
                           const char* function, const char* what, Write write) {
  if (!count) return null_argument(error, function, "count");
  *count = n;
  if (capacity < n) {
    if (capacity == 0 && !out) return ok(error);  // the sizing call
    return fail(error, ANNEX_BUFFER_TOO_SMALL,
                std::string(function) + ": " + std::to_string(n) + " " + what +
                    ", the buffer holds " + std::to_string(capacity));
  }
  if (n > 0) {
    if (!out) return null_argument(error, function, "the buffer");
    write(out);
  }
  return ok(error);
}

template <typename T>
annex_status copy_out(const std::vector<T>& items, T* out, size_t capacity, size_t* count,
                      annex_error** error, const char* function) {
  return two_call_copy(items.size(), out, capacity, count, error, function, "items",
                       [&](T* to) { std::copy(items.begin(), items.end(), to); });
}

// `index` of `size` items (of the `what` named in the message), else the error.
annex_status check_index(annex_error** error, const char* function, size_t index, size_t size,
                         const char* what) {
  if (index < size) return ANNEX_OK;
  return fail(error, ANNEX_INVALID_ARGUMENT,
              std::string(function) + ": index " + std::to_string(index) + " of " +
                  std::to_string(size) + " " + what);
}

void copy3(const annex::Vec3& v, double out[3]) {
  out[0] = v.x;
  out[1] = v.y;
  out[2] = v.z;
}

annex_status make_match(const annex::HapticSpec& spec, const annex::PhysicalScene& scene,
                        annex_match** out, annex_error** error) {
  auto m = std::make_unique<annex_match>();
  m->spec = spec;
  m->scene = scene;
  m->result = annex::match_objects(m->spec, m->scene);
  m->voter_row.assign(m->spec.objects.size(), std::nullopt);
  for (size_t r = 0; r < m->result.voters.size(); ++r) {
    const auto vi = static_cast<size_t>(m->result.voters[r]);
    m->voter_row[vi] = r;
    std::vector<std::string> row;
    for (size_t j = 0; j < m->scene.objects.size() && j < m->result.table[r].size(); ++j)
      row.push_back(annex::format_explanation(m->spec.objects[vi], m->scene.objects[j],
                                              m->result.table[r][j]));
    m->explanations.push_back(std::move(row));
  }
  m->report = annex::format_vote_table(m->spec, m->scene, m->result);
  *out = m.release();
  return ok(error);
}

// The events of one push: props annexed, lost (state turned lost) and released.
void collect_events(annex_session& s, const annex::FrameReport& r, int frame) {
  s.events.clear();
  const std::vector<annex::AnnexedObject>& before = s.objects;
  auto find = [](const std::vector<annex::AnnexedObject>& v, const std::string& name)
      -> const annex::AnnexedObject* {
    for (const annex::AnnexedObject& o : v)
      if (o.virtual_name == name) return &o;
    return nullptr;
  };
  for (const std::string& name : r.released) {
    const annex::AnnexedObject* o = find(before, name);
    s.events.push_back({ANNEX_EVENT_RELEASED, name, o ? o->physical_id : std::string(), frame});
  }
  for (const annex::AnnexedObject& o : r.objects) {
    const annex::AnnexedObject* old = find(before, o.virtual_name);
    const bool same_prop = old && old->physical_id == o.physical_id;
    if (!same_prop) s.events.push_back({ANNEX_EVENT_ANNEXED, o.virtual_name, o.physical_id, frame});
    const bool was_lost = same_prop && old->track.state == annex::TrackingState::lost;
    if (o.track.state == annex::TrackingState::lost && !was_lost)
      s.events.push_back({ANNEX_EVENT_LOST, o.virtual_name, o.physical_id, frame});
  }
}

}  // namespace

extern "C" {

/* ---- Errors and versions ---- */

const char* annex_error_message(const annex_error* e) { return e ? e->message.c_str() : ""; }
annex_status annex_error_status(const annex_error* e) { return e ? e->status : ANNEX_OK; }
const char* annex_error_origin(const annex_error* e) { return e ? e->origin.c_str() : ""; }
int annex_error_line(const annex_error* e) { return e ? e->line : 0; }
int annex_error_column(const annex_error* e) { return e ? e->column : 0; }
void annex_error_destroy(annex_error* e) { delete e; }

const char* annex_status_name(annex_status status) {
  switch (status) {
    case ANNEX_OK: return "ANNEX_OK";
    case ANNEX_INVALID_ARGUMENT: return "ANNEX_INVALID_ARGUMENT";
    case ANNEX_PARSE_ERROR: return "ANNEX_PARSE_ERROR";
    case ANNEX_IO_ERROR: return "ANNEX_IO_ERROR";
    case ANNEX_SCAN_FAILED: return "ANNEX_SCAN_FAILED";
    case ANNEX_BUFFER_TOO_SMALL: return "ANNEX_BUFFER_TOO_SMALL";
    case ANNEX_ABI_MISMATCH: return "ANNEX_ABI_MISMATCH";
    case ANNEX_INTERNAL_ERROR: return "ANNEX_INTERNAL_ERROR";
  }
  return "unknown status";
}

const char* annex_version_string(void) { return ANNEX_VERSION_STRING; }
int annex_abi_version(void) { return ANNEX_ABI_VERSION; }

annex_status annex_check_abi(int expected_abi, annex_error** error) {
  if (expected_abi != ANNEX_ABI_VERSION)
    return fail(error, ANNEX_ABI_MISMATCH,
                "the caller was built for Annex C ABI " + std::to_string(expected_abi) +
                    ", this library " + ANNEX_VERSION_STRING + " has ABI " +
                    std::to_string(ANNEX_ABI_VERSION));
  return ok(error);
}

/* ---- Specs ---- */

annex_status annex_spec_load_file(const char* path, annex_spec** out, annex_error** error) {
  return guarded(error, [&] {
    if (!path) return null_argument(error, "annex_spec_load_file", "path");
    if (!out) return null_argument(error, "annex_spec_load_file", "out");
    std::vector<annex::Diagnostic> warnings;
    annex::Result<annex::HapticSpec> spec = annex::read_haptic_file(path, &warnings);
    if (!spec) return fail(error, file_status(spec.error()), spec.error());
    auto h = std::make_unique<annex_spec>();
    h->spec = std::move(*spec);
    for (const annex::Diagnostic& w : warnings) h->warnings.push_back(w.format());
    *out = h.release();
    return ok(error);
  });
}

annex_status annex_spec_load_text(const char* text, const char* origin, annex_spec** out,
                                  annex_error** error) {
  return guarded(error, [&] {
    if (!text) return null_argument(error, "annex_spec_load_text", "text");
    if (!out) return null_argument(error, "annex_spec_load_text", "out");
    std::vector<annex::Diagnostic> warnings;
    annex::Result<annex::HapticSpec> spec =
        annex::parse_haptic(text, origin ? origin : "<text>", &warnings);
    if (!spec) return fail(error, ANNEX_PARSE_ERROR, spec.error());
    auto h = std::make_unique<annex_spec>();
    h->spec = std::move(*spec);
    for (const annex::Diagnostic& w : warnings) h->warnings.push_back(w.format());
    *out = h.release();
    return ok(error);
  });
}

annex_status annex_spec_validate_text(const char* text, const char* origin, annex_error** error) {
  return guarded(error, [&] {
    if (!text) return null_argument(error, "annex_spec_validate_text", "text");
    annex::Result<annex::HapticSpec> spec = annex::parse_haptic(text, origin ? origin : "<text>");
    if (!spec) return fail(error, ANNEX_PARSE_ERROR, spec.error());
    return ok(error);
  });
}

void annex_spec_destroy(annex_spec* spec) { delete spec; }
size_t annex_spec_object_count(const annex_spec* s) { return s ? s->spec.objects.size() : 0; }
const char* annex_spec_object_name(const annex_spec* s, size_t i) {
  return s && i < s->spec.objects.size() ? s->spec.objects[i].name.c_str() : nullptr;
}
double annex_spec_object_model_scale(const annex_spec* s, size_t i) {
  return s && i < s->spec.objects.size() ? s->spec.objects[i].model_scale : 0.0;
}
size_t annex_spec_warning_count(const annex_spec* s) { return s ? s->warnings.size() : 0; }
const char* annex_spec_warning(const annex_spec* s, size_t i) {
  return s && i < s->warnings.size() ? s->warnings[i].c_str() : nullptr;
}

/* ---- Frames ---- */

void annex_intrinsics_init(annex_intrinsics* k) {
  if (!k) return;
  const annex::CameraIntrinsics d;
  *k = annex_intrinsics{d.width, d.height, d.fx, d.fy, d.cx, d.cy};
}

annex_status annex_frame_from_points(const float* xyz, int width, int height, const uint8_t* rgb,
                                     annex_frame** out, annex_error** error) {
  return guarded(error, [&] {
    if (!xyz) return null_argument(error, "annex_frame_from_points", "xyz");
    if (!out) return null_argument(error, "annex_frame_from_points", "out");
    if (annex_status s = check_size(error, "annex_frame_from_points", width, height)) return s;
    auto h = std::make_unique<annex_frame>();
    h->frame.width = width;
    h->frame.height = height;
    const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
    h->frame.points.resize(n);
    for (size_t i = 0; i < n; ++i) {
      annex::PointXYZRGB& p = h->frame.points[i];
      p.x = xyz[3 * i];
      p.y = xyz[3 * i + 1];
      p.z = xyz[3 * i + 2];
      if (rgb) {
        p.r = rgb[3 * i];
        p.g = rgb[3 * i + 1];
        p.b = rgb[3 * i + 2];
      } else {
        p.r = p.g = p.b = 128;
      }
    }
    *out = h.release();
    return ok(error);
  });
}

annex_status annex_frame_from_depth(const uint16_t* depth, int width, int height,
                                    const annex_intrinsics* intrinsics, double depth_scale_m,
                                    const uint8_t* rgb, annex_frame** out, annex_error** error) {
  return guarded(error, [&] {
    const char* fn = "annex_frame_from_depth";
    if (!depth) return null_argument(error, fn, "depth");
    if (!intrinsics) return null_argument(error, fn, "intrinsics");
    if (!out) return null_argument(error, fn, "out");
    if (annex_status s = check_size(error, fn, width, height)) return s;
    const annex::CameraIntrinsics k = intrinsics_from(*intrinsics);
    if (annex::Status s = annex::validate_intrinsics(k, "intrinsics"); !s)
      return fail(error, ANNEX_INVALID_ARGUMENT, std::string(fn) + ": " + s.error().message);
    if (k.width != width || k.height != height)
      return fail(error, ANNEX_INVALID_ARGUMENT,
                  std::string(fn) + ": the intrinsics are for " + std::to_string(k.width) +
                      " x " + std::to_string(k.height) + ", the depth image is " +
                      std::to_string(width) + " x " + std::to_string(height));
    if (!(depth_scale_m > 0) || !std::isfinite(depth_scale_m))
      return fail(error, ANNEX_INVALID_ARGUMENT,
                  std::string(fn) + ": depth_scale_m must be greater than 0 (0.001 for "
                                    "millimetres), got " + std::to_string(depth_scale_m));
    auto h = std::make_unique<annex_frame>();
    h->frame.width = width;
    h->frame.height = height;
    h->frame.points.resize(static_cast<size_t>(width) * static_cast<size_t>(height));
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (int v = 0; v < height; ++v)
      for (int u = 0; u < width; ++u) {
        const size_t i = static_cast<size_t>(v) * static_cast<size_t>(width) + static_cast<size_t>(u);
        annex::PointXYZRGB& p = h->frame.points[i];
        if (depth[i] == 0) {
          p.x = p.y = p.z = nan;
        } else {
          const double z = depth[i] * depth_scale_m;
          p.x = static_cast<float>((u - k.cx) * z / k.fx);
          p.y = static_cast<float>((v - k.cy) * z / k.fy);
          p.z = static_cast<float>(z);
        }
        if (rgb) {
          p.r = rgb[3 * i];
          p.g = rgb[3 * i + 1];
          p.b = rgb[3 * i + 2];
        } else {
          p.r = p.g = p.b = 128;
        }
      }
    *out = h.release();
    return ok(error);
  });
}

annex_status annex_frame_load_pcd(const char* path, annex_frame** out, annex_error** error) {
  return guarded(error, [&] {
    if (!path) return null_argument(error, "annex_frame_load_pcd", "path");
    if (!out) return null_argument(error, "annex_frame_load_pcd", "out");
    annex::Result<annex::Frame> frame = annex::read_pcd(path);
    if (!frame) return fail(error, file_status(frame.error()), frame.error());
    auto h = std::make_unique<annex_frame>();
    h->frame = std::move(*frame);
    *out = h.release();
    return ok(error);
  });
}

void annex_frame_destroy(annex_frame* frame) { delete frame; }
int annex_frame_width(const annex_frame* f) { return f ? f->frame.width : 0; }
int annex_frame_height(const annex_frame* f) { return f ? f->frame.height : 0; }

annex_status annex_frame_points(const annex_frame* f, float* xyz, size_t capacity, size_t* count,
                                annex_error** error) {
  return guarded(error, [&] {
    if (!f) return null_argument(error, "annex_frame_points", "frame");
    const std::vector<annex::PointXYZRGB>& points = f->frame.points;
    return two_call_copy(points.size() * 3, xyz, capacity, count, error, "annex_frame_points",
                         "floats", [&](float* to) {
                           for (size_t i = 0; i < points.size(); ++i) {
                             to[3 * i] = points[i].x;
                             to[3 * i + 1] = points[i].y;
                             to[3 * i + 2] = points[i].z;
                           }
                         });
  });
}

/* ---- Scanning ---- */

void annex_scan_params_init(annex_scan_params* c) {
  if (!c) return;
  const annex::ScanParams p;
  *c = annex_scan_params{p.camera_tilt_deg,     p.max_plane_angle_deg, p.min_height_m,
                         p.max_height_m,        p.max_depth_m,         p.cluster_tolerance_m,
                         p.min_cluster_points,  p.threads};
}

annex_status annex_scanner_create(const annex_scan_params* params, annex_scanner** out,
                                  annex_error** error) {
  return guarded(error, [&] {
    if (!out) return null_argument(error, "annex_scanner_create", "out");
    annex_scan_params c;
    annex_scan_params_init(&c);
    if (params) c = *params;
    const annex::ScanParams p = scan_params_from(c);
    if (annex::Status s = annex::validate_scan_params(p, "annex_scan_params"); !s)
      return fail(error, ANNEX_INVALID_ARGUMENT, s.error());
    *out = new annex_scanner{p};
    return ok(error);
  });
}

annex_status annex_scanner_create_from_config(const char* path, annex_scanner** out,
                                              annex_error** error) {
  return guarded(error, [&] {
    if (!path) return null_argument(error, "annex_scanner_create_from_config", "path");
    if (!out) return null_argument(error, "annex_scanner_create_from_config", "out");
    annex::Result<annex::ScanParams> p = annex::read_scan_config_file(path);
    if (!p) return fail(error, file_status(p.error()), p.error());
    if (annex::Status s = annex::validate_scan_params(*p, path); !s)
      return fail(error, ANNEX_INVALID_ARGUMENT, s.error());
    *out = new annex_scanner{*p};
    return ok(error);
  });
}

void annex_scanner_destroy(annex_scanner* scanner) { delete scanner; }

annex_status annex_scan(annex_scanner* scanner, const annex_frame* frame, annex_scene** out,
                        annex_error** error) {
  return guarded(error, [&] {
    if (!scanner) return null_argument(error, "annex_scan", "scanner");
    if (!frame) return null_argument(error, "annex_scan", "frame");
    if (!out) return null_argument(error, "annex_scan", "out");
    annex::Result<annex::ScanResult> r = annex::scan_frame(frame->frame, scanner->params);
    if (!r) return fail(error, ANNEX_SCAN_FAILED, r.error());
    *out = new annex_scene{std::move(r->scene), std::move(r->surfaces)};
    return ok(error);
  });
}

/* ---- Scenes ---- */

annex_status annex_scene_load_file(const char* path, annex_scene** out, annex_error** error) {
  return guarded(error, [&] {
    if (!path) return null_argument(error, "annex_scene_load_file", "path");
    if (!out) return null_argument(error, "annex_scene_load_file", "out");
    annex::Result<annex::PhysicalScene> scene = annex::read_scene_file(path);
    if (!scene) return fail(error, file_status(scene.error()), scene.error());
    *out = new annex_scene{std::move(*scene), {}};
    return ok(error);
  });
}

void annex_scene_destroy(annex_scene* scene) { delete scene; }
size_t annex_scene_object_count(const annex_scene* s) { return s ? s->scene.objects.size() : 0; }

annex_status annex_scene_object(const annex_scene* s, size_t index, annex_physical_object* out,
                                annex_error** error) {
  return guarded(error, [&] {
    if (!s) return null_argument(error, "annex_scene_object", "scene");
    if (!out) return null_argument(error, "annex_scene_object", "out");
    if (annex_status st =
            check_index(error, "annex_scene_object", index, s->scene.objects.size(), "objects"))
      return st;
    const annex::PhysicalObject& o = s->scene.objects[index];
    *out = annex_physical_object{o.id.c_str(), static_cast<int>(o.primitives.size()),
                                 o.point_count, o.fit};
    return ok(error);
  });
}

annex_status annex_scene_primitive(const annex_scene* s, size_t object, size_t primitive,
                                   annex_primitive* out, annex_error** error) {
  return guarded(error, [&] {
    if (!s) return null_argument(error, "annex_scene_primitive", "scene");
    if (!out) return null_argument(error, "annex_scene_primitive", "out");
    if (object >= s->scene.objects.size() ||
        primitive >= s->scene.objects[object].primitives.size())
      return fail(error, ANNEX_INVALID_ARGUMENT,
                  "annex_scene_primitive: no primitive " + std::to_string(primitive) +
                      " of object " + std::to_string(object));
    const annex::PhysicalPrimitive& p = s->scene.objects[object].primitives[primitive];
    annex_primitive c{};
    c.shape = static_cast<annex_shape>(p.kind);
    c.shape_name = annex::shape_name(p.kind).data();  // names are string literals
    const auto names = annex::dimension_names(p.kind);
    c.dimension_count = static_cast<int>(std::min({size_t{3}, names.size(), p.dimensions_m.size()}));
    for (int d = 0; d < c.dimension_count; ++d) {
      c.dimension_names[d] = names[static_cast<size_t>(d)].data();
      c.dimensions_m[d] = p.dimensions_m[static_cast<size_t>(d)];
    }
    copy3(p.center, c.center);
    copy3(p.axis, c.axis);
    c.fit = p.fit;
    *out = c;
    return ok(error);
  });
}

const char* annex_scene_object_on(const annex_scene* s, size_t index) {
  return s && index < s->scene.objects.size() ? s->scene.objects[index].on_object.c_str()
                                              : nullptr;
}

size_t annex_scene_surface_count(const annex_scene* s) { return s ? s->surfaces.size() : 0; }

annex_status annex_scene_with_surfaces(const annex_scene* s, annex_scene** out,
                                       annex_error** error) {
  return guarded(error, [&] {
    if (!s) return null_argument(error, "annex_scene_with_surfaces", "scene");
    if (!out) return null_argument(error, "annex_scene_with_surfaces", "out");
    annex::PhysicalScene scene = s->scene;
    scene.objects.insert(scene.objects.end(), s->surfaces.begin(), s->surfaces.end());
    *out = new annex_scene{std::move(scene), {}};
    return ok(error);
  });
}

int annex_scene_primitive_x_axis(const annex_scene* s, size_t object, size_t primitive,
                                 double x_axis[3]) {
  if (!s || object >= s->scene.objects.size() ||
      primitive >= s->scene.objects[object].primitives.size())
    return 0;
  const annex::PhysicalPrimitive& p = s->scene.objects[object].primitives[primitive];
  if (p.kind != annex::ShapeKind::plane || annex::norm(p.x_axis) == 0) return 0;
  if (x_axis) copy3(p.x_axis, x_axis);
  return 1;
}

int annex_scene_support(const annex_scene* s, double normal[3], double* d) {
  if (!s || !s->scene.support) return 0;
  if (normal) copy3(s->scene.support->normal, normal);
  if (d) *d = s->scene.support->d;
  return 1;
}

/* ---- Matching ---- */

annex_status annex_match_objects(const annex_spec* spec, const annex_scene* scene,
                                 annex_match** out, annex_error** error) {
  return guarded(error, [&] {
    if (!spec) return null_argument(error, "annex_match_objects", "spec");
    if (!scene) return null_argument(error, "annex_match_objects", "scene");
    if (!out) return null_argument(error, "annex_match_objects", "out");
    return make_match(spec->spec, scene->scene, out, error);
  });
}

void annex_match_destroy(annex_match* match) { delete match; }
size_t annex_match_count(const annex_match* m) { return m ? m->result.matches.size() : 0; }

annex_status annex_match_entry_at(const annex_match* m, size_t index, annex_match_entry* out,
                                  annex_error** error) {
  return guarded(error, [&] {
    if (!m) return null_argument(error, "annex_match_entry_at", "match");
    if (!out) return null_argument(error, "annex_match_entry_at", "out");
    if (annex_status st = check_index(error, "annex_match_entry_at", index,
                                      m->result.matches.size(), "entries"))
      return st;
    const annex::MatchEntry& e = m->result.matches[index];
    const auto vi = static_cast<size_t>(e.virtual_index);
    out->virtual_name = m->spec.objects.at(vi).name.c_str();
    out->physical_id =
        e.physical_index
            ? m->scene.objects.at(static_cast<size_t>(*e.physical_index)).id.c_str()
            : nullptr;
    out->vote = e.vote;
    return ok(error);
  });
}

const char* annex_match_explanation(const annex_match* m, size_t v, size_t p) {
  if (!m || v >= m->voter_row.size() || !m->voter_row[v]) return nullptr;
  const std::vector<std::string>& row = m->explanations[*m->voter_row[v]];
  return p < row.size() ? row[p].c_str() : nullptr;
}

const char* annex_match_report(const annex_match* m) { return m ? m->report.c_str() : ""; }

/* ---- Sessions ---- */

void annex_session_params_init(annex_session_params* c) {
  if (!c) return;
  const annex::SessionParams p;
  *c = annex_session_params{};
  annex_scan_params_init(&c->scan);
  c->scan_every = p.scan_every;
  c->release_after_frames = p.release_after_frames;
  c->threads = p.threads;
  c->min_vote = p.match.min_vote;
  c->background_scan = 1;
  c->has_intrinsics = 0;
  annex_intrinsics_init(&c->intrinsics);
}

namespace {

// The session of `spec` with `params` (defaults for NULL), its scan's parameters `scan`.
annex_status create_session(const annex_spec* spec, const annex_session_params* params,
                            const annex::ScanParams& scan, annex_session** out,
                            annex_error** error) {
  annex_session_params c;
  annex_session_params_init(&c);
  if (params) c = *params;
  annex::SessionParams p;
  p.scan = scan;
  p.scan_every = c.scan_every;
  p.release_after_frames = c.release_after_frames;
  p.threads = c.threads;
  p.match.min_vote = c.min_vote;
  p.scan_mode = c.background_scan ? annex::ScanMode::background : annex::ScanMode::same_frame;
  if (c.has_intrinsics) p.camera = intrinsics_from(c.intrinsics);
  annex::Result<annex::AnnexSession> s = annex::AnnexSession::create(spec->spec, p);
  if (!s) return fail(error, ANNEX_INVALID_ARGUMENT, s.error());
  *out = new annex_session(std::move(*s));
  return ok(error);
}

}  // namespace

annex_status annex_session_create(const annex_spec* spec, const annex_session_params* params,
                                  annex_session** out, annex_error** error) {
  return guarded(error, [&] {
    if (!spec) return null_argument(error, "annex_session_create", "spec");
    if (!out) return null_argument(error, "annex_session_create", "out");
    annex_scan_params scan;
    annex_scan_params_init(&scan);
    if (params) scan = params->scan;
    return create_session(spec, params, scan_params_from(scan), out, error);
  });
}

annex_status annex_session_create_with_scan_config(const annex_spec* spec,
                                                   const annex_session_params* params,
                                                   const char* scan_config_path,
                                                   annex_session** out, annex_error** error) {
  return guarded(error, [&] {
    constexpr const char* kName = "annex_session_create_with_scan_config";
    if (!spec) return null_argument(error, kName, "spec");
    if (!scan_config_path) return null_argument(error, kName, "scan_config_path");
    if (!out) return null_argument(error, kName, "out");
    annex::Result<annex::ScanParams> scan = annex::read_scan_config_file(scan_config_path);
    if (!scan) return fail(error, file_status(scan.error()), scan.error());
    if (annex::Status s = annex::validate_scan_params(*scan, scan_config_path); !s)
      return fail(error, ANNEX_INVALID_ARGUMENT, s.error());
    if (params) scan->threads = params->scan.threads;
    return create_session(spec, params, *scan, out, error);
  });
}

void annex_session_destroy(annex_session* session) { delete session; }

annex_status annex_session_push(annex_session* s, const annex_frame* frame, annex_error** error) {
  return guarded(error, [&] {
    if (!s) return null_argument(error, "annex_session_push", "session");
    if (!frame) return null_argument(error, "annex_session_push", "frame");
    if (frame->frame.points.empty())
      return fail(error, ANNEX_INVALID_ARGUMENT, "annex_session_push: the frame has no points");
    const int index = s->pushes++;
    annex::FrameReport r = s->session.process(frame->frame, index);
    collect_events(*s, r, index);
    s->objects = std::move(r.objects);
    s->objects_c.clear();
    for (const annex::AnnexedObject& o : s->objects) {
      annex_object c{};
      c.virtual_name = o.virtual_name.c_str();
      c.physical_id = o.physical_id.c_str();
      c.virtual_index = o.virtual_index;
      c.state = static_cast<annex_tracking_state>(o.track.state);
      c.confidence = o.track.confidence;
      c.vote = o.vote;
      const annex::ModelPose pose =
          annex::decompose_model_transform(annex::world_from_model(s->session.spec(), o));
      copy3(pose.translation, c.position);
      c.rotation[0] = pose.rotation.w;
      c.rotation[1] = pose.rotation.x;
      c.rotation[2] = pose.rotation.y;
      c.rotation[3] = pose.rotation.z;
      copy3(pose.scale, c.scale);
      c.matched_frame = o.matched_frame;
      s->objects_c.push_back(c);
    }
    s->scan_error.reset();
    if (r.scan_error) s->scan_error = r.scan_error->format();
    annex_frame_info& info = s->info;
    info = annex_frame_info{};
    info.frame = index;
    info.scan_applied = r.scanned ? 1 : 0;
    info.scan_frame = r.scanned ? r.scan_frame_index : -1;
    info.scan_failed = r.scan_error ? 1 : 0;
    info.scan_error = s->scan_error ? s->scan_error->c_str() : nullptr;
    info.matched = r.match ? 1 : 0;
    info.scan_ms = r.times.scan_ms;
    info.track_ms = r.times.track_ms;
    info.total_ms = r.times.total_ms;
    return ok(error);
  });
}

annex_status annex_session_objects(const annex_session* s, annex_object* out, size_t capacity,
                                   size_t* count, annex_error** error) {
  return guarded(error, [&] {
    if (!s) return null_argument(error, "annex_session_objects", "session");
    return copy_out(s->objects_c, out, capacity, count, error, "annex_session_objects");
  });
}

annex_status annex_session_events(const annex_session* s, annex_event* out, size_t capacity,
                                  size_t* count, annex_error** error) {
  return guarded(error, [&] {
    if (!s) return null_argument(error, "annex_session_events", "session");
    std::vector<annex_event> events;
    for (const annex_session::Event& e : s->events)
      events.push_back({e.kind, e.virtual_name.c_str(), e.physical_id.c_str(), e.frame});
    return copy_out(events, out, capacity, count, error, "annex_session_events");
  });
}

annex_status annex_session_frame_info(const annex_session* s, annex_frame_info* out,
                                      annex_error** error) {
  return guarded(error, [&] {
    if (!s) return null_argument(error, "annex_session_frame_info", "session");
    if (!out) return null_argument(error, "annex_session_frame_info", "out");
    if (s->pushes == 0)
      return fail(error, ANNEX_INVALID_ARGUMENT,
                  "annex_session_frame_info: no frame has been pushed yet");
    *out = s->info;
    return ok(error);
  });
}

/* ---- Unity ---- */

void annex_pose_to_unity(const double position[3], const double q[4], double unity_position[3],
                         double unity_rotation_xyzw[4]) {
  if (position && unity_position) {
    const double p[3] = {position[0], -position[1], position[2]};
    std::memcpy(unity_position, p, sizeof p);
  }
  if (q && unity_rotation_xyzw) {
    const double r[4] = {-q[1], q[2], -q[3], q[0]};
    std::memcpy(unity_rotation_xyzw, r, sizeof r);
  }
}

}  // extern "C"
