#pragma once
// A dark surface loses depth where its infrared return is weak: the sensor reports
// nothing there (missing pixels, not noise), and what is left of the object is a
// scatter of small grid clusters, each under the size floor, parted by pixels with no
// depth. Such fragments are pieces of one surface when the pixels between them have no
// depth (or depth on the line between them) and they lie as close in 3D as the gap
// allows; joined, they are one cluster when together they reach the floor. Clusters at
// or above the floor are left as they are. Private to the scanner.

#include <functional>
#include <vector>

#include "annex/runtime/frame.h"

namespace annex {

struct DropoutJoinParams {
  // The widest run of missing pixels bridged between two fragments (ScanParams::
  // dropout_max_gap_px says why 8).
  int max_gap_px = 8;
};

// grids: grid clusters (pixel indices at `step`), mask: the support each pixel is over
// (fragments over different supports are not joined); tolerance(z): the clustering
// tolerance at depth z; floor(grid): the points a cluster needs (its grid pixels count
// step^2 each, as the scanner counts them). Returns the clusters with each joined group
// in place of its first fragment, the other fragments removed, order otherwise kept.
std::vector<std::vector<int>> join_dropout_fragments(
    const Frame& frame, const std::vector<char>& mask, std::vector<std::vector<int>> grids, int step,
    const std::function<double(double)>& tolerance,
    const std::function<int(const std::vector<int>&)>& floor, const DropoutJoinParams& params = {});

}  // namespace annex
