// annex-bench-scan: the scanner's figures for docs/BENCHMARKS.md and docs/perception.md.
//   speed     our organized pipeline vs the paper's straightforward PCL pipeline on the
//             same frame (real milk_cartoon scan when ../shared is present, and a
//             generated scene), per-stage medians;
//   accuracy  shape class accuracy and size errors on a larger generated set;
//   ransac    CGAL Efficient RANSAC (the paper's detector) vs ObjectShapeRecognizer on
//             the same clusters: class accuracy, size error, time per cluster.
//   world     the widened generator: class, size, support and cone direction per
//             distance band, a confusion matrix per shape, false props and slivers.
// Usage: annex-bench-scan [--repeat N] [--pcl-repeat N] [--threads N] [--scenes N] [--world N]
//        [--world-seed FIRST] [--rooms] [--skip-pcl] [--world-only] [--speed-only]
//        [--pool-per-scan] [--verbose] [--png-dir DIR] [--scan-conf FILE] [--downsample N]
//        [--render-scale S] [--sensor NAME] [--flying SHARE] [--stacked SHARE]
//        [--everyday SHARE] [--lying SHARE]
//        (--repeat: our scans per frame, 30; --pcl-repeat: PCL's, interleaved with ours,
//        default max(5, repeat / 3); --threads: our worker threads, 2; --speed-only: the
//        speed section alone, e.g. under callgrind; --pool-per-scan: every scan starts its
//        own worker threads (scan_frame without ScanWorkers, as before session 8); --verbose: every
//        world-set miss, misclassification, leg and sliver; --png-dir: the world scenes' pictures,
//        frames and truth (.truth.scene);
//        --world-seed: the world set's first seed, 2001: the tuned set; 5001: held out;
//        --rooms: room_scene_params, table heights 0.4-1.1 m, a rolled camera, chairs,
//        shelves and objects on their boards, objects on the floor, touching, across a table
//        edge, dark; --downsample N: the world set's frames as a sensor of 1/N the
//        resolution sees them, every N-th pixel of every N-th row; --render-scale S: rendered
//        by a camera of S times the Kinect's resolution and focal length, 0.25 to 3;
//        --sensor NAME: rendered with another camera's depth noise, kinect, stereo or tof
//        (depth_noise.h); the scan's own model is the config's depth_noise; --flying SHARE:
//        that share of the edge pixels kept return a depth between their two surfaces
//        (SensorNoiseParams::flying_share: a time-of-flight or stereo camera's mixed
//        pixels); --stacked SHARE: that share of the boxes and cylinders carry an object on
//        their top (stacked_share); --everyday SHARE: that share of the cylinders are mugs
//        or bottles, of the cones narrowing down cups with a handle (everyday_share; the
//        features mug, bottle and cup); --lying SHARE: that share of the plain cylinders on
//        the table or a furniture top rest on their side (lying_share; the feature lying))
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "annex/formats/scene_format.h"
#include "annex/reference/object_shape_recognizer_cgal.h"
#include "annex/reference/scanner_pcl_reference.h"
#include "annex/runtime/depth_noise.h"
#include "annex/runtime/object_shape_recognizer.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/scan_overlay.h"
#include "annex/runtime/scan_workers.h"
#include "annex/runtime/scanner.h"
#include "annex/runtime/synthetic_scene.h"

namespace {

// The benchmarks time and score the objects: no flat surfaces for virtual panels (the
// PCL reference pipeline finds none either).
annex::ScanParams objects_only() {
  annex::ScanParams p;
  p.plane_candidates = false;
  return p;
}

using namespace annex;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}

double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return in ? one + " " + five + " " + fifteen : std::string("unknown");
}

// One pipeline's runs: per-stage wall times, wall and CPU (all threads) per run.
struct Timings {
  const char* name = "";
  std::map<std::string, std::vector<double>> stages;
  std::vector<std::string> order;
  std::vector<double> wall, cpu;
  int objects = 0;
  bool failed = false;

  template <typename Run>
  void run(const Frame& frame, Run pipeline) {
    if (failed) return;
    const double c0 = cpu_ms();
    const auto t0 = Clock::now();
    const Result<ScanResult> r = pipeline(frame);
    wall.push_back(ms_since(t0));
    cpu.push_back(cpu_ms() - c0);
    if (!r) {
      std::printf("  %s: %s\n", name, r.error().format().c_str());
      failed = true;
      return;
    }
    objects = static_cast<int>(r->scene.objects.size());
    for (const StageTime& s : r->stages) {
      if (!stages.count(s.name)) order.push_back(s.name);
      stages[s.name].push_back(s.ms);
    }
  }
  void print() const {
    if (wall.empty()) return;
    std::printf("  %-10s objects=%d", name, objects);
    for (const std::string& s : order) std::printf("  %s=%.1f", s.c_str(), median(stages.at(s)));
    std::printf("\n  %-10s wall median_ms=%.1f min_ms=%.1f  cpu median_ms=%.1f min_ms=%.1f  (%zu runs)\n",
                "", median(wall), *std::min_element(wall.begin(), wall.end()), median(cpu),
                *std::min_element(cpu.begin(), cpu.end()), wall.size());
  }
};

