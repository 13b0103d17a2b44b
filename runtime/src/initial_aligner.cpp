// InitialAligner, seeded part: yaw hypotheses at candidate centres, refined by ICP.
#include "annex/runtime/initial_aligner.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace annex {
namespace {

Quat axis_angle(Vec3 axis, double angle_rad) {
  const Vec3 a = normalized(axis);
  const double s = std::sin(angle_rad / 2);
  return {std::cos(angle_rad / 2), a.x * s, a.y * s, a.z * s};
}

bool better(const IcpResult& a, const IcpResult& b) {
  if (a.ok != b.ok) return a.ok;
  if (std::abs(a.fitness - b.fitness) > 0.02) return a.fitness > b.fitness;
  return a.rms_m < b.rms_m;
}

}  // namespace

InitialAlignResult align_initial(const TrackingModel& model, const InitialAlignInput& input,
                                 const InitialAlignParams& params) {
  InitialAlignResult out;
  if (input.frame == nullptr || model.points.empty()) return out;
  const Vec3 up = input.support ? input.support->normal : rotate(input.orientation, {0, 0, 1});
  const int yaws = model.symmetry == Symmetry::spherical ? 1 : std::max(1, params.yaw_hypotheses);
  const double half = model.radius_m + params.search_margin_m;
  // ICP from a seed may turn freely, but its result must stay within the volume searched
  // around the seed: a centre farther than `half` was pulled there by points at the
  // cube's edge, of something else (a hidden sphere's model fits a neighbouring
  // cylinder's side at 0.6-0.7 fitness).
  IcpParams icp = params.icp;
  icp.max_step_m = half;
  icp.max_step_deg = 180;

  std::vector<Vec3> positions;
  for (const Vec3& p : input.positions) {
    const bool near_seen =
        std::any_of(positions.begin(), positions.end(), [&](Vec3 q) { return norm(q - p) < 0.01; });
    if (!near_seen) positions.push_back(p);
  }

  IcpResult best;
  bool have = false;
  for (const Vec3& p : positions) {
    const TargetCloud target =
        segment_target_volume(*input.frame, input.camera, p, half, input.support);
    if (target.points.size() < 20) continue;
    for (int k = 0; k < yaws; ++k) {
      const Quat q =
          normalized(axis_angle(up, 2 * std::numbers::pi * k / yaws) * input.orientation);
      const IcpResult r = track_icp(model, target, {p, q}, icp);
      ++out.hypotheses;
      if (!have || better(r, best)) {
        best = r;
        have = true;
      }
    }
  }
  if (have && best.ok && best.fitness >= params.min_fitness) {
    out = {true, best.pose, best.fitness, best.rms_m, "seed", out.hypotheses};
    return out;
  }

  // Fallback: FPFH + RANSAC around the most likely position, for shapes whose
  // orientation the seeds cannot cover.
  if (params.fpfh_fallback && model.symmetry == Symmetry::none && !positions.empty()) {
    const TargetCloud target =
        segment_target_volume(*input.frame, input.camera, positions.front(), half, input.support);
    if (target.points.size() >= 50) {
      if (const auto guess = align_fpfh(model, target, params.fpfh)) {
        const IcpResult r = track_icp(model, target, *guess, icp);
        ++out.hypotheses;
        if (r.ok && r.fitness >= params.min_fitness)
          return {true, r.pose, r.fitness, r.rms_m, "fpfh", out.hypotheses};
      }
    }
  }
  if (have) {
    out.pose = best.pose;
    out.fitness = best.fitness;
    out.rms_m = best.rms_m;
  }
  return out;
}

}  // namespace annex
