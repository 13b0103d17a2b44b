#pragma once
// The paper's scanning pipeline built from PCL's stock filters, kept to measure the
// scanner against (bench/bench_scan.cpp) and as a cross-check in tests. Lives in
// annex_reference, which only bench/ and tests/ link: not part of the installed library.

#include "annex/common/result.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/scanner.h"

namespace annex {

// The paper's pipeline with PCL's stock filters (5 mm voxel grid, SAC plane, convex
// hull, polygonal prism, Euclidean clusters, MLS, SAC sphere/cylinder/cone fits with
// most inliers winning). Slow; kept for the benchmark and as a cross-check.
struct PclReferenceParams {
  double voxel_m = 0.005;
  double plane_distance_m = 0.01;
  double cluster_tolerance_m = 0.02;
  int min_cluster_points = 100;
  double mls_radius_m = 0.03;
  double shape_distance_m = 0.01;
  int shape_iterations = 1000;
};
Result<ScanResult> scan_frame_pcl_reference(const Frame& frame,
                                            const PclReferenceParams& params = {});

}  // namespace annex