// Both pipelines in one run, interleaved: each PCL run follows an equal share of ours,
// so a change of load hits both alike. Medians and minimums of each, and their ratios.
// `pool_per_scan`: each scan starts and joins its own helper threads (scan_frame without
// ScanWorkers) instead of keeping one set across the run, as a session does.
void speed(const Frame& frame, const char* label, int repeat, int pcl_repeat, int threads,
           bool pool_per_scan) {
  std::printf("speed on %s (%dx%d), load average %s, worker threads %s:\n", label, frame.width,
              frame.height, load_average().c_str(), pool_per_scan ? "started per scan" : "kept across scans");
  ScanParams params = objects_only();
  params.threads = threads;
  Timings ours, theirs;
  ours.name = "annex";
  theirs.name = "pcl-paper";
  ScanWorkers workers;
  auto annex = [&](const Frame& f) {
    return pool_per_scan ? scan_frame(f, params) : scan_frame(f, params, workers);
  };
  auto pcl = [](const Frame& f) { return scan_frame_pcl_reference(f); };
  // The same scan with the flat surfaces for virtual panels (plane_candidates: on in
  // `annex-runtime scan` and in a session whose spec holds a plane), each run beside one
  // of ours: what `scan` takes, apart from the comparison with PCL, which finds none.
  ScanParams with_surfaces = params;
  with_surfaces.plane_candidates = true;
  Timings surfaces;
  surfaces.name = "annex+surf";
  auto annex_surfaces = [&](const Frame& f) {
    return pool_per_scan ? scan_frame(f, with_surfaces) : scan_frame(f, with_surfaces, workers);
  };
  ours.run(frame, annex);  // warm-up: first-touch allocations, caches
  surfaces.run(frame, annex_surfaces);
  ours = Timings{};
  ours.name = "annex";
  surfaces = Timings{};
  surfaces.name = "annex+surf";
  const int rounds = std::max(1, pcl_repeat);
  for (int r = 0; r < rounds; ++r) {
    const int share = repeat * (r + 1) / rounds - repeat * r / rounds;
    for (int i = 0; i < share; ++i) {
      ours.run(frame, annex);
      surfaces.run(frame, annex_surfaces);
    }
    if (pcl_repeat > 0) theirs.run(frame, pcl);
  }
  ours.print();
  surfaces.print();
  if (!ours.wall.empty() && !surfaces.wall.empty() && !ours.failed && !surfaces.failed)
    std::printf("  flat surfaces add: wall median %.1f ms, cpu median %.1f ms\n",
                median(surfaces.wall) - median(ours.wall), median(surfaces.cpu) - median(ours.cpu));
  theirs.print();
  if (!ours.wall.empty() && !theirs.wall.empty() && !ours.failed && !theirs.failed) {
    auto lo = [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); };
    std::printf("  pcl / annex: wall medians %.1fx, wall mins %.1fx, cpu medians %.1fx, cpu mins "
                "%.1fx (threads=%d; load average at the end %s)\n",
                median(theirs.wall) / median(ours.wall), lo(theirs.wall) / lo(ours.wall),
                median(theirs.cpu) / median(ours.cpu), lo(theirs.cpu) / lo(ours.cpu), threads,
                load_average().c_str());
  }
}

struct TruthMatch {
  const PhysicalPrimitive* truth = nullptr;
  size_t cluster = 0;
};

// Each true object's nearest scanned cluster (by position on the table), within 6 cm.
std::vector<TruthMatch> match_truth(const PhysicalScene& truth, const ScanResult& scan) {
  std::vector<TruthMatch> out;
  const Vec3 n = truth.support->normal;
  for (const PhysicalObject& t : truth.objects) {
    const PhysicalPrimitive& tp = t.primitives.at(0);
    double best = 0.06;
    int pick = -1;
    for (size_t k = 0; k < scan.clusters.size(); ++k) {
      Vec3 c;
      for (const Vec3& p : scan.clusters[k].points) c = c + p;
      c = c * (1.0 / std::max<size_t>(1, scan.clusters[k].points.size()));
      if (!scan.scene.objects[k].primitives.empty()) c = scan.scene.objects[k].primitives[0].center;
      const Vec3 d = c - tp.center;
      const double dist = norm(d - n * dot(d, n));
      if (dist < best) {
        best = dist;
        pick = static_cast<int>(k);
      }
    }
    if (pick >= 0) out.push_back({&tp, static_cast<size_t>(pick)});
  }
  return out;
}

struct Tally {
  int objects = 0, found = 0, correct = 0;
  std::vector<double> errors;
  std::map<std::string, int> confusion;
  std::vector<double> ms;
  void add(const PhysicalPrimitive& truth, const std::vector<PhysicalPrimitive>& got) {
    ++found;
    const std::string g = got.empty() ? "unknown" : std::string(shape_name(got[0].kind));
    ++confusion[std::string(shape_name(truth.kind)) + " -> " + g];
    if (got.empty() || got[0].kind != truth.kind) return;
    ++correct;
    std::vector<double> a = truth.dimensions_m, b = got[0].dimensions_m;
    if (a.size() != b.size()) return;
    if (truth.kind == ShapeKind::box) {
      std::sort(a.begin(), a.begin() + 2);
      std::sort(b.begin(), b.begin() + 2);
    }
    for (size_t i = 0; i < a.size(); ++i) errors.push_back(std::abs(a[i] - b[i]));
  }
  void print(const char* name) const {
    std::printf("  %-10s objects=%d found=%d class_accuracy=%.1f%% median_size_error_mm=%.2f "
                "p90_size_error_mm=%.2f",
                name, objects, found, objects ? 100.0 * correct / objects : 0.0,
                1000 * median(errors), 1000 * percentile(errors, 0.9));
    if (!ms.empty()) std::printf(" median_ms_per_cluster=%.2f", median(ms));
    std::printf("\n");
    for (const auto& [k, v] : confusion) std::printf("      %-22s %d\n", k.c_str(), v);
  }
};

SyntheticFrame synthetic(std::uint64_t seed) {
  SyntheticSceneParams p;
  p.seed = seed;
  const Result<SyntheticScene> scene = generate_scene(p);
  if (!scene) {
    std::fprintf(stderr, "generate_scene(%llu): %s\n", static_cast<unsigned long long>(seed),
                 scene.error().format().c_str());
    std::exit(1);
  }
  SyntheticFrame f = render_scene(*scene);
  return f;
}

