#pragma once
// Match preview: what the runtime's ObjectFinder would decide for the spec being
// edited against a recorded or library scene, laid out for the editor's panel.

#include <optional>
#include <string>
#include <vector>

#include "annex/common/haptic_model.h"
#include "annex/common/object_finder.h"
#include "annex/common/physical_scene.h"

namespace annex::authoring {

struct Candidate {
  int physical = -1;  // into PhysicalScene::objects
  std::string id;
  VoteExplanation explanation;
  // The spec's exclude rule that keeps this prop out ("tall: shape any, prop_height
  // min 0.4"); empty when it takes part. Excluded props rank last, greyed.
  std::string excluded_by;
};

struct ObjectPreview {
  int object = -1;  // into HapticSpec::objects
  std::string name;
  bool voted = false;             // annexable objects vote
  std::vector<Candidate> ranked;  // every physical object, vote descending
  std::optional<int> assigned;    // Hungarian result; none: virtual-only
  std::string assigned_id;
  double assigned_vote = 0;
};

struct MatchPreview {
  std::vector<ObjectPreview> objects;  // spec order
  double total_vote = 0;
};

MatchPreview preview_match(const HapticSpec& spec, const PhysicalScene& scene,
                           const MatchParams& params = {});

}  // namespace annex::authoring
