// annex-runtime scan CLOUD.pcd: the scanner on one frame (docs/perception.md).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "annex/formats/scene_format.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/plane_candidates.h"
#include "annex/runtime/scan_overlay.h"
#include "annex/runtime/scan_workers.h"
#include "annex/runtime/scanner.h"
#include "commands.h"
#include "depth_options.h"
#include "scan_options.h"

namespace annex::cli {
namespace {

std::string num(double x, int digits = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  std::string s = buf;
  if (s == "-0.0000") s = "0.0000";
  return s;
}

std::string vec(Vec3 v) { return num(v.x) + "," + num(v.y) + "," + num(v.z); }

// up: the normal of the support the object stands on, which a cone's `narrows` is read
// against (up: a lampshade, a cone on its base; down: a cup, a bowl, a flower pot).
std::string primitive_fields(const PhysicalPrimitive& p, const std::optional<Vec3>& up = {}) {
  std::string out(shape_name(p.kind));
  const auto names = dimension_names(p.kind);
  for (size_t k = 0; k < names.size() && k < p.dimensions_m.size(); ++k)
    out.append(" ").append(names[k]).append("=").append(num(p.dimensions_m[k]));
  if (p.kind == ShapeKind::cone && p.narrow_radius_m > 0)
    out.append(" narrow_radius=").append(num(p.narrow_radius_m));
  out.append(" center=").append(vec(p.center)).append(" axis=").append(vec(p.axis));
  if (p.kind == ShapeKind::cone && up && norm(p.axis) > 0) {
    // The axis runs from the wide end to the narrow one.
    const double c = dot(normalized(p.axis), normalized(*up));
    out.append(" narrows=").append(c > 0.7 ? "up" : c < -0.7 ? "down" : "side");
  }
  if (p.kind == ShapeKind::plane) out.append(" x_axis=").append(vec(p.x_axis));
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

int run_scan(const std::vector<std::string>& args) {
  const auto parsed = parse_args("scan", args,
                                 {{"explain"},
                                  {"scene", "png", "config", "repeat", "color", "intrinsics",
                                   "depth-scale", "supports", "depth-noise"}});
  if (!parsed) return kExitBadInput;
  if (parsed->positional.size() != 1) {
    std::cerr << "annex-runtime scan: error: expected one CLOUD.pcd or DEPTH.png (see --help)\n";
    return kExitBadInput;
  }
  long repeat = 0;
  if (auto v = parsed->get("repeat")) {
    const auto n = parse_count("scan", "repeat", *v);
    if (!n) return kExitBadInput;
    repeat = *n;
  }
  std::optional<ScanParams> options = read_scan_options("scan", *parsed);
  if (!options) return kExitBadInput;
  ScanParams params = *options;
  if (auto v = parsed->get("supports")) {
    Result<ScanParams> chosen = with_support_selection(params, *v);
    if (!chosen) {
      std::cerr << "annex-runtime scan: error: --" << chosen.error().message << "\n";
      return kExitBadInput;
    }
    params = *chosen;
  }
  FrameSourceParams depth_params;
  if (!read_depth_options("scan", *parsed, depth_params)) return kExitBadInput;
  const Result<Frame> frame = read_frame_file(parsed->positional[0], *parsed, depth_params);
  if (!frame) {
    std::cerr << frame.error().format() << "\n";
    return kExitBadInput;
  }
  ScanWorkers workers;  // kept for --repeat's scans
  Result<ScanResult> scan = scan_frame(*frame, params, workers);
  if (!scan) {
    Error e = scan.error();
    e.location.origin = parsed->positional[0];
    std::cerr << e.format() << "\n";
    return kExitFailure;
  }
  const ScanResult& r = *scan;
  const Plane& pl = r.plane;
  std::cout << "plane normal=" << vec(pl.normal) << " d=" << num(pl.d)
            << " points=" << r.plane_inliers << "\n";
  for (const SupportSurface& s : r.scene.supports)
    std::cout << "support " << s.id << " normal=" << vec(s.plane.normal) << " d=" << num(s.plane.d)
              << " points=" << s.point_count << "\n";
  for (size_t i = 0; i < r.scene.objects.size(); ++i) {
    const PhysicalObject& o = r.scene.objects[i];
    std::optional<Vec3> up;
    for (const SupportSurface& sp : r.scene.supports)
      if (sp.id == o.support_id) up = sp.plane.normal;
    const std::string tail = " support=" + o.support_id +
                             (o.on_object.empty() ? "" : " on=" + o.on_object) +
                             (o.partial ? " partial=1" : "");
    if (o.primitives.empty()) {
      std::cout << "object " << o.id << " unknown points=" << o.point_count << " fit=0" << tail
                << "\n";
    } else {
      std::cout << "object " << o.id << " " << primitive_fields(o.primitives[0], up)
                << " points=" << o.point_count << " fit=" << num(o.fit, 2) << tail << "\n";
      for (size_t k = 1; k < o.primitives.size(); ++k)
        std::cout << "part " << o.id << " " << primitive_fields(o.primitives[k], up)
                  << " fit=" << num(o.primitives[k].fit, 2) << "\n";
    }
    if (parsed->has("explain") && i < r.clusters.size())
      for (const ShapeFit& c : r.clusters[i].shape.candidates)
        std::cout << "  candidate " << o.id << " " << primitive_fields(c.primitive)
                  << " coverage=" << num(c.coverage, 2) << " rms_mm=" << num(c.rms_m * 1000, 1)
                  << "\n";
  }
  for (const PhysicalObject& o : r.surfaces)
    if (!o.primitives.empty())
      std::cout << "surface " << o.id << " " << primitive_fields(o.primitives[0])
                << " points=" << o.point_count << " support=" << o.support_id
                << (o.partial ? " partial=1" : "") << "\n";
  if (r.scene.objects.empty())
    std::cerr << "annex-runtime scan: note: no objects stand on the " << r.scene.supports.size()
              << " support(s) found (" << r.plane_inliers
              << " points on the first). A support seen only in part may need a hull margin: "
                 "--config samples/config/room.conf\n";
  if (repeat > 0) {
    std::map<std::string, std::vector<double>> stage_ms;
    std::vector<std::string> order;
    std::vector<double> totals;
    for (long i = 0; i < repeat; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      const Result<ScanResult> again = scan_frame(*frame, params, workers);
      totals.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      if (!again) continue;
      for (const StageTime& s : again->stages) {
        if (!stage_ms.count(s.name)) order.push_back(s.name);
        stage_ms[s.name].push_back(s.ms);
      }
    }
    for (const std::string& name : order)
      std::cout << "stage " << name << " median_ms=" << num(median(stage_ms[name]), 2) << "\n";
    std::cout << "total median_ms=" << num(median(totals), 2) << "\n";
  }
  if (auto path = parsed->get("scene")) {
    create_parent_dirs(*path);
    const Status s = write_scene_file(*path, scene_with_surfaces(r));
    if (!s) {
      std::cerr << s.error().format() << "\n";
      return kExitBadInput;
    }
  }
  if (auto path = parsed->get("png")) {
    create_parent_dirs(*path);
    const Status s = write_png(*path, draw_scan_overlay(*frame, r));
    if (!s) {
      std::cerr << s.error().format() << "\n";
      return kExitBadInput;
    }
  }
  return kExitOk;
}

}  // namespace

extern const Command kScanCommand = {
    "scan", "find the table plane and the objects on it in one depth frame",
    "usage: annex-runtime scan (CLOUD.pcd | DEPTH.png [--color RGB.png]\n"
    "                          [--intrinsics fx,fy,cx,cy] [--depth-scale S])\n"
    "                          [--scene OUT.scene] [--png OUT.png] [--config FILE]\n"
    "                          [--depth-noise NAME] [--supports WHICH] [--explain]\n"
    "                          [--repeat N]\n"
    "\n"
    "Finds every near-horizontal support (floor, table, shelf, seat), the objects\n"
    "standing on each and each object's primitives (sphere, cylinder, cone or frustum,\n"
    "torus, box). Prints\n"
    "  plane normal=x,y,z d=D points=N                 (the first support)\n"
    "  support <id> normal=x,y,z d=D points=N           (one per support)\n"
    "  object <id> <shape> <dim>=<metres>... center=x,y,z axis=x,y,z points=N fit=F\n"
    "         support=<id> [partial=1]\n"
    "  part <id> <shape> <dim>=<metres>... center=x,y,z axis=x,y,z fit=F   (secondary)\n"
    "  surface <id> plane size_x=X size_y=Y center=x,y,z axis=x,y,z x_axis=x,y,z\n"
    "          points=N support=<id>     (a flat surface for a virtual panel: a box's top\n"
    "          '<object>.top', a support's free rectangle '<support>.free')\n"
    "with ids p1, p2, ... left to right in the image; an object with no fitting shape\n"
    "prints 'object <id> unknown points=N fit=0 support=<id>'. partial=1: cut by the\n"
    "image border or seen by too few points; such objects do not vote by default.\n"
    "\n"
    "A depth frame is a PCD cloud or a 16-bit depth PNG, back-projected through the\n"
    "intrinsics (default the Kinect's 525,525,319.5,239.5) with value / S = metres:\n"
    "  --color RGB.png    the colour image registered to DEPTH.png\n"
    "  --intrinsics LIST  fx,fy,cx,cy in pixels\n"
    "  --depth-scale S    stored value per metre (default 1000; TUM RGB-D 5000)\n"
    "  --scene OUT.scene  write the objects, then the surfaces, as a scene file\n"
    "                     (docs/scene-format.md)\n"
    "  --png OUT.png      write the camera view with objects coloured and "
    "outlined\n" ANNEX_SCAN_OPTIONS_HELP
    "  --supports WHICH   whose objects: all (within support_reach_m, the default),\n"
    "                     nearest, highest, largest, or a support id such as s2\n"
    "  --explain          after each object, every shape tried: 'candidate <id> <shape>\n"
    "                     <dim>=<metres>... coverage=C rms_mm=R' (the highest score wins;\n"
    "                     docs/perception.md)\n"
    "  --repeat N         run the pipeline N more times; print per-stage medians\n"
    "                     'stage <name> median_ms=<x>' and 'total median_ms=<x>'\n"
    "\n"
    "Exit status: 0 ok, 1 no horizontal plane in the frame, 2 bad arguments or input.\n",
    run_scan};

}  // namespace annex::cli