// Normals the way the scanner computes them are not exposed per cluster; both
// recognizers get the smoothed points, CGAL estimates jet normals itself (as in the
// paper's pipeline and FIELD-NOTES' measurement).
void accuracy_and_ransac(int scenes, int cgal_scenes) {
  Tally ours, cgal, ours_same;
  std::vector<double> scan_ms;
  for (int seed = 1; seed <= scenes; ++seed) {
    const SyntheticFrame f = synthetic(1000 + seed);
    const auto t0 = Clock::now();
    const Result<ScanResult> scan = scan_frame(f.frame, objects_only());
    scan_ms.push_back(ms_since(t0));
    if (!scan) {
      ours.objects += static_cast<int>(f.truth.objects.size());
      continue;
    }
    ours.objects += static_cast<int>(f.truth.objects.size());
    const std::vector<TruthMatch> matches = match_truth(f.truth, *scan);
    for (const TruthMatch& m : matches) ours.add(*m.truth, scan->scene.objects[m.cluster].primitives);
    if (seed > cgal_scenes) continue;
    cgal.objects += static_cast<int>(f.truth.objects.size());
    ours_same.objects += static_cast<int>(f.truth.objects.size());
    for (const TruthMatch& m : matches) {
      const ScanCluster& c = scan->clusters[m.cluster];
      auto t1 = Clock::now();
      const ObjectShape mine = recognize_object_shape(c.points, {}, scan->plane);
      ours_same.ms.push_back(ms_since(t1));
      std::vector<PhysicalPrimitive> mp;
      for (const ShapeFit& s : mine.primitives) mp.push_back(s.primitive);
      ours_same.add(*m.truth, mp);
      t1 = Clock::now();
      const ObjectShape theirs = recognize_object_shape_cgal(c.points, {});
      cgal.ms.push_back(ms_since(t1));
      std::vector<PhysicalPrimitive> tp;
      for (const ShapeFit& s : theirs.primitives) tp.push_back(s.primitive);
      cgal.add(*m.truth, tp);
    }
  }
  std::printf("accuracy on %d generated scenes (seeds 1001-%d), full scan:\n", scenes,
              1000 + scenes);
  ours.print("annex");
  std::printf("  scan median_ms=%.1f per frame\n", median(scan_ms));
  std::printf("ransac comparison on the clusters of %d scenes (same smoothed points, no "
              "scanner normals: jet normals k=18 for CGAL, none for ours):\n",
              cgal_scenes);
  ours_same.print("annex");
  cgal.print("cgal-eff");
}

// The widened generator (world_scene_params): floor, legs, a second support, tall
// furniture, cameras 0.5-3 m away and 0-60 degrees down, cones either way up, flat and
// cut, objects across the border. Objects are matched by the labels of their pixels:
// a scanned object stands for the truth object most of its pixels show.
struct BandTally {
  int objects = 0, found = 0, correct = 0, direction_right = 0, cones = 0, support_right = 0;
  int flagged_partial = 0;  // found whole objects the scan flagged partial (they do not vote)
  std::vector<double> errors;
  // The scanned support under each found object against its truth support: the angle
  // between their normals (degrees) and the scanned plane's height at the truth foot (m).
  std::vector<double> support_tilt_deg, support_foot_m;
};

std::string truth_class(const PhysicalPrimitive& p) {
  std::string name(shape_name(p.kind));
  if (p.kind != ShapeKind::cone) return name;
  const bool down = p.axis.y > 0;  // camera y points down; the axis runs wide to narrow
  name += down ? " apex-down" : " apex-up";
  if (p.narrow_radius_m > 0) name += " frustum";
  if (p.dimensions_m[1] < 2 * p.dimensions_m[0]) name += " flat";
  return name;
}

const char* background_name(int label) {
  switch (label) {
    case kLabelLeg: return "leg";
    case kLabelFurniture: return "furniture";
    case kLabelChair: return "chair";
    case kLabelShelf: return "shelf";
    case kLabelBackChair:
      return "back chair";
    case kLabelCabinet:
      return "cabinet";
    case kLabelPole:
      return "pole";
    default: return "background";
  }
}

// A false prop's footing, for --verbose: its points' heights above its support (lowest
// and highest, cm) and what the pixel two rows under each column's lowest one shows
// (the label most columns see there).
std::string footing_note(const SyntheticFrame& f, const ScanCluster& c) {
  double lo = 1e9, hi = -1e9;
  std::map<int, int> lowest, below;
  const int w = f.frame.width;
  for (int i : c.pixels) {
    const PointXYZRGB& p = f.frame.points[static_cast<size_t>(i)];
    if (!std::isfinite(p.z)) continue;
    const double h = dot(c.support.normal, Vec3{p.x, p.y, p.z}) + c.support.d;
    lo = std::min(lo, h), hi = std::max(hi, h);
    auto [it, fresh] = lowest.try_emplace(i % w, i);
    if (!fresh) it->second = std::max(it->second, i);
  }
  for (const auto& [col, i] : lowest) {
    const size_t j = static_cast<size_t>(i + 2 * w);
    if (j < f.labels.size()) ++below[f.labels[j]];
  }
  int label = kLabelNothing, n = -1;
  for (const auto& [l, v] : below)
    if (v > n) label = l, n = v;
  char text[96];
  std::snprintf(text, sizeof text, "h %.1f-%.1f cm, below it %s", 100 * lo, 100 * hi,
                label >= 0             ? "an object"
                : label == kLabelTable ? "table"
                : label == kLabelFloor ? "floor"
                : label == kLabelWall  ? "wall"
                                       : background_name(label));
  return text;
}

