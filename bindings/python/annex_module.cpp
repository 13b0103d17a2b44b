// `import annex`: the C++ library for Python (pybind11), numpy arrays in and out.
// Points are (H, W, 3) float32 arrays in the sensor frame (metres, x right, y down,
// z forward, NaN where the sensor saw nothing). Failures raise annex.Error with the
// library's "file:line:col: error: ..." message.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "annex/common/object_finder.h"
#include "annex/formats/haptic_format.h"
#include "annex/runtime/annex_session.h"
#include "annex/runtime/match_report.h"
#include "annex/runtime/params_validation.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/scanner.h"
#include "annex/version.h"

namespace py = pybind11;

namespace {

struct AnnexError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <typename T>
T unwrap(annex::Result<T> r) {
  if (!r) throw AnnexError(r.error().format());
  return std::move(r).value();
}

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

annex::Frame frame_from_array(const FloatArray& points) {
  if (points.ndim() != 3 || points.shape(2) != 3)
    throw py::value_error("points must be an (H, W, 3) array of x, y, z, got " +
                          std::to_string(points.ndim()) + " dimensions");
  if (points.shape(0) < 1 || points.shape(1) < 1 || points.shape(0) * points.shape(1) > (1 << 28))
    throw py::value_error("points must hold 1 to 2^28 pixels");
  annex::Frame f;
  f.height = static_cast<int>(points.shape(0));
  f.width = static_cast<int>(points.shape(1));
  const float* p = points.data();
  f.points.resize(static_cast<size_t>(f.width) * static_cast<size_t>(f.height));
  for (size_t i = 0; i < f.points.size(); ++i) {
    f.points[i].x = p[3 * i];
    f.points[i].y = p[3 * i + 1];
    f.points[i].z = p[3 * i + 2];
    f.points[i].r = f.points[i].g = f.points[i].b = 128;
  }
  return f;
}

py::array_t<float> array_from_frame(const annex::Frame& f) {
  py::array_t<float> out({static_cast<py::ssize_t>(f.height), static_cast<py::ssize_t>(f.width),
                          py::ssize_t{3}});
  float* p = out.mutable_data();
  for (size_t i = 0; i < f.points.size(); ++i) {
    p[3 * i] = f.points[i].x;
    p[3 * i + 1] = f.points[i].y;
    p[3 * i + 2] = f.points[i].z;
  }
  return out;
}

py::array_t<double> vec(const annex::Vec3& v) {
  py::array_t<double> a(3);
  double* p = a.mutable_data();
  p[0] = v.x;
  p[1] = v.y;
  p[2] = v.z;
  return a;
}

py::dict dims_of(const annex::PhysicalPrimitive& p) {
  py::dict d;
  const auto names = annex::dimension_names(p.kind);
  for (size_t i = 0; i < names.size() && i < p.dimensions_m.size(); ++i)
    d[py::str(std::string(names[i]))] = p.dimensions_m[i];
  return d;
}

annex::ScanParams scan_params(const std::optional<std::string>& config) {
  annex::ScanParams p = config ? unwrap(annex::read_scan_config_file(*config)) : annex::ScanParams{};
  if (annex::Status s = annex::validate_scan_params(p); !s) throw AnnexError(s.error().format());
  return p;
}

annex::PhysicalScene scene_from(const std::vector<annex::PhysicalObject>& objects) {
  annex::PhysicalScene scene;
  scene.objects = objects;
  return scene;
}

// One match row as Python sees it.
struct PyMatch {
  std::string virtual_name;
  std::optional<std::string> physical_id;
  double vote = 0;
  std::string explanation;  // the chosen pair's breakdown; "" when virtual-only
};

// An annexed object with the virtual model's pose in the sensor frame: position,
// rotation (w, x, y, z), per-axis scale, and the 4x4 model-to-sensor matrix.
struct PyAnnexed {
  std::string virtual_name, physical_id, state;
  double confidence = 0, vote = 0;
  int matched_frame = 0;
  py::array_t<double> position, rotation, scale, matrix;
};

PyAnnexed annexed(const annex::HapticSpec& spec, const annex::AnnexedObject& o) {
  PyAnnexed x;
  x.virtual_name = o.virtual_name;
  x.physical_id = o.physical_id;
  x.state = std::string(annex::tracking_state_name(o.track.state));
  x.confidence = o.track.confidence;
  x.vote = o.vote;
  x.matched_frame = o.matched_frame;
  const annex::Affine a = annex::world_from_model(spec, o);
  const annex::ModelPose p = annex::decompose_model_transform(a);
  x.position = vec(p.translation);
  x.rotation = py::array_t<double>(4);
  double* q = x.rotation.mutable_data();
  q[0] = p.rotation.w;
  q[1] = p.rotation.x;
  q[2] = p.rotation.y;
  q[3] = p.rotation.z;
  x.scale = vec(p.scale);
  x.matrix = py::array_t<double>({4, 4});
  // Affine holds the top three rows (row-major 3x4); the fourth is 0 0 0 1.
  double* m = x.matrix.mutable_data();
  for (int i = 0; i < 12; ++i) m[i] = a.m[static_cast<size_t>(i)];
  m[12] = m[13] = m[14] = 0;
  m[15] = 1;
  return x;
}

struct PySession {
  annex::AnnexSession session;
  int frames = 0;
};

}  // namespace

