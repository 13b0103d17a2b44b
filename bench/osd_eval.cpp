// Scoring against the OSD labels (bench/osd_eval.h).
#include "osd_eval.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "annex/formats/file_io.h"
#include "annex/runtime/depth_png.h"

namespace annex {

Result<OsdScene> read_osd_scene(const std::filesystem::path& dir, const std::string& name) {
  const CameraIntrinsics k;  // the mOSD clouds' pixels: fx = fy = 525, cx = 319.5, cy = 239.5
  Result<Frame> frame =
      read_depth_frame(dir / (name + "_depth.png"), dir / (name + "_color.png"), k);
  if (!frame) return frame.error();
  Result<ColorImage> label = read_color_png(dir / (name + "_label.png"));
  if (!label) return label.error();
  if (label->width != frame->width || label->height != frame->height)
    return Error{"label image is " + std::to_string(label->width) + "x" +
                     std::to_string(label->height) + ", the depth image " +
                     std::to_string(frame->width) + "x" + std::to_string(frame->height),
                 {(dir / (name + "_label.png")).string(), 0, 0}};
  OsdScene s;
  s.name = name;
  s.frame = std::move(*frame);
  s.object_of_pixel.assign(s.frame.points.size(), 0);
  for (size_t i = 0; i < s.frame.points.size(); ++i) {
    const int l = label->rgb[3 * i];
    if (l < 10 || !std::isfinite(s.frame.points[i].z)) continue;
    s.object_of_pixel[i] = l / 10;
    ++s.labelled_points[l / 10];
  }
  return s;
}

OsdScene subsampled(const OsdScene& scene, int n) {
  if (n <= 1) return scene;
  OsdScene s;
  s.name = scene.name;
  s.frame = subsampled(scene.frame, n);
  s.object_of_pixel =
      every_nth_pixel(scene.object_of_pixel, scene.frame.width, scene.frame.height, n);
  // An object the sampling misses whole is no longer in the scene's truth.
  for (int id : s.object_of_pixel)
    if (id > 0) ++s.labelled_points[id];
  return s;
}

std::string OsdExpectations::class_of(const std::string& scene, int object) const {
  const auto s = classes.find(scene);
  if (s == classes.end()) return "any";
  const auto o = s->second.find(object);
  return o == s->second.end() ? "any" : o->second;
}

Result<OsdExpectations> parse_osd_expectations(std::string_view text, std::string_view origin) {
  OsdExpectations out;
  int line_no = 0;
  size_t pos = 0;
  while (pos <= text.size()) {
    const size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view line = text.substr(pos, end - pos);
    ++line_no;
    pos = end + 1;
    if (const size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    // Split into tokens with their 1-based columns.
    std::vector<std::pair<std::string, int>> tokens;
    for (size_t i = 0; i < line.size();) {
      if (line[i] == ' ' || line[i] == '\t' || line[i] == '\r') {
        ++i;
        continue;
      }
      size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
      tokens.emplace_back(std::string(line.substr(i, j - i)), static_cast<int>(i) + 1);
      i = j;
    }
    if (tokens.empty()) {
      if (end == text.size()) break;
      continue;
    }
    auto fail = [&](const std::string& msg, int col) {
      return Error{msg, {std::string(origin), line_no, col}};
    };
    if (tokens.size() != 3)
      return fail("expected 'SCENE OBJECT CLASS', got " + std::to_string(tokens.size()) + " fields",
                  tokens.front().second);
    char* stop = nullptr;
    const long id = std::strtol(tokens[1].first.c_str(), &stop, 10);
    if (*stop != '\0' || id < 1 || id > 25)
      return fail("object id must be a whole number 1-25, got '" + tokens[1].first + "'",
                  tokens[1].second);
    const std::string& cls = tokens[2].first;
    if (cls != "box" && cls != "cylinder" && cls != "frustum" && cls != "any")
      return fail("class must be box, cylinder, frustum or any, got '" + cls + "'",
                  tokens[2].second);
    auto& scene = out.classes[tokens[0].first];
    if (scene.count(static_cast<int>(id)))
      return fail("object " + tokens[1].first + " of " + tokens[0].first + " listed twice",
                  tokens[1].second);
    scene[static_cast<int>(id)] = cls;
    if (end == text.size()) break;
  }
  return out;
}

Result<OsdExpectations> read_osd_expectations_file(const std::filesystem::path& path) {
  Result<std::string> text = read_text_file(path);
  if (!text) return text.error();
  return parse_osd_expectations(*text, path.string());
}

std::string osd_category(int n) {
  if (n <= 16) return "boxes";
  if (n <= 24) return "stacked";
  if (n <= 32) return "occluded";
  return "round";
}

namespace {

// The pixel of `pixels` farthest from every pixel outside them (chamfer distance, 1
// across and sqrt 2 diagonally), among those within half a pixel of that farthest
// distance the one nearest to the points' mean (sx, sy, sz sums) projected to the image.
int most_interior_pixel(const std::vector<int>& pixels, int width, int height, double sx,
                        double sy, double sz, const CameraIntrinsics& k) {
  if (pixels.empty() || width <= 0 || height <= 0) return -1;
  int u0 = width, u1 = -1, v0 = height, v1 = -1;
  for (int i : pixels) {
    u0 = std::min(u0, i % width);
    u1 = std::max(u1, i % width);
    v0 = std::min(v0, i / width);
    v1 = std::max(v1, i / width);
  }
  // A one-pixel frame of outside pixels round the object's box.
  const int w = u1 - u0 + 3, h = v1 - v0 + 3;
  constexpr double kFar = 1e9, kDiag = 1.4142135623730951;
  std::vector<double> dist(static_cast<size_t>(w) * h, 0.0);
  for (int i : pixels) dist[static_cast<size_t>(i / width - v0 + 1) * w + (i % width - u0 + 1)] = kFar;
  auto at = [&](int x, int y) -> double& { return dist[static_cast<size_t>(y) * w + x]; };
  for (int y = 1; y < h - 1; ++y)
    for (int x = 1; x < w - 1; ++x)
      if (at(x, y) > 0)
        at(x, y) = std::min({at(x, y), at(x - 1, y) + 1, at(x, y - 1) + 1, at(x - 1, y - 1) + kDiag,
                             at(x + 1, y - 1) + kDiag});
  double deepest = 0;
  for (int y = h - 2; y >= 1; --y)
    for (int x = w - 2; x >= 1; --x)
      if (at(x, y) > 0) {
        at(x, y) = std::min({at(x, y), at(x + 1, y) + 1, at(x, y + 1) + 1, at(x + 1, y + 1) + kDiag,
                             at(x - 1, y + 1) + kDiag});
        deepest = std::max(deepest, at(x, y));
      }
  const bool has_mean = sz > 0;
  const double mu = has_mean ? k.fx * sx / sz + k.cx : 0, mv = has_mean ? k.fy * sy / sz + k.cy : 0;
  int pick = -1;
  double best = 1e300;
  for (int i : pixels) {
    if (at(i % width - u0 + 1, i / width - v0 + 1) < deepest - 0.5) continue;
    const double du = i % width - mu, dv = i / width - mv;
    if (pick < 0 || du * du + dv * dv < best) {
      best = du * du + dv * dv;
      pick = i;
    }
  }
  return pick;
}

}  // namespace

OsdSceneScore score_osd_scene(const OsdScene& scene, const ScanResult& scan,
                              const OsdExpectations& expectations) {
  OsdSceneScore score;
  const Frame& f = scene.frame;
  const CameraIntrinsics k;
  std::map<int, int> found_by;  // object id -> reported index holding it whole
  score.reported = static_cast<int>(scan.clusters.size());
  for (size_t r = 0; r < scan.clusters.size(); ++r) {
    const ScanCluster& c = scan.clusters[r];
    double sx = 0, sy = 0, sz = 0;
    std::map<int, int> held;
    for (int i : c.pixels) {
      sx += f.points[i].x;
      sy += f.points[i].y;
      sz += f.points[i].z;
      ++held[scene.object_of_pixel[i]];
    }
    // The centre: the object's most interior pixel (farthest from any pixel not its
    // own), the one nearest to its points' mean projected to the image among equals.
    // An object seen as an L or a ring (a lower box around the one standing on it) has
    // its mean on its neighbour, and its own pixel nearest that mean on its inner edge,
    // where crease pixels the labels give the neighbour lie; its interior lies on itself.
    int centre_on = 0;
    if (const int p = most_interior_pixel(c.pixels, f.width, f.height, sx, sy, sz, k); p >= 0)
      centre_on = scene.object_of_pixel[p];
    int big_shares = 0;
    for (const auto& [id, n] : held)
      if (id > 0 && n > 0.25 * scene.labelled_points.at(id)) ++big_shares;
    const bool merge = big_shares >= 2;
    score.merges += merge;
    double ratio = 0;
    if (centre_on > 0) ratio = static_cast<double>(c.pixels.size()) / scene.labelled_points.at(centre_on);
    const bool whole = centre_on > 0 && ratio >= 0.5 && ratio <= 1.6;
    const bool fragment = centre_on > 0 && ratio < 0.5;
    score.fragments += fragment;
    if (whole) {
      ++score.whole;
      if (!found_by.count(centre_on)) found_by[centre_on] = static_cast<int>(r);
    }
    const std::string kind =
        c.shape.primitives.empty() ? "unknown" : std::string(shape_name(c.shape.primitives.front().primitive.kind));
    // The label holding most of its pixels (0: the table or no label), and its share.
    int most = 0, most_n = 0;
    for (const auto& [id, n] : held)
      if (n > most_n) most = id, most_n = n;
    char note[240];
    std::snprintf(note, sizeof note,
                  "reported %zu %s points=%zu centre_on=%d ratio=%.2f most=%d:%.2f%s%s%s", r,
                  kind.c_str(), c.pixels.size(), centre_on, ratio, most,
                  c.pixels.empty() ? 0.0 : static_cast<double>(most_n) / c.pixels.size(),
                  whole ? " whole" : "", fragment ? " fragment" : "", merge ? " merge" : "");
    score.notes.push_back(note);
  }
  std::map<int, std::array<double, 3>> centre;  // object id -> sum u, sum v, count
  for (size_t i = 0; i < scene.object_of_pixel.size(); ++i)
    if (const int id = scene.object_of_pixel[i]; id > 0) {
      auto& c = centre[id];
      c[0] += static_cast<double>(i % f.width);
      c[1] += static_cast<double>(i / f.width);
      c[2] += 1;
    }
  for (const auto& [id, n] : scene.labelled_points) {
    OsdObjectScore o;
    o.id = id;
    o.labelled_points = n;
    o.expected = expectations.class_of(scene.name, id);
    ++score.labelled;
    if (const auto it = found_by.find(id); it != found_by.end()) {
      o.found = true;
      ++score.found;
      const ScanCluster& c = scan.clusters[it->second];
      o.reported = c.shape.primitives.empty() ? "unknown"
                                              : std::string(shape_name(c.shape.primitives.front().primitive.kind));
    }
    if (o.expected == "box") {
      ++score.box_expected;
      o.shape_ok = o.reported == "box";
      score.box_ok += o.shape_ok;
    } else if (o.expected == "cylinder") {
      ++score.cylinder_expected;
      o.shape_ok = o.reported == "cylinder";
      score.cylinder_ok += o.shape_ok;
    } else if (o.expected == "frustum") {
      ++score.frustum_expected;
      o.shape_ok = o.reported == "cone" || o.reported == "cylinder";
      score.frustum_ok += o.shape_ok;
    }
    char note[160];
    const auto& c = centre[id];
    std::snprintf(note, sizeof note, "object %d at u=%.0f v=%.0f points=%d expected=%s found=%d as=%s",
                  id, c[0] / c[2], c[1] / c[2], n, o.expected.c_str(), o.found, o.reported.c_str());
    score.notes.push_back(note);
    score.objects.push_back(o);
  }
  return score;
}

}  // namespace annex