// The room features a generated object has (none in world_scene_params' scenes).
std::vector<std::string> room_features(const SyntheticScene& s, const SyntheticObject& o) {
  std::vector<std::string> out;
  if (o.support < 0) out.push_back("floor");
  if (o.support > 0 && s.furniture[static_cast<size_t>(o.support - 1)].role == SyntheticBlock::Role::shelf)
    out.push_back("on-shelf");
  if (o.touching >= 0) out.push_back("touching");
  if (o.overhang) out.push_back("overhang");
  if (o.albedo < 1) out.push_back("dark");
  if (o.on_object >= 0) out.push_back("stacked");
  if (o.lying) out.push_back("lying");
  if (!o.details.empty())  // --everyday
    out.push_back(o.kind == ShapeKind::cone                   ? "cup"
                  : o.details.front().kind == ShapeKind::cone ? "bottle"
                                                              : "mug");
  const auto index = static_cast<int>(&o - s.objects.data());  // o is one of s.objects
  if (std::any_of(s.objects.begin(), s.objects.end(),
                  [&](const SyntheticObject& other) { return other.on_object == index; }))
    out.push_back("under");
  return out;
}

// One truth object into a band's tally: found, class, size errors (boxes' sides sorted).
void tally_feature(BandTally& b, const PhysicalPrimitive& tp, const PhysicalObject* got) {
  ++b.objects;
  if (!got) return;
  ++b.found;
  if (got->primitives.empty() || got->primitives[0].kind != tp.kind) return;
  ++b.correct;
  std::vector<double> a = tp.dimensions_m, g = got->primitives[0].dimensions_m;
  if (tp.kind == ShapeKind::box) {
    std::sort(a.begin(), a.begin() + 2);
    std::sort(g.begin(), g.begin() + 2);
  }
  for (size_t i = 0; i < a.size() && i < g.size(); ++i) b.errors.push_back(std::abs(a[i] - g[i]));
}

// The frame a sensor of 1/n the resolution sees of the same scene (subsampled: as a 320 x
// 240 stream or a phone's depth map sees a room the Kinect sees at 640 x 480), its labels
// and its truth's pixel counts with it.
SyntheticFrame subsampled(const SyntheticScene& scene, const SyntheticFrame& f, int n) {
  if (n <= 1) return f;
  SyntheticFrame out;
  out.frame = subsampled(f.frame, n);
  out.labels = every_nth_pixel(f.labels, f.frame.width, f.frame.height, n);
  out.truth = ground_truth(scene, &out.frame, &out.labels);
  return out;
}

// The scene seen by a camera of `scale` times the Kinect's resolution and focal length,
// the same field of view (its layout drawn for the Kinect's image).
SyntheticScene with_camera_scaled(SyntheticScene scene, double scale) {
  if (scale == 1) return scene;
  const CameraIntrinsics& k = scene.camera;
  scene.camera = resized_intrinsics(k, static_cast<int>(std::lround(k.width * scale)),
                                    static_cast<int>(std::lround(k.height * scale)));
  return scene;
}

// `first_seed`: the first scene's seed (2001, the set the scanner was tuned on; any
// other start is a held-out set).
// `room`: room_scene_params (table heights 0.4-1.1 m, camera roll) instead of
// world_scene_params.
// The camera the world set is seen by.
struct WorldCamera {
  int downsample = 1;       // a sensor of 1/n the resolution (every n-th pixel and row)
  double render_scale = 1;  // rendered by a camera of that many times the resolution
  SensorNoiseParams noise;  // the Kinect's by default; --sensor NAME another's depth noise
};

// The generator's shares the command line sets (--stacked, --everyday, --lying).
struct SceneShares {
  double stacked = 0;
  double everyday = 0;
  double lying = 0;
};

