#pragma once
// The Voter (paper, "Voting Equation"):
//   x_vp = C * w_o * w_s * sum_h( min(h_v, h_p) / max(h_v, h_p) * w_h )
// with the w_h of the chosen primitive normalised to sum to 1, so C is the highest
// possible vote (docs/voting.md gives every decision the paper leaves open).

#include <string>
#include <vector>

#include "annex/common/haptic_model.h"
#include "annex/common/physical_scene.h"

namespace annex {

struct VoteParams {
  double max_vote = 100.0;  // C
};

// One dimension's share of a vote.
struct DimensionTerm {
  std::string name;
  double virtual_m = 0;
  double physical_m = 0;
  double ratio = 0;   // min / max, in [0, 1]
  double weight = 0;  // w_h after normalisation
};

// Why a virtual object voted what it did for a physical object.
struct VoteExplanation {
  double vote = 0;
  int virtual_primitive = -1;   // index into VirtualObject::primitives, -1: no shared shape
  int physical_primitive = -1;  // index into PhysicalObject::primitives
  double object_weight = 0;     // w_o
  double primitive_weight = 0;  // w_s
  double dimension_sum = 0;     // sum of ratio * normalised w_h
  std::vector<DimensionTerm> terms;
};

// Primitive indices in the order the Voter tries them: w_s descending, ties in
// authored order.
std::vector<int> primitive_priority_order(const VirtualObject& object);

VoteExplanation explain_vote(const VirtualObject& v, const PhysicalObject& p,
                             const VoteParams& params = {});

inline double vote(const VirtualObject& v, const PhysicalObject& p,
                   const VoteParams& params = {}) {
  return explain_vote(v, p, params).vote;
}

}  // namespace annex
