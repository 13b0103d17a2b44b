// The scan config file: `key value...` lines, `#` comments, blank lines ignored.
// Every key names a ScanParams field (samples/config/scan.conf lists them all with
// the Kinect defaults). Errors: file:line:col.
#include <algorithm>
#include <charconv>
#include <optional>
#include <cmath>
#include <string>
#include <vector>

#include "annex/formats/file_io.h"
#include "annex/formats/text_lexer.h"
#include "annex/runtime/scanner.h"

namespace annex {
namespace {

// 'text' with its quotes (appended: GCC 12 warns falsely on "'" + std::string).
std::string in_quotes(std::string_view text) {
  std::string q(1, '\'');
  q.append(text);
  q.push_back('\'');
  return q;
}

enum class Kind { real, positive, non_negative, angle, whole, unit_share, flag };

struct Field {
  std::string_view key;
  Kind kind;
  double* real = nullptr;
  int* whole = nullptr;
  double min_whole = 0;
  bool* flag = nullptr;
};

}  // namespace

Result<ScanParams> parse_scan_config(std::string_view text, std::string_view origin) {
  ScanParams p;
  std::uint64_t seed = p.shape.seed;
  const std::vector<Field> fields = {
      {"camera_tilt_deg", Kind::angle, &p.camera_tilt_deg},
      {"depth_noise_base_m", Kind::non_negative, &p.depth_noise.base_m},
      {"depth_noise_quadratic", Kind::non_negative, &p.depth_noise.quadratic_per_m},
      {"depth_noise_centre_m", Kind::real, &p.depth_noise.centre_m},
      {"max_plane_angle_deg", Kind::angle, &p.max_plane_angle_deg},
      {"first_plane_fits_up", Kind::flag, nullptr, nullptr, 0, &p.first_plane_fits_up},
      {"first_plane_normals_up", Kind::flag, nullptr, nullptr, 0, &p.first_plane_normals_up},
      {"surface_max_incidence_deg", Kind::angle, &p.surface_max_incidence_deg},
      {"first_plane_noise_fit", Kind::flag, nullptr, nullptr, 0, &p.first_plane_noise_fit},
      {"noise_fit_min_turn_deg", Kind::angle, &p.noise_fit_min_turn_deg},
      {"plane_distance_m", Kind::positive, &p.plane_distance_m},
      {"plane_noise_factor", Kind::non_negative, &p.plane_noise_factor},
      {"band_along_ray", Kind::flag, nullptr, nullptr, 0, &p.band_along_ray},
      {"hull_margin_m", Kind::non_negative, &p.hull_margin_m},
      {"floor_margin_m", Kind::non_negative, &p.floor_margin_m},
      {"plane_iterations", Kind::whole, nullptr, &p.plane_iterations, 1},
      {"min_plane_points", Kind::whole, nullptr, &p.min_plane_points, 3},
      {"pixel_stride", Kind::whole, nullptr, &p.pixel_stride, 1},
      {"min_height_m", Kind::non_negative, &p.min_height_m},
      {"max_height_m", Kind::positive, &p.max_height_m},
      {"max_depth_m", Kind::positive, &p.max_depth_m},
      {"cluster_tolerance_m", Kind::positive, &p.cluster_tolerance_m},
      {"cluster_noise_factor", Kind::non_negative, &p.cluster_noise_factor},
      {"cluster_window_px", Kind::whole, nullptr, &p.cluster_window_px, 1},
      {"dropout_max_gap_px", Kind::whole, nullptr, &p.dropout_max_gap_px, 1},
      {"dropout_join_to_floor", Kind::flag, nullptr, nullptr, 0, &p.dropout_join_to_floor},
      {"min_cluster_points", Kind::whole, nullptr, &p.min_cluster_points, 12},
      {"max_cluster_points", Kind::whole, nullptr, &p.max_cluster_points, 12},
      {"mls_radius_m", Kind::non_negative, &p.mls_radius_m},
      {"mls_window_px", Kind::whole, nullptr, &p.mls_window_px, 1},
      {"min_view_cos", Kind::unit_share, &p.min_view_cos},
      {"part_margin_m", Kind::non_negative, &p.part_margin_m},
      {"part_share", Kind::unit_share, &p.part_share},
      {"part_hang_reach_m", Kind::non_negative, &p.part_hang_reach_m},
      {"neck_min_slope_deg", Kind::non_negative, &p.neck_min_slope_deg},
      {"neck_max_width_share", Kind::unit_share, &p.neck_max_width_share},
      {"part_fit_slack", Kind::unit_share, &p.part_fit_slack},
      {"unseen_hold_no_parts", Kind::flag, nullptr, nullptr, 0, &p.unseen_hold_no_parts},
      {"overhang_margin_m", Kind::non_negative, &p.overhang_margin_m},
      {"seen_part_reach_m", Kind::non_negative, &p.seen_part_reach_m},
      {"support_from_foot", Kind::flag, nullptr, nullptr, 0, &p.support_from_foot},
      {"touching_max_coverage", Kind::unit_share, &p.touching_max_coverage},
      {"touching_part_coverage", Kind::unit_share, &p.touching_part_coverage},
      {"touching_two_feet_coverage", Kind::unit_share, &p.touching_two_feet_coverage},
      {"touching_gap_evidence", Kind::non_negative, &p.touching_gap_evidence},
      {"touching_waist_share", Kind::unit_share, &p.touching_waist_share},
      {"touching_misfit_cut", Kind::flag, nullptr, nullptr, 0, &p.touching_misfit_cut},
      {"touching_level_cut", Kind::flag, nullptr, nullptr, 0, &p.touching_level_cut},
      {"touching_width_step", Kind::flag, nullptr, nullptr, 0, &p.touching_width_step},
      {"touching_min_part_size_m", Kind::positive, &p.touching_min_part_size_m},
      {"threads", Kind::whole, nullptr, &p.threads, 1},
      {"max_planes", Kind::whole, nullptr, &p.max_planes, 1},
      {"support_reach_m", Kind::positive, &p.support_reach_m},
      {"furniture_area_m2", Kind::non_negative, &p.furniture_area_m2},
      {"max_support_tilt_deg", Kind::angle, &p.max_support_tilt_deg},
      {"min_support_area_m2", Kind::non_negative, &p.min_support_area_m2},
      {"support_regions_seen_only", Kind::flag, nullptr, nullptr, 0, &p.support_regions_seen_only},
      {"min_support_gap_m", Kind::non_negative, &p.min_support_gap_m},
      {"support_gap_reach_m", Kind::non_negative, &p.support_gap_reach_m},
      {"support_gap_reach_sigmas", Kind::non_negative, &p.support_gap_reach_sigmas},
      {"support_edge_min_share", Kind::unit_share, &p.support_edge_min_share},
      {"support_floor_step_sigmas", Kind::non_negative, &p.support_floor_step_sigmas},
      {"edges_of_supports_only", Kind::flag, nullptr, nullptr, 0, &p.edges_of_supports_only},
      {"min_support_seen_share", Kind::unit_share, &p.min_support_seen_share},
      {"join_parted_surfaces", Kind::flag, nullptr, nullptr, 0, &p.join_parted_surfaces},
      {"grazing_support_deg", Kind::angle, &p.grazing_support_deg},
      {"grazing_max_seen_share", Kind::unit_share, &p.grazing_max_seen_share},
      {"grazing_max_through_share", Kind::unit_share, &p.grazing_max_through_share},
      {"under_width_share", Kind::unit_share, &p.under_width_share},
      {"legs_on_lowest_only", Kind::flag, nullptr, nullptr, 0, &p.legs_on_lowest_only},
      {"leg_top_reach_m", Kind::non_negative, &p.leg_top_reach_m},
      {"top_look_noise_sigmas", Kind::non_negative, &p.top_look_noise_sigmas},
      {"furniture_min_height_m", Kind::non_negative, &p.furniture_min_height_m},
      {"board_when_seen_under", Kind::flag, nullptr, nullptr, 0, &p.board_when_seen_under},
      {"on_top_noise_factor", Kind::non_negative, &p.on_top_noise_factor},
      {"furniture_min_width_m", Kind::non_negative, &p.furniture_min_width_m},
      {"min_stand_ratio", Kind::non_negative, &p.min_stand_ratio},
      {"cut_top_share", Kind::unit_share, &p.cut_top_share},
      {"drop_above_band_cut", Kind::flag, nullptr, nullptr, 0, &p.drop_above_band_cut},
      {"support_edge_m", Kind::non_negative, &p.support_edge_m},
      {"partial_when_top_hidden", Kind::flag, nullptr, nullptr, 0, &p.partial_when_top_hidden},
      {"hidden_foot_min_height_m", Kind::non_negative, &p.hidden_foot_min_height_m},
      {"partial_when_foot_behind_higher", Kind::flag, nullptr, nullptr, 0,
       &p.partial_when_foot_behind_higher},
      {"partial_when_seen_under", Kind::flag, nullptr, nullptr, 0, &p.partial_when_seen_under},
      {"seen_under_raised_bands", Kind::non_negative, &p.seen_under_raised_bands},
      {"support_slab_check", Kind::flag, nullptr, nullptr, 0, &p.support_slab_check},
      {"panel_noise_factor", Kind::non_negative, &p.panel_noise_factor},
      {"panel_flat_m", Kind::non_negative, &p.panel_flat_m},
      {"panel_span_share", Kind::non_negative, &p.panel_span_share},
      {"below_support_sigmas", Kind::non_negative, &p.below_support_sigmas},
      {"below_support_ends_at_objects", Kind::flag, nullptr, nullptr, 0,
       &p.below_support_ends_at_objects},
      {"edge_room_factor", Kind::non_negative, &p.edge_room_factor},
      {"support_fit_sigmas", Kind::non_negative, &p.support_fit_sigmas},
      {"support_fit_max_se_deg", Kind::non_negative, &p.support_fit_max_se_deg},
      {"support_fit_height_alone", Kind::flag, nullptr, nullptr, 0, &p.support_fit_height_alone},
      {"support_fit_facing_deg", Kind::angle, &p.support_fit_facing_deg},
      {"support_fit_median_test", Kind::flag, nullptr, nullptr, 0, &p.support_fit_median_test},
      {"min_cluster_points_far", Kind::whole, nullptr, &p.min_cluster_points_far, 12},
      {"border_px", Kind::whole, nullptr, &p.border_px, 0},
      {"foot_at_border", Kind::flag, nullptr, nullptr, 0, &p.foot_at_border},
      {"fitted_foot_at_border", Kind::flag, nullptr, nullptr, 0, &p.fitted_foot_at_border},
      {"sensor_min_range_m", Kind::non_negative, &p.sensor_min_range_m},
      {"near_cut_margin_m", Kind::non_negative, &p.near_cut_margin_m},
      {"pixel_units_focal_px", Kind::non_negative, &p.pixel_units_focal_px},
      {"min_whole_points", Kind::whole, nullptr, &p.min_whole_points, 0},
      {"hull_to_camera", Kind::flag, nullptr, nullptr, 0, &p.hull_to_camera},
      {"drop_cut_clusters", Kind::flag, nullptr, nullptr, 0, &p.drop_cut_clusters},
      {"cut_join_column_share", Kind::unit_share, &p.cut_join_column_share},
      {"shape_min_tolerance_m", Kind::positive, &p.shape.min_tolerance_m},
      {"shape_noise_factor", Kind::non_negative, &p.shape.noise_factor},
      {"shape_min_coverage", Kind::unit_share, &p.shape.min_coverage},
      {"shape_complexity_margin", Kind::unit_share, &p.shape.complexity_margin},
      {"shape_min_radius_m", Kind::positive, &p.shape.min_radius_m},
      {"shape_max_radius_m", Kind::positive, &p.shape.max_radius_m},
      {"shape_min_cone_taper", Kind::unit_share, &p.shape.min_cone_taper},
      {"shape_cone_taper_doubt", Kind::non_negative, &p.shape.cone_taper_doubt},
      {"shape_flat_cone_sides", Kind::flag, nullptr, nullptr, 0, &p.shape.flat_cone_sides},
      {"shape_lid_spread_sigmas", Kind::non_negative, &p.shape.lid_spread_sigmas},
      {"shape_circle_own_scatter", Kind::flag, nullptr, nullptr, 0, &p.shape.circle_own_scatter},
      {"shape_min_secondary_share", Kind::unit_share, &p.shape.min_secondary_share},
      {"shape_pair_min_secondary_share", Kind::unit_share, &p.shape.pair_min_secondary_share},
      {"shape_pair_max_neck_share", Kind::unit_share, &p.shape.pair_max_neck_share},
      {"shape_side_shape_penalty", Kind::unit_share, &p.shape.side_shape_penalty},
      {"shape_sphere_cap_depth_share", Kind::non_negative, &p.shape.sphere_cap_depth_share},
      {"shape_sphere_max_top_over_width", Kind::positive, &p.shape.sphere_max_top_over_width},
      {"shape_sphere_min_curvature_share", Kind::non_negative, &p.shape.sphere_min_curvature_share},
      {"shape_max_fit_points", Kind::whole, nullptr, &p.shape.max_fit_points, 50},
      {"shape_box_azimuth_doubt_m", Kind::non_negative, &p.shape.box_azimuth_doubt_m},
      {"shape_refine_sample_points", Kind::whole, nullptr, &p.shape.refine_sample_points, 0},
      {"shape_max_round_facetedness", Kind::unit_share, &p.shape.max_round_facetedness},
      {"shape_min_round_outline", Kind::unit_share, &p.shape.min_round_outline},
      {"shape_min_footprint_roundness", Kind::non_negative, &p.shape.min_footprint_roundness},
      {"shape_min_foot_seen_pixels", Kind::whole, nullptr, &p.shape.min_foot_seen_pixels, 1},
      {"shape_min_foot_seen_share", Kind::unit_share, &p.shape.min_foot_seen_share},
      {"shape_foot_seen_model_share", Kind::unit_share, &p.shape.foot_seen_model_share},
      {"shape_foot_seen_along_ray", Kind::flag, nullptr, nullptr, 0, &p.shape.foot_seen_along_ray},
      {"shape_own_side_hides", Kind::flag, nullptr, nullptr, 0, &p.shape.own_side_hides},
      {"shape_one_face_box_partial", Kind::flag, nullptr, nullptr, 0,
       &p.shape.one_face_box_partial},
      {"shape_torus_own_points", Kind::flag, nullptr, nullptr, 0, &p.shape.torus_own_points},
      {"segment_enabled", Kind::flag, nullptr, nullptr, 0, &p.segment.enabled},
      {"stack_on_objects", Kind::flag, nullptr, nullptr, 0, &p.stack_on_objects},
      {"join_occluded", Kind::flag, nullptr, nullptr, 0, &p.join_occluded},
      {"join_across_supports", Kind::flag, nullptr, nullptr, 0, &p.join_across_supports},
      {"segment_arm_m", Kind::positive, &p.segment.arm_m},
      {"segment_min_arm_px", Kind::positive, &p.segment.min_arm_px},
      {"segment_max_chord_slope", Kind::positive, &p.segment.max_chord_slope},
      {"segment_right_angle_depth_share", Kind::unit_share, &p.segment.right_angle_depth_share},
      {"segment_min_crease_depth_m", Kind::positive, &p.segment.min_crease_depth_m},
      {"segment_noise_factor", Kind::non_negative, &p.segment.noise_factor},
      {"segment_min_object_points", Kind::whole, nullptr, &p.segment.min_object_points, 0},
      {"segment_min_object_share", Kind::unit_share, &p.segment.min_object_share},
      {"segment_level_cut", Kind::flag, nullptr, nullptr, 0, &p.segment.level_cut},
      {"segment_level_min_span", Kind::unit_share, &p.segment.level_min_span},
      {"segment_level_min_height_m", Kind::positive, &p.segment.level_min_height_m},
      {"plane_candidates", Kind::flag, nullptr, nullptr, 0, &p.plane_candidates},
      {"plane_min_side_m", Kind::positive, &p.planes.min_side_m},
      {"plane_clearance_m", Kind::non_negative, &p.planes.clearance_m},
      {"plane_cell_m", Kind::positive, &p.planes.cell_m},
      {"plane_max_face_tilt_deg", Kind::angle, &p.planes.max_face_tilt_deg},
      {"plane_min_face_share", Kind::unit_share, &p.planes.min_face_share},
      {"plane_slab_ratio", Kind::unit_share, &p.planes.slab_ratio},
      {"plane_reach_m", Kind::positive, &p.planes.reach_m},
  };
  auto error = [&](std::string message, int line, int column) {
    return Error{std::move(message), {std::string(origin), line, column}};
  };
  auto number = [&](const detail::Token& t, int line, double& out) -> std::optional<Error> {
    const auto [end, ec] = std::from_chars(t.text.data(), t.text.data() + t.text.size(), out);
    if (ec != std::errc() || end != t.text.data() + t.text.size() || !std::isfinite(out))
      return error("expected a number, got " + in_quotes(t.text), line, t.column);
    return std::nullopt;
  };

  // The same lexer as the .haptic and .scene readers: comments, quoting and control
  // characters behave alike in every Annex text file.
  detail::Lexer lexer(text, origin);
  if (Status size = lexer.check_size(kMaxTextFileBytes); !size) return size.error();
  detail::Line parsed;
  while (true) {
    Result<bool> more = lexer.next(parsed);
    if (!more) return more.error();
    if (!*more) break;
    const int line_no = parsed.number;
    const std::vector<detail::Token>& tok = parsed.tokens;
    const std::string_view key = tok[0].text;
    const int want = key == "up" ? 3 : 1;
    if (static_cast<int>(tok.size()) - 1 != want) {
      const int col = tok.size() > static_cast<size_t>(want) + 1
                          ? tok[want + 1].column
                          : parsed.end_column;
      return error(in_quotes(key) + " takes " + std::to_string(want) +
                       (want == 1 ? " value" : " values"),
                   line_no, col);
    }
    if (key == "up") {
      double v[3];
      for (int k = 0; k < 3; ++k)
        if (auto e = number(tok[k + 1], line_no, v[k])) return *e;
      if (std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) < 1e-9)
        return error("'up' must not be the zero vector", line_no, tok[1].column);
      p.up = {v[0], v[1], v[2]};
    } else if (key == "supports") {
      Result<ScanParams> chosen = with_support_selection(p, tok[1].text);
      if (!chosen) return error(chosen.error().message, line_no, tok[1].column);
      p = *chosen;
    } else if (key == "depth_noise") {
      const std::optional<DepthNoise> noise = depth_noise_named(tok[1].text);
      if (!noise)
        return error("'depth_noise' expects one of " + std::string(kDepthNoiseNames) + ", got " +
                         in_quotes(tok[1].text),
                     line_no, tok[1].column);
      p.depth_noise = *noise;
    } else if (key == "seed") {
      std::uint64_t s = 0;
      const std::string_view t = tok[1].text;
      const auto [e, ec] = std::from_chars(t.data(), t.data() + t.size(), s);
      if (ec != std::errc() || e != t.data() + t.size())
        return error("expected a whole number >= 0, got " + in_quotes(t), line_no,
                     tok[1].column);
      seed = s;
    } else {
      const Field* field = nullptr;
      for (const Field& f : fields)
        if (f.key == key) field = &f;
      if (!field) {
        std::vector<std::string_view> keys{"up", "seed", "supports", "depth_noise"};
        for (const Field& f : fields) keys.push_back(f.key);
        return error("unknown key " + in_quotes(key) + detail::suggestion(key, keys), line_no,
                     tok[0].column);
      }
      double x = 0;
      if (auto e = number(tok[1], line_no, x)) return *e;
      const int col = tok[1].column;
      switch (field->kind) {
        case Kind::real:
          break;
        case Kind::positive:
          if (x <= 0) return error(in_quotes(key) + " must be > 0", line_no, col);
          break;
        case Kind::non_negative:
          if (x < 0) return error(in_quotes(key) + " must be >= 0", line_no, col);
          break;
        case Kind::angle:
          if (x < 0 || x > 90)
            return error(in_quotes(key) + " must be within [0, 90] degrees", line_no,
                         col);
          break;
        case Kind::unit_share:
          if (x < 0 || x > 1)
            return error(in_quotes(key) + " must be within [0, 1]", line_no, col);
          break;
        case Kind::flag:
          if (x != 0 && x != 1)
            return error(in_quotes(key) + " must be 0 or 1", line_no, col);
          *field->flag = x == 1;
          break;
        case Kind::whole:
          if (x != std::floor(x) || x < field->min_whole || x > 1e7)
            return error(in_quotes(key) + " must be a whole number >= " +
                             std::to_string(static_cast<int>(field->min_whole)),
                         line_no, col);
          break;
      }
      if (field->real) *field->real = x;
      if (field->whole) *field->whole = static_cast<int>(x);
    }
  }
  if (p.max_height_m <= p.min_height_m)
    return error("max_height_m must exceed min_height_m", 0, 0);
  if (p.shape.max_radius_m <= p.shape.min_radius_m)
    return error("shape_max_radius_m must exceed shape_min_radius_m", 0, 0);
  if (!p.depth_noise.positive()) return error(std::string(kDepthNoiseMustBePositive), 0, 0);
  p.shape.seed = seed;
  return p;
}

Result<ScanParams> with_support_selection(ScanParams params, std::string_view choice) {
  const std::pair<std::string_view, SupportSelection> names[] = {
      {"all", SupportSelection::all},
      {"nearest", SupportSelection::nearest},
      {"highest", SupportSelection::highest},
      {"largest", SupportSelection::largest}};
  for (const auto& [name, value] : names)
    if (choice == name) {
      params.supports = value;
      params.support_id.clear();
      return params;
    }
  // A support id: 's' and a whole number from 1.
  const bool id = choice.size() >= 2 && choice[0] == 's' && choice[1] != '0' &&
                  std::all_of(choice.begin() + 1, choice.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (!id)
    return Error{"supports must be all, nearest, highest, largest or a support id such as s2, got '" +
                     std::string(choice) + "'",
                 {}};
  params.supports = SupportSelection::id;
  params.support_id = std::string(choice);
  return params;
}

Result<ScanParams> read_scan_config_file(const std::filesystem::path& path) {
  Result<std::string> text = read_text_file(path);
  if (!text) return text.error();
  return parse_scan_config(*text, path.string());
}

}  // namespace annex
