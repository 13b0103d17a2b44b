#include "annex/runtime/match_report.h"

#include <algorithm>
#include <cstdio>

#include "annex/common/prop_exclusion.h"

namespace annex {
namespace {

std::string fixed(double x, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, x);
  return buf;
}

std::string pad(std::string s, size_t width) {
  if (s.size() < width) s.append(width - s.size(), ' ');
  return s;
}

}  // namespace

std::string format_match_lines(const HapticSpec& spec, const PhysicalScene& scene,
                               const MatchResult& result) {
  std::string out;
  for (const MatchEntry& m : result.matches) {
    const std::string& name = spec.objects[m.virtual_index].name;
    if (m.physical_index)
      out += "match " + name + " " + scene.objects[*m.physical_index].id + " " +
             fixed(m.vote, 2) + "\n";
    else
      out += "virtual-only " + name + "\n";
  }
  return out;
}

std::string format_explanation(const VirtualObject& v, const PhysicalObject& p,
                               const VoteExplanation& e) {
  std::string out = v.name + " x " + p.id + ": ";
  if (e.virtual_primitive < 0) {
    out += "no shared shape, vote 0\n";
    return out;
  }
  const Primitive& prim = v.primitives[e.virtual_primitive];
  out += std::string(shape_name(prim.kind)) + " '" + prim.name + "' ~ " + p.id + " primitive " +
         std::to_string(e.physical_primitive + 1) + "\n";
  for (const DimensionTerm& t : e.terms) {
    out += "    " + pad(t.name, 13) + " virtual " + fixed(t.virtual_m, 4) + " m  physical " +
           fixed(t.physical_m, 4) + " m  ratio " + fixed(t.ratio, 3) + "  x w_h " +
           fixed(t.weight, 3) + " = " + fixed(t.ratio * t.weight, 3) + "\n";
  }
  out += "    vote = C x w_o " + fixed(e.object_weight, 3) + " x w_s " +
         fixed(e.primitive_weight, 3) + " x sum " + fixed(e.dimension_sum, 3) + " = " +
         fixed(e.vote, 2) + "\n";
  return out;
}

std::string format_vote_table(const HapticSpec& spec, const PhysicalScene& scene,
                              const MatchResult& result) {
  size_t name_width = 8;
  for (int v : result.voters) name_width = std::max(name_width, spec.objects[v].name.size() + 1);
  size_t col_width = 8;
  for (const auto& p : scene.objects) col_width = std::max(col_width, p.id.size() + 2);
  auto excluded = [&](size_t j) {
    return j < result.excluded_by.size() && result.excluded_by[j] >= 0;
  };
  // Votes of excluded props go in parentheses: room for them.
  for (size_t j = 0; j < scene.objects.size(); ++j)
    if (excluded(j)) col_width = std::max<size_t>(col_width, 10);

  std::string out = "votes (rows: virtual objects that vote; columns: physical objects)\n";
  out += pad("", name_width);
  for (const auto& p : scene.objects) out += pad(p.id, col_width);
  out += "\n";
  for (size_t r = 0; r < result.voters.size(); ++r) {
    out += pad(spec.objects[result.voters[r]].name, name_width);
    for (size_t j = 0; j < scene.objects.size(); ++j) {
      const std::string vote = fixed(result.table[r][j].vote, 2);
      out += pad(excluded(j) ? "(" + vote + ")" : vote, col_width);
    }
    out += "\n";
  }
  bool any_excluded = false;
  for (size_t j = 0; j < scene.objects.size(); ++j) {
    if (!excluded(j)) continue;
    if (!any_excluded) out += "\nexcluded by the spec (votes in parentheses, never matched)\n";
    any_excluded = true;
    const ExcludeRule& rule = spec.exclude[static_cast<size_t>(result.excluded_by[j])];
    char height[48];
    std::snprintf(height, sizeof height, "%.3f", prop_height_m(scene.objects[j], scene.support));
    out += "  " + scene.objects[j].id + ": rule '" + rule.name + "' (" +
           describe_exclude_rule(rule) + "); prop_height " + height + " m\n";
  }
  out += "\nbreakdown (pairs that share a shape)\n";
  for (size_t r = 0; r < result.voters.size(); ++r) {
    const VirtualObject& v = spec.objects[result.voters[r]];
    for (size_t j = 0; j < scene.objects.size(); ++j) {
      const VoteExplanation& e = result.table[r][j];
      if (e.virtual_primitive >= 0) out += format_explanation(v, scene.objects[j], e);
    }
  }
  out += "\ntotal vote " + fixed(result.total_vote, 2) + "\n";
  return out;
}

}  // namespace annex
