#pragma once
// Scoring a scan against an OSD labelled scene (../shared/data/osd-learn): which
// labelled objects the scan found whole, which reported objects are fragments or
// merges, and whether each object found has the shape class its label expects.
// Shared by annex-eval-osd and the clutter tests.

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "annex/common/result.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/scanner.h"

namespace annex {

// One labelled scene: the frame (depth + colour) and per pixel the object id
// (label // 10 for labels >= 10; 0 for no point and for the table).
struct OsdScene {
  std::string name;
  Frame frame;
  std::vector<int> object_of_pixel;
  std::map<int, int> labelled_points;  // object id -> labelled pixels with depth
};

Result<OsdScene> read_osd_scene(const std::filesystem::path& dir, const std::string& name);

// The scene as a sensor of 1/n the resolution sees it (annex::subsampled), its labels
// with it and the labelled pixels counted anew.
OsdScene subsampled(const OsdScene& scene, int n);

// Expected shape class per scene and object id: "box", "cylinder" (cans, jars, mugs),
// "frustum" (bowls, cups, pots: a cone or a cylinder), "any" (not scored).
struct OsdExpectations {
  std::map<std::string, std::map<int, std::string>> classes;
  std::string class_of(const std::string& scene, int object) const;
};
// Lines `learnN OBJECT CLASS` (# comments); errors carry file:line:col.
Result<OsdExpectations> parse_osd_expectations(std::string_view text, std::string_view origin);
Result<OsdExpectations> read_osd_expectations_file(const std::filesystem::path& path);

// "boxes" (learn0-16), "stacked" (17-24), "occluded" (25-32), "round" (33-44).
std::string osd_category(int scene_number);

struct OsdObjectScore {
  int id = 0;
  int labelled_points = 0;
  std::string expected;   // class from the table
  bool found = false;     // one reported object holds it whole
  std::string reported;   // the salient kind of that object ("unknown" when none)
  bool shape_ok = false;
};

struct OsdSceneScore {
  int labelled = 0, found = 0, reported = 0, whole = 0, fragments = 0, merges = 0;
  int box_expected = 0, box_ok = 0, cylinder_expected = 0, cylinder_ok = 0;
  int frustum_expected = 0, frustum_ok = 0;
  std::vector<OsdObjectScore> objects;
  std::vector<std::string> notes;  // one line per reported object, for --verbose
};

// The definitions of bench/eval_osd.cpp's header comment.
OsdSceneScore score_osd_scene(const OsdScene& scene, const ScanResult& scan,
                              const OsdExpectations& expectations);

}  // namespace annex
