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
  // Every fragment under the floor is joined (ScanParams::dropout_join_to_floor says
  // why); false: only those under half of it, which the scanner drops at once.
  bool to_floor = true;
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

// The pixels an object covers in the image, with depth or not: `pixels` (image indices,
// each with depth) and the pixels without depth they enclose, those inside a run of
// missing pixels at most max_gap_px long with one of `pixels` at each end both in its
// row and in its column. A dark surface loses its depth in scattered pixels (the sensor
// judges each pixel's return alone); those pixels are still the object's area, unknown
// rather than free, so a size floor meant for the object's image area counts them. A
// pixel without depth at the object's outline (a silhouette edge, dropout against the
// background) is enclosed in at most one direction and is not counted.
int silhouette_pixels(const Frame& frame, const std::vector<int>& pixels, int max_gap_px);

// The pixels with depth in the step x step blocks next to a grid cluster's pixels
// (`grid`, every step-th pixel) whose own grid pixel has no depth: no cluster grows
// through such a block, so on a dark surface, where most grid pixels lose their depth,
// most of what the sensor returned is never looked at. accept(pixel, grid_pixel) is
// the scanner's test that a pixel belongs with the grid pixel beside its block (within
// the clustering tolerance, above the support). Sorted, each once, none in a block of
// `grid` itself.
std::vector<int> dropout_block_pixels(const Frame& frame, const std::vector<int>& grid, int step,
                                      const std::function<bool(int, int)>& accept);

}  // namespace annex
