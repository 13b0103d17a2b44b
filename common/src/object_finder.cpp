#include "annex/common/object_finder.h"

namespace annex {

MatchResult match_objects(const HapticSpec& spec, const PhysicalScene& scene,
                          const MatchParams& params, const std::vector<bool>& matched,
                          const std::vector<bool>& taken) {
  auto flag = [](const std::vector<bool>& flags, size_t i) {
    return i < flags.size() && flags[i];
  };
  MatchResult result;
  result.matches.resize(spec.objects.size());
  for (size_t i = 0; i < spec.objects.size(); ++i) {
    result.matches[i].virtual_index = static_cast<int>(i);
    if (spec.objects[i].annexable && !flag(matched, i))
      result.voters.push_back(static_cast<int>(i));
  }
  std::vector<int> candidates;
  for (size_t j = 0; j < scene.objects.size(); ++j)
    if (!flag(taken, j) && (params.partial_objects_vote || !scene.objects[j].partial))
      candidates.push_back(static_cast<int>(j));

  WeightMatrix weights{static_cast<int>(result.voters.size()),
                       static_cast<int>(candidates.size()), {}};
  weights.values.reserve(static_cast<size_t>(weights.rows) * weights.cols);
  result.table.resize(result.voters.size());
  for (size_t r = 0; r < result.voters.size(); ++r) {
    const VirtualObject& v = spec.objects[result.voters[r]];
    result.table[r].resize(scene.objects.size());
    for (int j : candidates) {
      VoteExplanation e = explain_vote(v, scene.objects[j], params.vote);
      // Pairs at or under the threshold act as dummy edges.
      weights.values.push_back(e.vote > params.min_vote ? e.vote : 0.0);
      result.table[r][j] = std::move(e);
    }
  }

  const Assignment a = max_weight_assignment(weights);
  for (size_t r = 0; r < result.voters.size(); ++r) {
    const int c = a.row_to_col[r];
    if (c < 0 || weights.at(static_cast<int>(r), c) <= 0) continue;
    MatchEntry& m = result.matches[result.voters[r]];
    m.physical_index = candidates[c];
    m.vote = weights.at(static_cast<int>(r), c);
    result.total_vote += m.vote;
  }
  return result;
}

}  // namespace annex
