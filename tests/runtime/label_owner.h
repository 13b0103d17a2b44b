// What a scanned object stands for in a generated frame, by the labels of its pixels
// (the scanner tests on generated worlds and rooms).
#pragma once
#include <cstddef>
#include <map>

#include "annex/runtime/scanner.h"
#include "annex/runtime/synthetic_scene.h"

namespace annex {

// The truth object most of a scanned object's pixels show, or a background label.
inline int majority_label(const SyntheticFrame& f, const ScanCluster& c) {
  std::map<int, int> votes;
  for (int i : c.pixels) ++votes[f.labels[static_cast<std::size_t>(i)]];
  int best = kLabelNothing, n = -1;
  for (const auto& [l, v] : votes)
    if (v > n) best = l, n = v;
  return best;
}

}  // namespace annex
