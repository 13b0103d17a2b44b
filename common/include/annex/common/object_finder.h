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
  // Pairs whose prop would need a dimension scaled beyond the primitive's scaling
  // limits are never matched (off: such a prop is matched and the model drawn clamped).
  bool within_limits = false;
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
  // Per physical object: the index into HapticSpec::exclude of the rule that keeps it
  // out of the match, or -1. Excluded objects are never assigned; their votes are still
  // in `table`, to show what the rule prevented.
  std::vector<int> excluded_by;
};

// The scale each dimension of the voting primitive would need on that prop (physical /
// virtual) and whether it lies within the primitive's limits. Empty without a vote.
struct LimitCheck {
  struct Need {
    std::string dimension;
    double scale = 1, min_scale = 1, max_scale = 1;
  };
  std::vector<Need> needs;
  bool within = true;
};
LimitCheck check_limits(const VirtualObject& v, const VoteExplanation& e);

// Why a pair may not be matched whatever the assignment: "" when it may, else e.g.
// "votes 9.92, under mug's min_vote 20". Checked in this order: no shared shape, the
// global threshold, the object's min_vote, the scaling limits (when asked for).
std::string pair_rejection(const VirtualObject& v, const VoteExplanation& e,
                           const MatchParams& params);

// `taken` marks physical objects already annexed (they do not take part); `matched`
// marks virtual objects that already have a prop (they do not vote). Either may be empty.
// Physical objects the spec's exclude rules forbid never take part (excluded_by).
MatchResult match_objects(const HapticSpec& spec, const PhysicalScene& scene,
                          const MatchParams& params = {},
                          const std::vector<bool>& matched = {},
                          const std::vector<bool>& taken = {});

}  // namespace annex
