// annex-eval-osd: the scanner on the OSD learning set (../shared/data/osd-learn, 45
// labelled tabletop scenes), the figures of docs/perception.md "Clutter".
//   recall     labelled objects found whole: one reported object whose centre (its
//              most interior pixel, nearest to its points' mean projected to the label
//              image among equals) lies on the labelled object and which holds 0.5 to 1.6 times its
//              labelled points;
//   precision  reported objects that are whole labelled objects;
//   fragments  reported objects centred on a labelled object with < 0.5x its points;
//   merges     reported objects holding > 25 % of the points of two or more objects;
//   shape      the salient primitive of each object found whole against the class the
//              expectations table (bench/osd_expectations.txt) gives its label.
// Per scene the scan time (median of --repeat runs) against the number of objects.
// Usage: annex-eval-osd OSD_DIR [--expect FILE] [--config SCAN.conf] [--repeat N]
//                       [--png-dir DIR] [--scenes FIRST-LAST] [--verbose] [--explain]
//                       [--method crease|none|lccp] [--downsample N]
// --explain prints, per reported object, its primitives and every candidate the shape
// recognizer tried (as `annex-runtime scan --explain` does).
// --method none scans without splitting clusters; lccp splits the unsplit clusters with
// PCL's supervoxels + LCCP instead (segments only: no shapes, so no shape columns).
// --downsample N scores the scenes as a sensor of 1/N the resolution sees them (every
// N-th pixel of every N-th row, labels with them).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "annex/runtime/depth_png.h"
#include "osd_eval.h"
#include "osd_lccp.h"
#include "annex/runtime/scan_overlay.h"
#include "annex/runtime/scanner.h"