void world_set(int scenes, int first_seed, bool room, const SceneShares& shares, bool verbose,
               const std::string& png_dir, const ScanParams& params, const WorldCamera& camera) {
  const char* bands[] = {"< 1.5 m", "1.5-2.5 m", "> 2.5 m"};
  BandTally tally[3];
  std::map<std::string, std::map<std::string, int>> confusion;
  int false_props = 0, false_legs = 0, false_furniture = 0, false_chairs = 0, false_shelves = 0,
      slivers = 0, partial_flagged = 0, cut_objects = 0, fragments = 0, whole_fragments = 0,
      scans = 0, failures = 0;
  // room_scene_params' extra elements: false props on each, scenes that have each.
  std::map<int, int> false_extras, extra_scenes;
  // The room features (room_scene_params): per feature and band, and touching pairs.
  std::map<std::string, std::array<BandTally, 3>> by_feature;
  std::map<std::string, std::map<std::string, int>> feature_confusion;
  int pairs = 0, pairs_split = 0;
  // Stacked objects (--stacked) both of whose objects were found: how many, and how many
  // of those the scan reports standing on the object under them (on=).
  int stacks = 0, stacks_on_right = 0;
  std::vector<double> scan_ms;
  for (int k = 1; k <= scenes; ++k) {
    const int seed = first_seed + k - 1;
    const auto seed64 = static_cast<std::uint64_t>(seed);
    SyntheticSceneParams scene_params =
        room ? room_scene_params(seed64) : world_scene_params(seed64);
    scene_params.stacked_share = shares.stacked;
    scene_params.everyday_share = shares.everyday;
    scene_params.lying_share = shares.lying;
    Result<SyntheticScene> scene = generate_scene(scene_params);
    if (scene) *scene = with_camera_scaled(std::move(*scene), camera.render_scale);
    if (!scene) {
      std::printf("  seed %d: %s\n", seed, scene.error().format().c_str());
      continue;
    }
    const SyntheticFrame f =
        subsampled(*scene, render_scene(*scene, camera.noise), camera.downsample);
    for (int label : {kLabelBackChair, kLabelCabinet, kLabelPole})
      extra_scenes[label] += std::find(f.labels.begin(), f.labels.end(), label) != f.labels.end();
    const auto t0 = Clock::now();
    const Result<ScanResult> scan = scan_frame(f.frame, params);
    scan_ms.push_back(ms_since(t0));
    ++scans;
    if (!scan) ++failures;
    if (!png_dir.empty() && scan) {
      std::filesystem::create_directories(png_dir);
      const std::string stem = png_dir + "/world_" + std::to_string(seed);
      const std::string name = stem + ".png";
      if (!write_png(name, draw_scan_overlay(f.frame, *scan)) ||
          !write_pcd(stem + ".pcd", f.frame) || !write_scene_file(stem + ".truth.scene", f.truth))
        std::printf("  cannot write %s, its .pcd or its .truth.scene\n", name.c_str());
    }
    // Majority label of each scanned object.
    std::vector<int> owner;
    if (scan)
      for (const ScanCluster& c : scan->clusters) {
        std::map<int, int> votes;
        for (int i : c.pixels) ++votes[f.labels[static_cast<size_t>(i)]];
        int best = kLabelNothing, n = -1;
        for (const auto& [l, v] : votes)
          if (v > n) best = l, n = v;
        owner.push_back(best);
      }
    for (size_t k2 = 0; k2 < owner.size(); ++k2) {
      const PhysicalObject& o = scan->scene.objects[k2];
      if (owner[k2] < 0) {
        if (o.partial) continue;
        ++false_props;
        false_legs += owner[k2] == kLabelLeg;
        false_furniture += owner[k2] == kLabelFurniture;
        false_chairs += owner[k2] == kLabelChair;
        false_shelves += owner[k2] == kLabelShelf;
        if (owner[k2] <= kLabelBackChair) ++false_extras[owner[k2]];
        if (verbose)
          std::printf("  seed %d %s: %s reported whole (%s, %d points, on %s, %s)\n", seed,
                      o.id.c_str(), background_name(owner[k2]),
                      o.primitives.empty() ? "unknown"
                                           : std::string(shape_name(o.primitives[0].kind)).c_str(),
                      o.point_count, o.support_id.c_str(),
                      footing_note(f, scan->clusters[k2]).c_str());
      } else if (f.truth.objects[static_cast<size_t>(owner[k2])].partial) {
        partial_flagged += o.partial;
        slivers += !o.partial;
        if (verbose && !o.partial)
          std::printf("  seed %d %s: border sliver reported whole (%d points)\n", seed, o.id.c_str(),
                      o.point_count);
      }
    }
    // The scanned object standing for each truth object: the largest of those whose
    // pixels are mostly its.
    std::vector<int> picks(f.truth.objects.size(), -1);
    std::vector<size_t> pick_pixels(f.truth.objects.size(), 0);
    for (size_t k2 = 0; k2 < owner.size(); ++k2) {
      if (owner[k2] < 0) continue;
      const auto t = static_cast<size_t>(owner[k2]);
      if (scan->clusters[k2].pixels.size() > pick_pixels[t])
        pick_pixels[t] = scan->clusters[k2].pixels.size(), picks[t] = static_cast<int>(k2);
    }
    for (size_t t = 0; t < f.truth.objects.size(); ++t) {
      const int partner = scene->objects[t].touching;
      if (partner < 0 || f.truth.objects[t].partial ||
          f.truth.objects[static_cast<size_t>(partner)].partial)
        continue;
      ++pairs;
      if (picks[t] >= 0 && picks[static_cast<size_t>(partner)] >= 0) ++pairs_split;
      else if (verbose)
        std::printf("  seed %d truth %zu and %d touching: %s\n", seed, t, partner,
                    picks[t] < 0 && picks[static_cast<size_t>(partner)] < 0 ? "both missed"
                                                                            : "one missed or merged");
    }
    for (size_t t = 0; t < f.truth.objects.size(); ++t) {
      const int under = scene->objects[t].on_object;
      if (under < 0 || picks[t] < 0 || picks[static_cast<size_t>(under)] < 0) continue;
      ++stacks;
      const PhysicalObject& upper = scan->scene.objects[static_cast<size_t>(picks[t])];
      const PhysicalObject& lower =
          scan->scene.objects[static_cast<size_t>(picks[static_cast<size_t>(under)])];
      if (upper.on_object == lower.id)
        ++stacks_on_right;
      else if (verbose)
        std::printf("  seed %d %s (truth %zu) stands on %s (truth %d), reported on '%s'\n", seed,
                    upper.id.c_str(), t, lower.id.c_str(), under, upper.on_object.c_str());
    }
    for (size_t t = 0; t < f.truth.objects.size(); ++t) {
      const PhysicalObject& truth = f.truth.objects[t];
      const std::vector<std::string> features = room_features(*scene, scene->objects[t]);
      if (truth.partial) {
        ++cut_objects;
        continue;
      }
      const PhysicalPrimitive& tp = truth.primitives[0];
      double largest = *std::max_element(tp.dimensions_m.begin(), tp.dimensions_m.end());
      if (tp.kind != ShapeKind::box) largest = std::max(largest, 2 * tp.dimensions_m[0]);
      if (largest < 0.05) continue;
      const double dist = norm(tp.center);
      const int band = dist < 1.5 ? 0 : dist < 2.5 ? 1 : 2;
      BandTally& b = tally[band];
      ++b.objects;
      const std::string shape_row = truth_class(tp);
      const std::string got_col =
          picks[t] < 0 ? "missed"
          : scan->scene.objects[static_cast<size_t>(picks[t])].primitives.empty()
              ? "unknown"
              : std::string(shape_name(scan->scene.objects[static_cast<size_t>(picks[t])].primitives[0].kind));
      for (const std::string& feature : features) {
        ++feature_confusion[feature + ": " + shape_row][got_col];
        tally_feature(by_feature[feature][static_cast<size_t>(band)], tp,
                      picks[t] < 0 ? nullptr : &scan->scene.objects[static_cast<size_t>(picks[t])]);
      }
      int pick = -1, pieces = 0;
      size_t most = 0;
      for (size_t k2 = 0; k2 < owner.size(); ++k2)
        if (owner[k2] == static_cast<int>(t)) {
          ++pieces;
          if (scan->clusters[k2].pixels.size() > most) most = scan->clusters[k2].pixels.size(), pick = static_cast<int>(k2);
        }
      fragments += std::max(0, pieces - 1);
      // A piece besides the largest reported whole is a prop the user could annex that
      // is no object: a bowl's rim apart from its body.
      for (size_t k2 = 0; k2 < owner.size(); ++k2) {
        if (owner[k2] != static_cast<int>(t) || static_cast<int>(k2) == pick) continue;
        const PhysicalObject& piece = scan->scene.objects[k2];
        if (piece.partial) continue;
        ++whole_fragments;
        if (verbose)
          std::printf(
              "  seed %d %s: a piece of truth %zu (%s at %.2f m) reported whole (%s, %d points)\n",
              seed, piece.id.c_str(), t, truth_class(tp).c_str(), dist,
              piece.primitives.empty() ? "unknown"
                                       : std::string(shape_name(piece.primitives[0].kind)).c_str(),
              piece.point_count);
      }
      const std::string row = truth_class(tp);
      if (pick < 0) {
        ++confusion[row]["missed"];
        if (verbose) {
          std::printf("  seed %d truth %zu %s at %.2f m: missed (%d points seen", seed, t, row.c_str(), dist,
                      truth.point_count);
          for (const std::string& feature : features) std::printf(", %s", feature.c_str());
          // The scanned object holding most of its pixels, when one does (a piece of a
          // larger cluster: its majority is another object's or the background's).
          std::map<size_t, int> held;
          for (size_t k2 = 0; k2 < owner.size(); ++k2)
            for (int i : scan->clusters[k2].pixels)
              held[k2] += f.labels[static_cast<size_t>(i)] == static_cast<int>(t);
          int holder = -1, most_held = 0;
          for (const auto& [k2, n] : held)
            if (n > most_held) most_held = n, holder = static_cast<int>(k2);
          if (holder >= 0)
            std::printf("; %d of them in %s of %zu pixels, mostly %s", most_held,
                        scan->scene.objects[static_cast<size_t>(holder)].id.c_str(),
                        scan->clusters[static_cast<size_t>(holder)].pixels.size(),
                        owner[static_cast<size_t>(holder)] < 0 ? background_name(owner[static_cast<size_t>(holder)])
                                                               : "another object");
          std::printf(")\n");
        }
        continue;
      }
      ++b.found;
      const PhysicalObject& o = scan->scene.objects[static_cast<size_t>(pick)];
      b.flagged_partial += o.partial;
      if (verbose && o.partial)
        std::printf("  seed %d %s truth %zu %s at %.2f m: whole, flagged partial (%d points)\n",
                    seed, o.id.c_str(), t, row.c_str(), dist, o.point_count);
      // The support: the truth plane of the object's support against the scan's.
      std::optional<Plane> got;
      for (const SupportSurface& s : scan->scene.supports)
        if (s.id == o.support_id) got = s.plane;
      if (!got && scan->scene.support) got = scan->scene.support;
      for (const SupportSurface& s : f.truth.supports) {
        if (s.id != truth.support_id || !got) continue;
        if (std::abs(s.plane.d - got->d) < 0.03 && dot(s.plane.normal, got->normal) > 0.995)
          ++b.support_right;
        const double tilt = std::acos(std::clamp(dot(s.plane.normal, got->normal), -1.0, 1.0)) *
                            180 / 3.14159265358979;
        const Vec3 foot = tp.center - s.plane.normal * (dot(s.plane.normal, tp.center) + s.plane.d);
        const double foot_error = std::abs(dot(got->normal, foot) + got->d);
        b.support_tilt_deg.push_back(tilt);
        b.support_foot_m.push_back(foot_error);
        if (verbose && (tilt > 3 || foot_error > 0.02))
          std::printf(
              "  seed %d %s truth %zu at %.2f m: support %s tilted %.1f deg, %.1f cm off at the "
              "foot\n",
              seed, o.id.c_str(), t, dist, o.support_id.c_str(), tilt, 100 * foot_error);
      }
      const std::string col = o.primitives.empty() ? "unknown" : std::string(shape_name(o.primitives[0].kind));
      ++confusion[row][col];
      if (verbose && (o.primitives.empty() || o.primitives[0].kind != tp.kind)) {
        std::printf("  seed %d %s truth %s [", seed, o.id.c_str(), row.c_str());
        for (double d : tp.dimensions_m) std::printf(" %.3f", d);
        const auto& won = scan->clusters[static_cast<size_t>(pick)].shape.primitives;
        std::printf(" ] at %.2f m, %d points", dist, o.point_count);
        for (const std::string& feature : features) std::printf(", %s", feature.c_str());
        std::printf(", partial=%d -> %s (cov %.2f rms %.1f); candidates:", o.partial ? 1 : 0, col.c_str(),
                    won.empty() ? 0.0 : won[0].coverage, won.empty() ? 0.0 : 1000 * won[0].rms_m);
        for (const ShapeFit& c : scan->clusters[static_cast<size_t>(pick)].shape.candidates)
          std::printf(" %s(cov %.2f rms %.1f)", std::string(shape_name(c.primitive.kind)).c_str(),
                      c.coverage, 1000 * c.rms_m);
        std::printf("\n");
      }
      if (o.primitives.empty() || o.primitives[0].kind != tp.kind) continue;
      ++b.correct;
      const PhysicalPrimitive& gp = o.primitives[0];
      if (tp.kind == ShapeKind::cone) {
        ++b.cones;
        b.direction_right += dot(gp.axis, tp.axis) > 0;
      }
      std::vector<double> a = tp.dimensions_m, g = gp.dimensions_m;
      if (tp.kind == ShapeKind::box) {
        std::sort(a.begin(), a.begin() + 2);
        std::sort(g.begin(), g.begin() + 2);
      }
      for (size_t i = 0; i < a.size() && i < g.size(); ++i) b.errors.push_back(std::abs(a[i] - g[i]));
    }
  }
  std::printf("world set: %d generated scenes (seeds %d-%d, %s), %d scans "
              "failed, scan median_ms=%.1f\n",
              scans, first_seed, first_seed + scenes - 1,
              room ? "room_scene_params" : "world_scene_params", failures, median(scan_ms));
  std::printf("  %-10s %7s %6s %8s %10s %10s %9s %9s\n", "band", "objects", "found", "class",
              "median_mm", "p90_mm", "support", "cone_dir");
  for (int i = 0; i < 3; ++i) {
    const BandTally& b = tally[i];
    std::printf("  %-10s %7d %6d %7.1f%% %10.2f %10.2f %8.1f%% %4d/%-4d\n", bands[i], b.objects,
                b.found, b.objects ? 100.0 * b.correct / b.objects : 0.0, 1000 * median(b.errors),
                1000 * percentile(b.errors, 0.9),
                b.found ? 100.0 * b.support_right / b.found : 0.0, b.direction_right, b.cones);
  }
  std::printf(
      "  support under found objects (tilt median/p90 deg, height at the foot median/p90 mm):");
  for (int i = 0; i < 3; ++i)
    std::printf(" %s %.2f/%.2f %.1f/%.1f%s", bands[i], median(tally[i].support_tilt_deg),
                percentile(tally[i].support_tilt_deg, 0.9), 1000 * median(tally[i].support_foot_m),
                1000 * percentile(tally[i].support_foot_m, 0.9), i < 2 ? ";" : "\n");
  std::printf("  whole objects flagged partial (they do not vote):");
  for (int i = 0; i < 3; ++i)
    std::printf(" %s %d of %d%s", bands[i], tally[i].flagged_partial, tally[i].found,
                i < 2 ? ";" : "\n");
  std::printf(
      "  false props (background, legs, furniture reported whole): %d (legs %d, "
      "furniture %d, chairs %d, shelves %d); border slivers reported whole: %d; cut "
      "objects flagged partial: %d (of %d cut objects); extra fragments: %d (reported whole: "
      "%d)\n",
      false_props, false_legs, false_furniture, false_chairs, false_shelves, slivers,
      partial_flagged, cut_objects, fragments, whole_fragments);
  if (room)
    std::printf(
        "  room extras (scenes showing it: false props on it): back chair %d: %d, cabinet %d: %d, "
        "pole %d: %d\n",
        extra_scenes[kLabelBackChair], false_extras[kLabelBackChair], extra_scenes[kLabelCabinet],
        false_extras[kLabelCabinet], extra_scenes[kLabelPole], false_extras[kLabelPole]);
  if (!by_feature.empty()) {
    std::printf("  room features (objects >= 5 cm, not cut; found / class / median size error per band):\n");
    for (const auto& [feature, bands3] : by_feature) {
      std::printf("    %-9s", feature.c_str());
      for (int i = 0; i < 3; ++i) {
        const BandTally& t = bands3[static_cast<size_t>(i)];
        std::printf("  %s %d/%d %5.1f%% %5.2f mm", bands[i], t.found, t.objects,
                    t.objects ? 100.0 * t.correct / t.objects : 0.0, 1000 * median(t.errors));
      }
      std::printf("\n");
    }
    std::printf("    touching pairs (both whole): %d, both found as separate objects: %d\n", pairs,
                pairs_split);
    if (shares.stacked > 0)
      std::printf("    stacked objects found with the object under them: %d, reported on it: %d\n",
                  stacks, stacks_on_right);
    std::printf("  room features' confusion (truth -> scanned):\n");
    for (const auto& [row, cols] : feature_confusion) {
      std::printf("    %-38s", row.c_str());
      for (const auto& [col, n] : cols) std::printf(" %s=%d", col.c_str(), n);
      std::printf("\n");
    }
  }
  std::printf("  confusion (truth -> scanned, all distances):\n");
  for (const auto& [row, cols] : confusion) {
    std::printf("    %-30s", row.c_str());
    for (const auto& [col, n] : cols) std::printf(" %s=%d", col.c_str(), n);
    std::printf("\n");
  }
}

