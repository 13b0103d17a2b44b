#pragma once
// Text that annex-runtime prints for a match: the script-facing lines
// (`match <virtual> <physical> <vote>`, `virtual-only <virtual>`) and the
// human-facing vote table with each pair's breakdown (docs/cli.md).

#include <string>

#include "annex/common/haptic_model.h"
#include "annex/common/object_finder.h"
#include "annex/common/physical_scene.h"

namespace annex {

// One line per virtual object, in spec order.
std::string format_match_lines(const HapticSpec& spec, const PhysicalScene& scene,
                               const MatchResult& result);

// The vote matrix (voters x physical objects) followed by every non-trivial pair's
// breakdown: chosen primitives, each dimension's sizes, ratio and weight, the product.
std::string format_vote_table(const HapticSpec& spec, const PhysicalScene& scene,
                              const MatchResult& result);

// One pair's breakdown, e.g. "v1 x p2: cylinder 'body' ~ cylinder#0: ...". Shared with the editor.
std::string format_explanation(const VirtualObject& v, const PhysicalObject& p,
                               const VoteExplanation& e);

}  // namespace annex
