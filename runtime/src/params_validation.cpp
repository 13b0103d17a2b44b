// Range checks of the parameter structs, one message per field.
#include "annex/runtime/params_validation.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace annex {
namespace {

std::string number(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

// Collects the first failed check, so each validator reads as a list of rules.
class Checker {
 public:
  explicit Checker(std::string_view prefix) : prefix_(prefix) {}

  // lo < x (strict) or lo <= x, and x <= hi; NaN always fails.
  void range(std::string_view field, double x, double lo, double hi, bool strict_lo = false) {
    if (error_) return;
    const bool ok = std::isfinite(x) && (strict_lo ? x > lo : x >= lo) && x <= hi;
    if (ok) return;
    std::string rule = std::isinf(hi) ? std::string(strict_lo ? "greater than " : "at least ") + number(lo)
                                      : std::string("in ") + (strict_lo ? "(" : "[") + number(lo) +
                                            ", " + number(hi) + "]";
    fail(field, "must be " + rule + ", got " + number(x));
  }
  void positive(std::string_view field, double x) { range(field, x, 0, INFINITY, true); }
  void non_negative(std::string_view field, double x) { range(field, x, 0, INFINITY); }
  void at_least(std::string_view field, double x, double lo) { range(field, x, lo, INFINITY); }
  void fail(std::string_view field, const std::string& what) {
    if (error_) return;
    error_ = Error{std::string(prefix_) + "." + std::string(field) + " " + what, {}};
  }
  void merge(const Status& s) {
    if (!error_ && !s) error_ = s.error();
  }
  Status status() const { return error_ ? Status{*error_} : Status{Ok{}}; }

 private:
  std::string prefix_;
  std::optional<Error> error_;
};

}  // namespace

Status validate_scan_params(const ScanParams& p, std::string_view prefix) {
  Checker c(prefix);
  const double up = std::sqrt(p.up.x * p.up.x + p.up.y * p.up.y + p.up.z * p.up.z);
  if (!(up > 1e-9) || !std::isfinite(up)) c.fail("up", "must be a non-zero direction");
  c.range("camera_tilt_deg", p.camera_tilt_deg, -90, 90);
  c.range("max_plane_angle_deg", p.max_plane_angle_deg, 0, 90);
  c.positive("plane_distance_m", p.plane_distance_m);
  c.non_negative("plane_noise_factor", p.plane_noise_factor);
  c.non_negative("pixel_units_focal_px", p.pixel_units_focal_px);
  if (!p.depth_noise.positive())
    c.fail(
        "depth_noise",
        "must be above 0 at every depth (base_m > 0, or quadratic_per_m > 0 with centre_m <= 0)");
  c.at_least("plane_iterations", p.plane_iterations, 1);
  // A pixel's prism mark holds 1 + a support's index, or past a seen part 1 + the count
  // + the index, in a byte.
  c.range("max_planes", p.max_planes, 1, 60);
  c.at_least("min_plane_points", p.min_plane_points, 3);
  c.at_least("pixel_stride", p.pixel_stride, 1);
  c.non_negative("hull_margin_m", p.hull_margin_m);
  c.non_negative("min_height_m", p.min_height_m);
  c.positive("max_height_m", p.max_height_m);
  if (p.max_height_m <= p.min_height_m)
    c.fail("max_height_m", "must be greater than min_height_m (" + number(p.min_height_m) +
                               "), got " + number(p.max_height_m));
  c.positive("max_depth_m", p.max_depth_m);
  c.positive("cluster_tolerance_m", p.cluster_tolerance_m);
  c.at_least("cluster_window_px", p.cluster_window_px, 1);
  c.at_least("dropout_max_gap_px", p.dropout_max_gap_px, 1);
  c.at_least("min_cluster_points", p.min_cluster_points, 1);
  c.at_least("max_cluster_points", p.max_cluster_points, 1);
  c.non_negative("mls_radius_m", p.mls_radius_m);
  c.at_least("mls_window_px", p.mls_window_px, 1);
  c.range("min_view_cos", p.min_view_cos, 0, 1);
  c.non_negative("part_margin_m", p.part_margin_m);
  c.non_negative("part_hang_reach_m", p.part_hang_reach_m);
  c.range("neck_min_slope_deg", p.neck_min_slope_deg, 0, 90);
  c.range("neck_max_width_share", p.neck_max_width_share, 0, 1);
  c.non_negative("overhang_margin_m", p.overhang_margin_m);
  c.non_negative("seen_part_reach_m", p.seen_part_reach_m);
  c.range("part_share", p.part_share, 0, 1);
  c.range("part_fit_slack", p.part_fit_slack, 0, 1);
  c.range("touching_max_coverage", p.touching_max_coverage, 0, 1);
  c.range("touching_part_coverage", p.touching_part_coverage, 0, 1);
  c.range("touching_two_feet_coverage", p.touching_two_feet_coverage, 0, 1);
  c.non_negative("touching_gap_evidence", p.touching_gap_evidence);
  c.range("touching_waist_share", p.touching_waist_share, 0, 1);
  c.positive("touching_min_part_size_m", p.touching_min_part_size_m);
  c.range("min_support_seen_share", p.min_support_seen_share, 0, 1);
  c.range("grazing_support_deg", p.grazing_support_deg, 0, 45);
  c.range("grazing_max_seen_share", p.grazing_max_seen_share, 0, 1);
  c.range("grazing_max_through_share", p.grazing_max_through_share, 0, 1);
  c.non_negative("support_gap_reach_m", p.support_gap_reach_m);
  c.non_negative("support_gap_reach_sigmas", p.support_gap_reach_sigmas);
  c.range("support_edge_min_share", p.support_edge_min_share, 0, 1);
  c.non_negative("support_floor_step_sigmas", p.support_floor_step_sigmas);
  c.non_negative("sensor_min_range_m", p.sensor_min_range_m);
  c.non_negative("near_cut_margin_m", p.near_cut_margin_m);
  c.non_negative("panel_flat_m", p.panel_flat_m);
  c.positive("shape.min_tolerance_m", p.shape.min_tolerance_m);
  c.non_negative("shape.noise_factor", p.shape.noise_factor);
  c.range("shape.min_coverage", p.shape.min_coverage, 0, 1);
  c.non_negative("shape.complexity_margin", p.shape.complexity_margin);
  c.positive("shape.min_radius_m", p.shape.min_radius_m);
  c.range("shape.max_radius_m", p.shape.max_radius_m, p.shape.min_radius_m, INFINITY);
  c.range("shape.min_cone_taper", p.shape.min_cone_taper, 0, 1);
  c.non_negative("shape.cone_taper_doubt", p.shape.cone_taper_doubt);
  c.range("shape.min_secondary_share", p.shape.min_secondary_share, 0, 1);
  c.range("shape.pair_min_secondary_share", p.shape.pair_min_secondary_share, 0, 1);
  c.range("shape.pair_max_neck_share", p.shape.pair_max_neck_share, 0, 1);
  c.non_negative("shape.side_shape_penalty", p.shape.side_shape_penalty);
  c.at_least("shape.max_fit_points", p.shape.max_fit_points, 10);
  c.non_negative("shape.box_azimuth_doubt_m", p.shape.box_azimuth_doubt_m);
  c.at_least("shape.refine_sample_points", p.shape.refine_sample_points, 0);
  c.positive("planes.min_side_m", p.planes.min_side_m);
  c.non_negative("planes.clearance_m", p.planes.clearance_m);
  c.positive("planes.cell_m", p.planes.cell_m);
  c.range("planes.max_face_tilt_deg", p.planes.max_face_tilt_deg, 0, 90);
  c.range("planes.min_face_share", p.planes.min_face_share, 0, 1);
  c.range("planes.slab_ratio", p.planes.slab_ratio, 0, 1);
  c.positive("planes.reach_m", p.planes.reach_m);
  c.at_least("threads", p.threads, 1);
  return c.status();
}

Status validate_tracker_params(const PoseTrackerParams& p, std::string_view prefix) {
  Checker c(prefix);
  c.non_negative("volume_margin_m", p.volume_margin_m);
  c.at_least("volume.stride_px", p.volume.stride_px, 1);
  c.at_least("volume.max_visited_pixels", p.volume.max_visited_pixels, 1);
  c.non_negative("volume.min_height_m", p.volume.min_height_m);
  c.non_negative("volume.support_noise_sigmas", p.volume.support_noise_sigmas);
  c.at_least("volume.normal_step_px", p.volume.normal_step_px, 1);
  for (const auto& [name, icp] : {std::pair<const char*, const IcpParams*>{"icp", &p.icp},
                                  {"align.icp", &p.align.icp}}) {
    const std::string f = name;
    c.positive(f + ".max_correspondence_m", icp->max_correspondence_m);
    c.range(f + ".final_correspondence_m", icp->final_correspondence_m, 0,
            icp->max_correspondence_m, true);
    c.at_least(f + ".max_iterations", icp->max_iterations, 1);
    c.non_negative(f + ".convergence_m", icp->convergence_m);
    c.positive(f + ".inlier_m", icp->inlier_m);
    c.range(f + ".min_fitness", icp->min_fitness, 0, 1);
    c.positive(f + ".max_rms_m", icp->max_rms_m);
    c.positive(f + ".max_step_m", icp->max_step_m);
    c.range(f + ".max_step_deg", icp->max_step_deg, 0, 180, true);
  }
  c.at_least("align.yaw_hypotheses", p.align.yaw_hypotheses, 1);
  c.non_negative("align.search_margin_m", p.align.search_margin_m);
  c.range("align.min_fitness", p.align.min_fitness, 0, 1);
  c.at_least("max_failures", p.max_failures, 0);
  return c.status();
}

Status validate_intrinsics(const CameraIntrinsics& k, std::string_view prefix) {
  Checker c(prefix);
  c.at_least("width", k.width, 1);
  c.at_least("height", k.height, 1);
  c.positive("fx", k.fx);
  c.positive("fy", k.fy);
  c.range("cx", k.cx, -0.5, k.width + 0.5);
  c.range("cy", k.cy, -0.5, k.height + 0.5);
  return c.status();
}

Status validate_session_params(const SessionParams& p) {
  Checker c("SessionParams");
  c.merge(validate_scan_params(p.scan, "SessionParams.scan"));
  c.merge(validate_tracker_params(p.tracker, "SessionParams.tracker"));
  if (p.camera) c.merge(validate_intrinsics(*p.camera, "SessionParams.camera"));
  c.positive("match.vote.max_vote", p.match.vote.max_vote);
  c.range("match.min_vote", p.match.min_vote, -INFINITY, INFINITY);
  c.at_least("scan_every", p.scan_every, 1);
  c.at_least("release_after_frames", p.release_after_frames, 1);
  c.at_least("threads", p.threads, 1);
  c.non_negative("same_prop_m", p.same_prop_m);
  c.at_least("model_points", p.model_points, 10);
  c.range("scan_nice", p.scan_nice, 0, 19);
  return c.status();
}

}  // namespace annex
