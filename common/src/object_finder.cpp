#include "annex/common/object_finder.h"

#include <cstdio>
#include "annex/common/prop_exclusion.h"

namespace annex {

namespace {

std::string fixed2(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

}  // namespace

LimitCheck check_limits(const VirtualObject& v, const VoteExplanation& e) {
  LimitCheck out;
  if (e.virtual_primitive < 0) return out;
  const Primitive& p = v.primitives[static_cast<size_t>(e.virtual_primitive)];
  for (const DimensionTerm& t : e.terms) {
    const int d = dimension_index(p.kind, t.name);
    if (d < 0 || t.virtual_m <= 0) continue;
    const Dimension& dim = p.dimensions[static_cast<size_t>(d)];
    LimitCheck::Need n{t.name, t.physical_m / t.virtual_m, dim.min_scale, dim.max_scale};
    out.within = out.within && n.scale >= n.min_scale && n.scale <= n.max_scale;
    out.needs.push_back(std::move(n));
  }
  return out;
}

std::string pair_rejection(const VirtualObject& v, const VoteExplanation& e,
                           const MatchParams& params) {
  if (e.virtual_primitive < 0 || e.vote <= 0) return "shares no primitive shape";
  if (e.vote <= params.min_vote)
    return "votes " + fixed2(e.vote) + ", at or under --min-vote " + fixed2(params.min_vote);
  if (e.vote < v.min_vote)
    return "votes " + fixed2(e.vote) + ", under " + v.name + "'s min_vote " + fixed2(v.min_vote);
  if (params.within_limits) {
    const LimitCheck c = check_limits(v, e);
    for (const LimitCheck::Need& n : c.needs)
      if (n.scale < n.min_scale || n.scale > n.max_scale)
        return "needs " + n.dimension + " scaled x" + fixed2(n.scale) + ", outside its limits " +
               fixed2(n.min_scale) + ".." + fixed2(n.max_scale);
  }
  return "";
}

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
  result.excluded_by.assign(scene.objects.size(), -1);
  for (size_t j = 0; j < scene.objects.size(); ++j) {
    if (flag(taken, j)) continue;
    if (!params.partial_objects_vote && scene.objects[j].partial) continue;
    // Heights (exclusion rules) are measured from the support the object stands on,
    // not from the scene's first one: a prop on a shelf is as tall as itself.
    std::optional<Plane> own = scene.support;
    for (const SupportSurface& s : scene.supports)
      if (s.id == scene.objects[j].support_id) own = s.plane;
    if (auto rule = excluding_rule(spec, scene.objects[j], own)) {
      result.excluded_by[j] = *rule;
      continue;
    }
    candidates.push_back(static_cast<int>(j));
  }

  WeightMatrix weights{static_cast<int>(result.voters.size()),
                       static_cast<int>(candidates.size()), {}};
  weights.values.reserve(static_cast<size_t>(weights.rows) * weights.cols);
  result.table.resize(result.voters.size());
  for (size_t r = 0; r < result.voters.size(); ++r) {
    const VirtualObject& v = spec.objects[result.voters[r]];
    result.table[r].resize(scene.objects.size());
    for (int j : candidates) {
      VoteExplanation e = explain_vote(v, scene.objects[j], params.vote);
      // Pairs at or under a threshold (or beyond the limits, when asked) act as dummy edges.
      weights.values.push_back(pair_rejection(v, e, params).empty() ? e.vote : 0.0);
      result.table[r][j] = std::move(e);
    }
    for (size_t j = 0; j < scene.objects.size(); ++j)
      if (result.excluded_by[j] >= 0) result.table[r][j] = explain_vote(v, scene.objects[j], params.vote);
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
