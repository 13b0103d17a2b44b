#pragma once
// The ObjectFinder's decision: every annexable virtual object without a prop votes
// for every physical object, and the Hungarian method picks the assignment with the
// highest total vote. A virtual object left on a dummy or zero-vote edge (or below
// the threshold) stays virtual-only.

#include <optional>
#include <string>
#include <vector>

#include "annex/common/assignment.h"
#include "annex/common/haptic_model.h"
#include "annex/common/physical_scene.h"
#include "annex/common/voter.h"

namespace annex {

struct MatchParams {
  VoteParams vote;
  double min_vote = 0.0;  // pairs voting at or below this are never matched
  // Objects a scan saw only in part (cut by the image border, too few points) are no
  // candidates unless this is set: a prop the user cannot grab whole is a poor prop.
  bool partial_objects_vote = false;
};

struct MatchEntry {
  int virtual_index = -1;                // into HapticSpec::objects
  std::optional<int> physical_index;     // into PhysicalScene::objects; none: virtual-only
  double vote = 0;
};

struct MatchResult {
  std::vector<int> voters;                 // spec indices of the virtual objects that voted
  std::vector<std::vector<VoteExplanation>> table;  // [voter][physical object]
  std::vector<MatchEntry> matches;         // one per spec object, in spec order
  double total_vote = 0;
};

// `taken` marks physical objects already annexed (they do not take part); `matched`
// marks virtual objects that already have a prop (they do not vote). Either may be empty.
MatchResult match_objects(const HapticSpec& spec, const PhysicalScene& scene,
                          const MatchParams& params = {},
                          const std::vector<bool>& matched = {},
                          const std::vector<bool>& taken = {});

}  // namespace annex
