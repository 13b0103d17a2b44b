// Annex from C++ (annex::annex): scan a frame, match a spec against it with the vote
// explanation, then run a session over the frames given.
//
//   annex_example_cpp SPEC.haptic FRAME.pcd...
#include <cstdio>
#include <iostream>

#include "annex/common/object_finder.h"
#include "annex/formats/haptic_format.h"
#include "annex/runtime/annex_session.h"
#include "annex/runtime/match_report.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/scanner.h"
#include "annex/version.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: " << argv[0] << " SPEC.haptic FRAME.pcd...\n";
    return 2;
  }
  std::cout << "annex " << annex::library_version() << " (headers " << ANNEX_VERSION_STRING
            << ")\n";
  annex::Result<annex::HapticSpec> spec = annex::read_haptic_file(argv[1]);
  if (!spec) {
    std::cerr << spec.error().format() << "\n";
    return 1;
  }
  annex::Result<annex::Frame> first = annex::read_pcd(argv[2]);
  if (!first) {
    std::cerr << first.error().format() << "\n";
    return 1;
  }
  annex::Result<annex::ScanResult> scan = annex::scan_frame(*first);
  if (!scan) {
    std::cerr << scan.error().format() << "\n";
    return 1;
  }
  const annex::MatchResult match = annex::match_objects(*spec, scan->scene);
  std::cout << annex::format_match_lines(*spec, scan->scene, match);

  annex::SessionParams params;
  // Frames read from files are processed offline: each scan applies in its own frame,
  // whatever the machine's load. A render loop sets ScanMode::background (no frame
  // waits for a scan; docs/embedding.md).
  params.scan_mode = annex::ScanMode::same_frame;
  annex::Result<annex::AnnexSession> session = annex::AnnexSession::create(*spec, params);
  if (!session) {
    std::cerr << session.error().format() << "\n";
    return 1;
  }
  for (int i = 2; i < argc; ++i) {
    annex::Result<annex::Frame> frame = annex::read_pcd(argv[i]);
    if (!frame) {
      std::cerr << frame.error().format() << "\n";
      return 1;
    }
    const annex::FrameReport r = session->process(*frame, i - 2);
    for (const annex::AnnexedObject& o : r.objects)
      std::cout << annex::format_pose_line(i - 2, *spec, o) << "\n";
  }
  return 0;
}
