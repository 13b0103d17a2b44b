#pragma once
// CGAL's Efficient RANSAC as the ObjectShapeRecognizer the paper used, kept to compare
// ours against (bench/bench_scan.cpp, tests). Lives in annex_reference, which only
// bench/ and tests/ link: not part of the installed library.

#include <cstdint>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/runtime/object_shape_recognizer.h"

namespace annex {

// The paper's method for comparison: CGAL 5.5 Efficient RANSAC (Schnabel et al. 2007)
// on the same points (jet normals estimated when `normals` is empty), salient primitive
// = the detected shape with most support. Used by the benchmark (docs/perception.md).
struct CgalRansacParams {
  double probability = 0.05;
  int min_points = 100;
  double epsilon_m = 0.005;
  double cluster_epsilon_m = 0.02;
  double normal_threshold = 0.85;
  int jet_neighbours = 18;
  std::uint64_t seed = 1;
};
ObjectShape recognize_object_shape_cgal(const std::vector<Vec3>& points,
                                        const std::vector<Vec3>& normals,
                                        const CgalRansacParams& params = {});

}  // namespace annex