PYBIND11_MODULE(annex, m) {
  m.doc() = "Annex: scan a depth frame into primitive-shaped props, match haptic specs to "
            "them, track them (docs/embedding.md)";
  m.attr("__version__") = ANNEX_VERSION_STRING;
  py::register_exception<AnnexError>(m, "Error", PyExc_ValueError);

  py::class_<annex::PhysicalPrimitive>(m, "Primitive")
      .def_property_readonly("shape", [](const annex::PhysicalPrimitive& p) {
        return std::string(annex::shape_name(p.kind));
      })
      .def_property_readonly("dims", &dims_of)
      .def_property_readonly("center", [](const annex::PhysicalPrimitive& p) { return vec(p.center); })
      .def_property_readonly("axis", [](const annex::PhysicalPrimitive& p) { return vec(p.axis); })
      // A plane's size_x direction, in its plane; zeros for other shapes.
      .def_property_readonly("x_axis", [](const annex::PhysicalPrimitive& p) { return vec(p.x_axis); })
      .def_readonly("fit", &annex::PhysicalPrimitive::fit);

  py::class_<annex::PhysicalObject>(m, "PhysicalObject")
      .def_readonly("id", &annex::PhysicalObject::id)
      .def_readonly("primitives", &annex::PhysicalObject::primitives)
      .def_readonly("point_count", &annex::PhysicalObject::point_count)
      .def_readonly("fit", &annex::PhysicalObject::fit)
      // The id of the object it stands on ("" on the support itself).
      .def_readonly("on_object", &annex::PhysicalObject::on_object)
      // The salient primitive's shape, dimensions (metres) and centre.
      .def_property_readonly("shape", [](const annex::PhysicalObject& o) {
        return o.primitives.empty() ? std::string("unknown")
                                    : std::string(annex::shape_name(o.primitives[0].kind));
      })
      .def_property_readonly("dims", [](const annex::PhysicalObject& o) {
        return o.primitives.empty() ? py::dict() : dims_of(o.primitives[0]);
      })
      .def_property_readonly("center", [](const annex::PhysicalObject& o) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        return o.primitives.empty() ? vec({nan, nan, nan}) : vec(o.primitives[0].center);
      })
      .def("__repr__", [](const annex::PhysicalObject& o) {
        return "<annex.PhysicalObject " + o.id + " " +
               (o.primitives.empty() ? "unknown" : std::string(annex::shape_name(o.primitives[0].kind))) +
               ">";
      });

  py::class_<annex::HapticSpec>(m, "Spec")
      .def_property_readonly("names", [](const annex::HapticSpec& s) {
        std::vector<std::string> names;
        for (const annex::VirtualObject& v : s.objects) names.push_back(v.name);
        return names;
      })
      // Metres per mesh unit of each virtual object (spec order; the `model_scale` key).
      .def_property_readonly("model_scales", [](const annex::HapticSpec& s) {
        std::vector<double> scales;
        for (const annex::VirtualObject& v : s.objects) scales.push_back(v.model_scale);
        return scales;
      })
      .def("__len__", [](const annex::HapticSpec& s) { return s.objects.size(); })
      .def("__str__", [](const annex::HapticSpec& s) { return annex::write_haptic(s); });

  py::class_<PyMatch>(m, "Match")
      .def_readonly("virtual", &PyMatch::virtual_name)
      .def_readonly("physical", &PyMatch::physical_id)
      .def_readonly("vote", &PyMatch::vote)
      .def_readonly("explanation", &PyMatch::explanation)
      .def("__repr__", [](const PyMatch& x) {
        return "<annex.Match " + x.virtual_name + " -> " + x.physical_id.value_or("(none)") + ">";
      });

  py::class_<PyAnnexed>(m, "AnnexedObject")
      .def_readonly("virtual", &PyAnnexed::virtual_name)
      .def_readonly("physical", &PyAnnexed::physical_id)
      .def_readonly("state", &PyAnnexed::state)
      .def_readonly("confidence", &PyAnnexed::confidence)
      .def_readonly("vote", &PyAnnexed::vote)
      .def_readonly("matched_frame", &PyAnnexed::matched_frame)
      .def_readonly("position", &PyAnnexed::position)
      .def_readonly("rotation", &PyAnnexed::rotation)
      .def_readonly("scale", &PyAnnexed::scale)
      .def_readonly("matrix", &PyAnnexed::matrix)
      .def("__repr__", [](const PyAnnexed& o) {
        return "<annex.AnnexedObject " + o.virtual_name + " on " + o.physical_id + " " + o.state + ">";
      });

  m.def("load_pcd", [](const std::string& path) { return array_from_frame(unwrap(annex::read_pcd(path))); },
        py::arg("path"), "Reads a .pcd file into an (H, W, 3) float32 array (unorganized: H = 1).");

  m.def("read_spec", [](const std::string& path) { return unwrap(annex::read_haptic_file(path)); },
        py::arg("path"), "Reads and validates a .haptic spec.");
  m.def("parse_spec",
        [](const std::string& text, const std::string& origin) {
          return unwrap(annex::parse_haptic(text, origin));
        },
        py::arg("text"), py::arg("origin") = "<text>");

  m.def("scan",
        [](const FloatArray& points, std::optional<std::string> config, bool surfaces) {
          const annex::Frame f = frame_from_array(points);
          annex::ScanParams p = scan_params(config);
          p.plane_candidates = surfaces;
          py::gil_scoped_release unlocked;
          const annex::ScanResult r = unwrap(annex::scan_frame(f, p));
          return annex::scene_with_surfaces(r).objects;
        },
        py::arg("points"), py::arg("config") = py::none(), py::arg("surfaces") = false,
        "The physical objects on the support in an organized frame, left to right "
        "(config: a scan.conf path); with surfaces=True followed by the flat surfaces a "
        "virtual panel may lie on (s1.free, p3.top, p1.face: one plane each), for match().");

  m.def("match",
        [](const annex::HapticSpec& spec, const std::vector<annex::PhysicalObject>& objects) {
          const annex::PhysicalScene scene = scene_from(objects);
          const annex::MatchResult r = annex::match_objects(spec, scene);
          std::vector<PyMatch> out;
          for (const annex::MatchEntry& e : r.matches) {
            PyMatch x;
            x.virtual_name = spec.objects.at(static_cast<size_t>(e.virtual_index)).name;
            x.vote = e.vote;
            if (e.physical_index) {
              const auto j = static_cast<size_t>(*e.physical_index);
              x.physical_id = scene.objects[j].id;
              for (size_t row = 0; row < r.voters.size(); ++row)
                if (r.voters[row] == e.virtual_index)
                  x.explanation = annex::format_explanation(
                      spec.objects[static_cast<size_t>(e.virtual_index)], scene.objects[j],
                      r.table[row][j]);
            }
            out.push_back(std::move(x));
          }
          return out;
        },
        py::arg("spec"), py::arg("objects"),
        "One Match per virtual object, spec order: the Voter and Hungarian assignment.");

  py::class_<PySession>(m, "Session")
      .def(py::init([](const annex::HapticSpec& spec, int scan_every, int release_after_frames,
                       int threads, bool background, std::optional<std::string> config) {
             annex::SessionParams p;
             p.scan = config ? unwrap(annex::read_scan_config_file(*config)) : annex::ScanParams{};
             p.scan_every = scan_every;
             p.release_after_frames = release_after_frames;
             p.threads = threads;
             p.scan_mode = background ? annex::ScanMode::background : annex::ScanMode::same_frame;
             return new PySession{unwrap(annex::AnnexSession::create(spec, p))};
           }),
           py::arg("spec"), py::arg("scan_every") = 10, py::arg("release_after_frames") = 45,
           py::arg("threads") = 2, py::arg("background") = false, py::arg("config") = py::none())
      .def("process",
           [](PySession& s, const FloatArray& points) {
             const annex::Frame f = frame_from_array(points);
             py::gil_scoped_release unlocked;
             const annex::FrameReport r = s.session.process(f, s.frames++);
             py::gil_scoped_acquire locked;
             std::vector<PyAnnexed> out;
             for (const annex::AnnexedObject& o : r.objects) out.push_back(annexed(s.session.spec(), o));
             return out;
           },
           py::arg("points"), "One frame: the annexed objects after it, spec order.")
      .def("wait_for_scan", [](PySession& s) {
        py::gil_scoped_release unlocked;
        s.session.wait_for_scan();
      });
}
