// The HMD config file (sensor-to-HMD extrinsics, eye separation, per-eye displays)
// and the eyes it defines. The lines are read with the formats' lexer, so messages
// and positions match the .haptic and .scene readers.
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <string>

#include "annex/formats/file_io.h"
#include "annex/runtime/renderer.h"
#include "annex/formats/text_lexer.h"

namespace annex {
namespace {

using detail::error_at;
using detail::Line;
using detail::LineReader;
using detail::read_header;
using detail::shown;
using detail::Token;

constexpr std::string_view kHeader = "annex-hmd";
constexpr int kVersion = 1;
constexpr std::size_t kMaxConfigBytes = 64u << 10;
constexpr int kMaxEyePixels = 16384;
// Unknown keys are warned about one by one up to this many; the rest of a file that
// is not an hmd.conf at all (thousands of unknown lines) gets one summary warning
// instead of a message with suggestions per line.
constexpr int kMaxUnknownKeyWarnings = 10;

constexpr std::string_view kKeys[] = {"sensor_to_hmd_translation",
                                      "sensor_to_hmd_rotation",
                                      "eye_separation",
                                      "resolution",
                                      "fov",
                                      "intrinsics",
                                      "left_intrinsics",
                                      "right_intrinsics",
                                      "near",
                                      "far"};

struct Pinhole {
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

Result<Pinhole> read_pinhole(LineReader& r, std::string_view key) {
  Pinhole p;
  for (double* v : {&p.fx, &p.fy}) {
    auto x = r.positive(key);
    if (!x) return x.error();
    *v = *x;
  }
  for (double* v : {&p.cx, &p.cy}) {
    auto x = r.number(key);
    if (!x) return x.error();
    *v = *x;
  }
  return p;
}

}  // namespace

Result<HmdConfig> parse_hmd_config(std::string_view text, std::string_view origin,
                                   std::vector<Diagnostic>* warnings) {
  detail::Lexer lexer(text, origin);
  if (auto st = lexer.check_size(kMaxConfigBytes); !st) return st.error();

  HmdConfig hmd;
  std::map<std::string, int, std::less<>> seen;  // key -> line, for duplicates
  int width = 640, height = 480;
  std::optional<double> fov_deg;
  std::optional<Pinhole> both, left, right;
  Token fov_token, intrinsics_token;
  bool have_header = false;
  int unknown_keys = 0, last_unknown_line = 0;
  Location first_unwarned;
  Line line;

  for (;;) {
    auto more = lexer.next(line);
    if (!more) return more.error();
    if (!*more) break;
    LineReader r(line, origin);
    const Token key = r.take();

    if (!have_header) {
      if (auto st = read_header(r, key, kHeader, kVersion); !st) return st.error();
      have_header = true;
      continue;
    }

    bool known = !key.quoted;
    if (known) {
      known = false;
      for (std::string_view k : kKeys) known = known || key.text == k;
    }
    if (!known) {
      if (warnings != nullptr && unknown_keys < kMaxUnknownKeyWarnings)
        warnings->push_back(Diagnostic{
            "unknown key " + shown(key) + " ignored" + detail::suggestion(key.text, kKeys),
            Location{std::string(origin), key.line, key.column}});
      else if (unknown_keys == kMaxUnknownKeyWarnings)
        first_unwarned = Location{std::string(origin), key.line, key.column};
      ++unknown_keys;
      last_unknown_line = key.line;
      continue;
    }
    if (auto it = seen.find(key.text); it != seen.end())
      return error_at(
          origin, key,
          "duplicate key '" + key.text + "' (first at line " + std::to_string(it->second) + ")");
    seen.emplace(key.text, key.line);

    if (key.text == "sensor_to_hmd_translation") {
      double* xyz[] = {&hmd.hmd_from_sensor.position.x, &hmd.hmd_from_sensor.position.y,
                       &hmd.hmd_from_sensor.position.z};
      for (double* v : xyz) {
        auto x = r.number(key.text);
        if (!x) return x.error();
        *v = *x;
      }
    } else if (key.text == "sensor_to_hmd_rotation") {
      Quat q;
      for (double* v : {&q.w, &q.x, &q.y, &q.z}) {
        auto x = r.number(key.text);
        if (!x) return x.error();
        *v = *x;
      }
      const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
      if (std::abs(n - 1.0) > detail::kNormTolerance)
        return error_at(origin, key,
                        "'sensor_to_hmd_rotation' must be a unit quaternion w x y z; its norm is " +
                            detail::format_number(n));
      hmd.hmd_from_sensor.rotation = normalized(q);
    } else if (key.text == "eye_separation") {
      auto x = r.positive(key.text);
      if (!x) return x.error();
      hmd.eye_separation_m = *x;
    } else if (key.text == "resolution") {
      for (int* v : {&width, &height}) {
        auto n = r.non_negative_int(key.text);
        if (!n) return n.error();
        if (*n < 1 || *n > kMaxEyePixels)
          return error_at(origin, r.last(),
                          "'resolution' must be between 1 and " + std::to_string(kMaxEyePixels) +
                              " pixels, found " + shown(r.last()));
        *v = *n;
      }
    } else if (key.text == "fov") {
      auto x = r.number(key.text);
      if (!x) return x.error();
      if (!(*x > 0 && *x < 180))
        return error_at(origin, r.last(),
                        "'fov' is the vertical field of view in degrees, in (0, 180); found " +
                            shown(r.last()));
      fov_deg = *x;
      fov_token = key;
    } else if (key.text == "near" || key.text == "far") {
      auto x = r.positive(key.text);
      if (!x) return x.error();
      (key.text == "near" ? hmd.near_m : hmd.far_m) = *x;
    } else {  // the three intrinsics keys
      auto p = read_pinhole(r, key.text);
      if (!p) return p.error();
      (key.text == "intrinsics" ? both : key.text == "left_intrinsics" ? left : right) = *p;
      if (key.text == "intrinsics") intrinsics_token = key;
    }
    if (auto st = r.expect_end(key.text); !st) return st.error();
  }

  if (!have_header)
    return Error{"empty input; expected the header 'annex-hmd 1'", lexer.end_location()};
  if (warnings != nullptr && unknown_keys > kMaxUnknownKeyWarnings) {
    const int more = unknown_keys - kMaxUnknownKeyWarnings;
    warnings->push_back(Diagnostic{std::to_string(more) + " more unknown key" +
                                       (more == 1 ? "" : "s") + " ignored, from here to line " +
                                       std::to_string(last_unknown_line),
                                   std::move(first_unwarned)});
  }
  if (fov_deg && both)
    return error_at(origin, fov_token.line > intrinsics_token.line ? fov_token : intrinsics_token,
                    "'fov' and 'intrinsics' both set; give one of them");
  if (hmd.far_m <= hmd.near_m) {
    const auto line_of = [&](std::string_view k) {
      auto it = seen.find(k);
      return it == seen.end() ? 0 : it->second;
    };
    return error_at(origin, std::max(line_of("near"), line_of("far")), 1,
                    "'far' (" + detail::format_number(hmd.far_m) +
                        ") must be greater than 'near' (" + detail::format_number(hmd.near_m) +
                        ")");
  }

  // Without intrinsics the eyes are centred pinholes of the given vertical field
  // of view (60 degrees by default).
  Pinhole base;
  if (both) {
    base = *both;
  } else {
    const double f = 0.5 * height / std::tan(0.5 * fov_deg.value_or(60.0) * std::numbers::pi / 180);
    base = {f, f, 0.5 * (width - 1), 0.5 * (height - 1)};
  }
  const auto eye = [&](const std::optional<Pinhole>& own) {
    const Pinhole p = own.value_or(base);
    return CameraIntrinsics{width, height, p.fx, p.fy, p.cx, p.cy};
  };
  hmd.left = eye(left);
  hmd.right = eye(right);
  return hmd;
}

Result<HmdConfig> read_hmd_config(const std::filesystem::path& path,
                                  std::vector<Diagnostic>* warnings) {
  auto text = read_text_file(path, kMaxConfigBytes);
  if (!text) return text.error();
  return parse_hmd_config(*text, path.string(), warnings);
}

Eye sensor_eye(const CameraIntrinsics& camera) {
  return Eye{camera, Affine{}, 0.05, 20.0};
}

std::array<Eye, 2> hmd_eyes(const HmdConfig& hmd) {
  const Affine hmd_from_sensor = affine_from_pose(hmd.hmd_from_sensor);
  // An eye at x = e in the HMD frame sees a point p_hmd at p_hmd - (e, 0, 0).
  const auto eye = [&](const CameraIntrinsics& in, double eye_x) {
    Affine eye_from_hmd;
    eye_from_hmd.m[3] = -eye_x;
    return Eye{in, eye_from_hmd * hmd_from_sensor, hmd.near_m, hmd.far_m};
  };
  return {eye(hmd.left, -0.5 * hmd.eye_separation_m), eye(hmd.right, 0.5 * hmd.eye_separation_m)};
}

}  // namespace annex
