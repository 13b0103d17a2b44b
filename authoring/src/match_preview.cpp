#include "annex/authoring/match_preview.h"

#include <algorithm>

#include "annex/common/prop_exclusion.h"

namespace annex::authoring {

MatchPreview preview_match(const HapticSpec& spec, const PhysicalScene& scene,
                           const MatchParams& params) {
  const MatchResult result = match_objects(spec, scene, params);
  MatchPreview out;
  out.total_vote = result.total_vote;
  for (std::size_t i = 0; i < spec.objects.size(); ++i) {
    ObjectPreview o;
    o.object = static_cast<int>(i);
    o.name = spec.objects[i].name;
    out.objects.push_back(std::move(o));
  }
  for (std::size_t r = 0; r < result.voters.size(); ++r) {
    ObjectPreview& o = out.objects[result.voters[r]];
    o.voted = true;
    for (std::size_t p = 0; p < result.table[r].size(); ++p) {
      Candidate c{static_cast<int>(p), scene.objects[p].id, result.table[r][p], {}};
      if (p < result.excluded_by.size() && result.excluded_by[p] >= 0) {
        const ExcludeRule& rule = spec.exclude[static_cast<std::size_t>(result.excluded_by[p])];
        c.excluded_by = rule.name + ": " + describe_exclude_rule(rule);
      }
      o.ranked.push_back(std::move(c));
    }
    std::stable_sort(o.ranked.begin(), o.ranked.end(), [](const Candidate& a, const Candidate& b) {
      if (a.excluded_by.empty() != b.excluded_by.empty()) return a.excluded_by.empty();
      return a.explanation.vote > b.explanation.vote;
    });
  }
  for (const MatchEntry& m : result.matches) {
    if (m.virtual_index < 0 || m.virtual_index >= static_cast<int>(out.objects.size())) continue;
    ObjectPreview& o = out.objects[m.virtual_index];
    o.assigned = m.physical_index;
    o.assigned_vote = m.vote;
    if (m.physical_index) o.assigned_id = scene.objects[*m.physical_index].id;
  }
  return out;
}

}  // namespace annex::authoring