void real_clusters(const Frame& frame) {
  const Result<ScanResult> scan = scan_frame(frame, objects_only());
  if (!scan) return;
  std::printf("real milk_cartoon clusters, ours vs CGAL Efficient RANSAC (3 seeds):\n");
  for (size_t k = 0; k < scan->clusters.size(); ++k) {
    const ScanCluster& c = scan->clusters[k];
    std::printf("  %s (%zu pts): ours=", scan->scene.objects[k].id.c_str(), c.points.size());
    if (c.shape.primitives.empty()) std::printf("unknown");
    for (const ShapeFit& s : c.shape.primitives) {
      std::printf("%s[", std::string(shape_name(s.primitive.kind)).c_str());
      for (double d : s.primitive.dimensions_m) std::printf(" %.3f", d);
      std::printf(" ] ");
    }
    std::printf(" cgal=");
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      CgalRansacParams p;
      p.seed = seed;
      const auto t0 = Clock::now();
      const ObjectShape s = recognize_object_shape_cgal(c.points, {}, p);
      const double ms = ms_since(t0);
      if (s.primitives.empty()) {
        std::printf("none(%.0fms) ", ms);
        continue;
      }
      const PhysicalPrimitive& q = s.primitives[0].primitive;
      std::printf("%s[", std::string(shape_name(q.kind)).c_str());
      for (double d : q.dimensions_m) std::printf(" %.3f", d);
      std::printf(" ](%.0fms) ", ms);
    }
    std::printf("\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 30, scenes = 100, world = 60, world_seed = 2001, pcl_repeat = -1, threads = ScanParams{}.threads;
  WorldCamera camera;
  bool pcl = true, world_only = false, speed_only = false, verbose = false, room = false;
  bool pool_per_scan = false;
  SceneShares shares;
  std::string png_dir;
  // The world set's scan parameters: the benchmarks' (objects only), or a scan config
  // file's over them (--scan-conf: an A/B run of one rule, e.g. touching_max_coverage 0).
  ScanParams world_params = objects_only();
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--repeat" && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else if (a == "--scenes" && i + 1 < argc) scenes = std::max(1, std::atoi(argv[++i]));
    else if (a == "--world" && i + 1 < argc) world = std::max(0, std::atoi(argv[++i]));
    else if (a == "--world-seed" && i + 1 < argc) world_seed = std::atoi(argv[++i]);
    else if (a == "--rooms") room = true;
    else if (a == "--stacked" && i + 1 < argc)
      shares.stacked = std::clamp(std::atof(argv[++i]), 0.0, 1.0);
    else if (a == "--everyday" && i + 1 < argc)
      shares.everyday = std::clamp(std::atof(argv[++i]), 0.0, 1.0);
    else if (a == "--lying" && i + 1 < argc)
      shares.lying = std::clamp(std::atof(argv[++i]), 0.0, 1.0);
    else if (a == "--flying" && i + 1 < argc)
      camera.noise.flying_share = std::clamp(std::atof(argv[++i]), 0.0, 1.0);
    else if (a == "--pcl-repeat" && i + 1 < argc) pcl_repeat = std::max(1, std::atoi(argv[++i]));
    else if (a == "--threads" && i + 1 < argc) threads = std::max(1, std::atoi(argv[++i]));
    else if (a == "--speed-only") speed_only = true;
    else if (a == "--pool-per-scan") pool_per_scan = true;
    else if (a == "--skip-pcl") pcl = false;
    else if (a == "--world-only") world_only = true;
    else if (a == "--verbose") verbose = true;
    else if (a == "--png-dir" && i + 1 < argc) png_dir = argv[++i];
    else if (a == "--downsample" && i + 1 < argc)
      camera.downsample = std::clamp(std::atoi(argv[++i]), 1, 8);
    else if (a == "--render-scale" && i + 1 < argc)
      camera.render_scale = std::clamp(std::atof(argv[++i]), 0.25, 3.0);
    else if (a == "--sensor" && i + 1 < argc) {
      const std::optional<DepthNoise> noise = depth_noise_named(argv[++i]);
      if (!noise) {
        std::fprintf(stderr, "annex-bench-scan: --sensor expects one of %s\n",
                     std::string(kDepthNoiseNames).c_str());
        return 2;
      }
      camera.noise.axial = *noise;
    } else if (a == "--scan-conf" && i + 1 < argc) {
      const Result<ScanParams> conf = read_scan_config_file(argv[++i]);
      if (!conf) {
        std::fprintf(stderr, "annex-bench-scan: %s\n", conf.error().format().c_str());
        return 2;
      }
      world_params = *conf;
      world_params.plane_candidates = false;
    } else {
      std::fprintf(
          stderr,
          "usage: annex-bench-scan [--repeat N] [--pcl-repeat N] [--threads N] [--scenes N] "
          "[--world N] [--world-seed FIRST] [--rooms] [--skip-pcl] [--world-only] [--speed-only] "
          "[--pool-per-scan] [--verbose] [--png-dir DIR] [--scan-conf FILE] [--downsample N] "
          "[--render-scale S] [--sensor NAME] [--flying SHARE] [--stacked SHARE]\n"
          "       [--everyday SHARE] [--lying SHARE]\n");
      return 2;
    }
  }
  if (world_only) {
    world_set(world, world_seed, room, shares, verbose, png_dir, world_params, camera);
    return 0;
  }
  const std::filesystem::path real =
      std::filesystem::path(ANNEX_SHARED_DIR) / "data/real/milk_cartoon_all_small_clorox.pcd";
  std::optional<Frame> real_frame;
  if (std::filesystem::exists(real)) {
    Result<Frame> f = read_pcd(real);
    if (f) real_frame = std::move(*f);
  }
  if (pcl_repeat < 0) pcl_repeat = std::max(5, repeat / 3);
  if (!pcl) pcl_repeat = 0;
  if (real_frame)
    speed(*real_frame, "milk_cartoon_all_small_clorox.pcd", repeat, pcl_repeat, threads, pool_per_scan);
  else std::printf("speed: ../shared/data/real absent, real frame skipped\n");
  if (speed_only) return 0;
  speed(synthetic(7).frame, "generated scene seed 7", repeat, pcl_repeat, threads, pool_per_scan);
  if (world > 0) world_set(world, world_seed, room, shares, verbose, png_dir, world_params, camera);
  accuracy_and_ransac(scenes, std::min(scenes, 30));
  if (real_frame) real_clusters(*real_frame);
  return 0;
}
