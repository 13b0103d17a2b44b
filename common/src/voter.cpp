#include "annex/common/voter.h"

#include <algorithm>
#include <numeric>

namespace annex {

std::vector<int> primitive_priority_order(const VirtualObject& object) {
  std::vector<int> order(object.primitives.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return object.primitives[a].weight > object.primitives[b].weight;
  });
  return order;
}

namespace {

// Boxes and planes have no canonical axis order on a scan: compare sizes sorted largest
// first, carrying each virtual dimension's weight with it.
struct Sized {
  double value;
  double weight;
  int index;
};

VoteExplanation score_pair(const VirtualObject& v, int vi, const PhysicalPrimitive& pp,
                           const VoteParams& params) {
  const Primitive& prim = v.primitives[vi];
  VoteExplanation e;
  e.virtual_primitive = vi;
  e.object_weight = v.priority;
  e.primitive_weight = prim.weight;

  const auto names = dimension_names(prim.kind);
  const size_t n = std::min({names.size(), prim.dimensions.size(), pp.dimensions_m.size()});
  std::vector<Sized> vd, pd;
  for (size_t i = 0; i < n; ++i) {
    vd.push_back({prim.dimensions[i].value_m, prim.dimensions[i].weight, static_cast<int>(i)});
    pd.push_back({pp.dimensions_m[i], 0.0, static_cast<int>(i)});
  }
  if (prim.kind == ShapeKind::box || prim.kind == ShapeKind::plane) {
    auto larger = [](const Sized& a, const Sized& b) { return a.value > b.value; };
    std::stable_sort(vd.begin(), vd.end(), larger);
    std::stable_sort(pd.begin(), pd.end(), larger);
  }

  double weight_sum = 0;
  for (const Sized& d : vd) weight_sum += d.weight;
  // All w_h zero means "any size will do": the shape alone earns the full vote.
  const bool shape_only = weight_sum <= 0;

  double sum = 0;
  for (size_t i = 0; i < n; ++i) {
    DimensionTerm t;
    t.name = std::string(names[vd[i].index]);
    t.virtual_m = vd[i].value;
    t.physical_m = pd[i].value;
    const double hi = std::max(t.virtual_m, t.physical_m);
    t.ratio = hi > 0 ? std::min(t.virtual_m, t.physical_m) / hi : 0.0;
    t.weight = shape_only ? 1.0 / static_cast<double>(n) : vd[i].weight / weight_sum;
    sum += t.ratio * t.weight;
    e.terms.push_back(std::move(t));
  }
  e.dimension_sum = sum;
  e.vote = params.max_vote * v.priority * prim.weight * sum;
  return e;
}

}  // namespace

VoteExplanation explain_vote(const VirtualObject& v, const PhysicalObject& p,
                             const VoteParams& params) {
  for (int vi : primitive_priority_order(v)) {
    const ShapeKind kind = v.primitives[vi].kind;
    // The first shared shape decides; among several physical primitives of that
    // shape, the one that fits the virtual primitive best counts.
    VoteExplanation best;
    for (size_t pi = 0; pi < p.primitives.size(); ++pi) {
      if (p.primitives[pi].kind != kind) continue;
      VoteExplanation e = score_pair(v, vi, p.primitives[pi], params);
      e.physical_primitive = static_cast<int>(pi);
      if (best.physical_primitive < 0 || e.vote > best.vote) best = std::move(e);
    }
    if (best.physical_primitive >= 0) return best;
  }
  VoteExplanation none;
  none.object_weight = v.priority;
  return none;
}

}  // namespace annex