namespace {

using namespace annex;
using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

struct Tally {
  int labelled = 0, found = 0, reported = 0, whole = 0, fragments = 0, merges = 0;
  int box_expected = 0, box_ok = 0, round_expected = 0, round_ok = 0;
  int frustum_expected = 0, frustum_ok = 0;
  void add(const OsdSceneScore& s) {
    labelled += s.labelled;
    found += s.found;
    reported += s.reported;
    whole += s.whole;
    fragments += s.fragments;
    merges += s.merges;
    box_expected += s.box_expected;
    box_ok += s.box_ok;
    round_expected += s.cylinder_expected;
    round_ok += s.cylinder_ok;
    frustum_expected += s.frustum_expected;
    frustum_ok += s.frustum_ok;
  }
};

// CPU time of the process (all threads), steadier than wall time on a loaded machine.
double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

std::string pct(int a, int b) {
  if (b == 0) return "    -";
  char t[32];
  std::snprintf(t, sizeof t, "%5.1f", 100.0 * a / b);
  return t;
}

// "cone radius=0.0600 height=0.0800 narrow_radius=0.0400 center=... axis=...".
std::string describe_primitive(const PhysicalPrimitive& p) {
  std::string out(shape_name(p.kind));
  char t[96];
  const auto names = dimension_names(p.kind);
  for (size_t k = 0; k < names.size() && k < p.dimensions_m.size(); ++k) {
    std::snprintf(t, sizeof t, " %s=%.4f", std::string(names[k]).c_str(), p.dimensions_m[k]);
    out += t;
  }
  if (p.narrow_radius_m > 0) {
    std::snprintf(t, sizeof t, " narrow_radius=%.4f", p.narrow_radius_m);
    out += t;
  }
  std::snprintf(t, sizeof t, " center=%.3f,%.3f,%.3f axis=%.3f,%.3f,%.3f", p.center.x, p.center.y,
                p.center.z, p.axis.x, p.axis.y, p.axis.z);
  return out + t;
}

void print_row(const char* name, const Tally& t) {
  std::printf("%-9s %4d %5d/%-3d %s  %5d/%-3d %s  %5d %6d   %2d/%-2d %s   %2d/%-2d %s   %2d/%-2d\n",
              name, t.labelled, t.found, t.labelled, pct(t.found, t.labelled).c_str(), t.whole,
              t.reported, pct(t.whole, t.reported).c_str(), t.fragments, t.merges, t.box_ok,
              t.box_expected, pct(t.box_ok, t.box_expected).c_str(), t.round_ok,
              t.round_expected, pct(t.round_ok, t.round_expected).c_str(), t.frustum_ok,
              t.frustum_expected);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: annex-eval-osd OSD_DIR [--expect FILE] [--config SCAN.conf] "
                 "[--repeat N] [--png-dir DIR] [--scenes FIRST-LAST] [--verbose] "
                 "[--explain] [--method crease|none|lccp] [--downsample N]\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::path expect_path = ANNEX_BENCH_DIR "/osd_expectations.txt";
  std::optional<std::filesystem::path> config, png_dir;
  int repeat = 5, first = 0, last = 44, downsample = 1;
  bool verbose = false, explain = false;
  std::string method = "crease";
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "annex-eval-osd: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--expect")
      expect_path = next();
    else if (a == "--config")
      config = next();
    else if (a == "--repeat")
      repeat = std::max(1, std::atoi(next().c_str()));
    else if (a == "--png-dir")
      png_dir = next();
    else if (a == "--downsample")
      downsample = std::clamp(std::atoi(next().c_str()), 1, 8);
    else if (a == "--scenes") {
      const std::string r = next();
      if (std::sscanf(r.c_str(), "%d-%d", &first, &last) != 2) {
        std::fprintf(stderr, "annex-eval-osd: --scenes wants FIRST-LAST, got '%s'\n", r.c_str());
        return 2;
      }
    } else if (a == "--method") {
      method = next();
      if (method != "crease" && method != "none" && method != "lccp") {
        std::fprintf(stderr, "annex-eval-osd: --method is crease, none or lccp, got '%s'\n",
                     method.c_str());
        return 2;
      }
    } else if (a == "--verbose")
      verbose = true;
    else if (a == "--explain")
      explain = true;
    else {
      std::fprintf(stderr, "annex-eval-osd: unknown option '%s'\n", a.c_str());
      return 2;
    }
  }
  ScanParams params;
  params.plane_candidates = false;  // objects are scored; a config file may say otherwise
  if (config) {
    Result<ScanParams> p = read_scan_config_file(*config);
    if (!p) {
      std::fprintf(stderr, "%s\n", p.error().format().c_str());
      return 2;
    }
    params = *p;
  }
  if (method != "crease") params.segment.enabled = false;
  Result<OsdExpectations> expectations = read_osd_expectations_file(expect_path);
  if (!expectations) {
    std::fprintf(stderr, "%s\n", expectations.error().format().c_str());
    return 2;
  }
  if (png_dir) std::filesystem::create_directories(*png_dir);

  std::map<std::string, Tally> by_category;
  Tally all;
  std::map<int, std::vector<double>> ms_by_objects, cpu_by_objects;
  std::vector<double> all_ms, all_cpu;
  std::map<std::string, std::vector<double>> stage_ms;
  std::vector<std::string> stage_order;
  for (int n = first; n <= last; ++n) {
    const std::string name = "learn" + std::to_string(n);
    Result<OsdScene> scene = read_osd_scene(dir, name);
    if (!scene) {
      std::fprintf(stderr, "%s\n", scene.error().format().c_str());
      return 2;
    }
    *scene = subsampled(*scene, downsample);
    std::vector<double> times, cpu_times;
    Result<ScanResult> scan = Error{"not run", {}};
    for (int r = 0; r < repeat; ++r) {
      const double c0 = cpu_ms();
      const auto t0 = Clock::now();
      scan = scan_frame(scene->frame, params);
      if (scan && method == "lccp") {
        std::vector<ScanCluster> segments;
        for (const ScanCluster& c : scan->clusters)
          for (std::vector<int>& part : lccp_split(scene->frame, c.pixels)) {
            ScanCluster sc;
            sc.pixels = std::move(part);
            if (sc.pixels.size() >= static_cast<size_t>(params.min_cluster_points))
              segments.push_back(std::move(sc));
          }
        scan->clusters = std::move(segments);
      }
      times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      cpu_times.push_back(cpu_ms() - c0);
    }
    if (scan)
      for (const StageTime& st : scan->stages) {
        if (!stage_ms.count(st.name)) stage_order.push_back(st.name);
        stage_ms[st.name].push_back(st.ms);
      }
    const double ms = median(times), cpu = median(cpu_times);
    OsdSceneScore score;
    if (scan) {
      score = score_osd_scene(*scene, *scan, *expectations);
      if (png_dir && method != "lccp") {
        const Status s = write_png(*png_dir / (name + ".png"), draw_scan_overlay(scene->frame, *scan));
        if (!s) std::fprintf(stderr, "%s\n", s.error().format().c_str());
      }
    } else {
      score = score_osd_scene(*scene, ScanResult{}, *expectations);
      std::printf("%s: scan failed: %s\n", name.c_str(), scan.error().format().c_str());
    }
    const std::string category = osd_category(n);
    by_category[category].add(score);
    all.add(score);
    ms_by_objects[score.labelled].push_back(ms);
    cpu_by_objects[score.labelled].push_back(cpu);
    all_ms.push_back(ms);
    all_cpu.push_back(cpu);
    std::printf("%-8s %-9s objects=%d found=%d reported=%d whole=%d fragments=%d merges=%d "
                "shape_ok=%d/%d scan_ms=%.1f\n",
                name.c_str(), category.c_str(), score.labelled, score.found, score.reported,
                score.whole, score.fragments, score.merges,
                score.box_ok + score.cylinder_ok + score.frustum_ok,
                score.box_expected + score.cylinder_expected + score.frustum_expected, ms);
    if (verbose)
      for (const std::string& line : score.notes) std::printf("    %s\n", line.c_str());
    if (explain && scan && method != "lccp")
      for (size_t k = 0; k < scan->clusters.size(); ++k) {
        const PhysicalObject& o = scan->scene.objects[k];
        std::printf("    object %s points=%d%s%s\n", o.id.c_str(), o.point_count,
                    o.on_object.empty() ? "" : (" on=" + o.on_object).c_str(), o.partial ? " partial" : "");
        for (const PhysicalPrimitive& p : o.primitives)
          std::printf("      primitive %s\n", describe_primitive(p).c_str());
        for (const ShapeFit& c : scan->clusters[k].shape.candidates)
          std::printf("      candidate %s coverage=%.2f rms_mm=%.1f\n",
                      describe_primitive(c.primitive).c_str(), c.coverage, c.rms_m * 1000);
      }
  }
  std::printf("\ncategory  objs  recall       %%    precision    %%  frags merges  "
              "box-as-box  %%   cyl-as-cyl %%   frustum\n");
  for (const char* c : {"boxes", "stacked", "occluded", "round"})
    if (by_category.count(c)) print_row(c, by_category[c]);
  print_row("all", all);
  std::printf("\nscan time against labelled objects (per scene the median of --repeat runs; "
              "wall clock, and CPU time of both threads):\n");
  for (const auto& [objects, ms] : ms_by_objects)
    std::printf("  objects=%d scenes=%zu median_ms=%.1f max_ms=%.1f cpu_median_ms=%.1f\n", objects,
                ms.size(), median(ms), *std::max_element(ms.begin(), ms.end()),
                median(cpu_by_objects[objects]));
  std::printf("  all scenes=%zu median_ms=%.1f max_ms=%.1f cpu_median_ms=%.1f\n", all_ms.size(),
              median(all_ms), all_ms.empty() ? 0.0 : *std::max_element(all_ms.begin(), all_ms.end()),
              median(all_cpu));
  std::printf("  stages (median over scenes, last run, wall ms):");
  for (const std::string& st : stage_order) std::printf(" %s=%.1f", st.c_str(), median(stage_ms[st]));
  std::printf("\n");
  return 0;
}
