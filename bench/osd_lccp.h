#pragma once
// PCL 1.13's supervoxels + LCCP (Stein et al. 2014) on one cluster, for the segmenter
// comparison in annex-eval-osd --method lccp (docs/perception.md, Clutter).

#include <vector>

#include "annex/runtime/frame.h"

namespace annex {

struct LccpParams {
  double voxel_m = 0.0075, seed_m = 0.03;  // PCL's example values
  double concavity_deg = 10, smoothness = 0.1;
  int min_segment_supervoxels = 3;
};

// The cluster's pixels (indices into frame.points) grouped by LCCP segment.
std::vector<std::vector<int>> lccp_split(const Frame& frame, const std::vector<int>& pixels,
                                         const LccpParams& params = {});

}  // namespace annex
