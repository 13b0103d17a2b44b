// Drawing the scan overlay: plain raster code (lines, quads of stb_easy_font's
// glyphs) on an RGB buffer, then the shared PNG writer.
#include "annex/runtime/scan_overlay.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "annex/formats/file_io.h"
#include "annex/formats/png_io.h"
#include "annex/runtime/target_volume_segmenter.h"

#include <stb/stb_easy_font.h>

namespace annex {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

constexpr Rgb kPalette[] = {{255, 80, 80},  {80, 200, 255}, {120, 255, 100}, {255, 200, 40},
                            {220, 100, 255}, {255, 140, 200}, {60, 255, 220}, {255, 255, 255}};

// RGB (3 channels) or RGBA (4, drawn opaque) pixels, row-major.
struct Canvas {
  std::uint8_t* px;
  int width, height, channels = 3;
  explicit Canvas(RgbImage& img) : px(img.rgb.data()), width(img.width), height(img.height) {}
  Canvas(std::uint8_t* pixels, int w, int h, int ch) : px(pixels), width(w), height(h), channels(ch) {}
  void put(int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    std::uint8_t* p = &px[(static_cast<size_t>(y) * width + x) * channels];
    p[0] = c[0];
    p[1] = c[1];
    p[2] = c[2];
    if (channels == 4) p[3] = 255;
  }
  void line(double x0, double y0, double x1, double y1, Rgb c, int thick = 1) {
    if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1))
      return;
    const double len = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
    if (len > 4 * (width + height)) return;  // projected from behind the camera
    const int steps = std::max(1, static_cast<int>(len));
    for (int i = 0; i <= steps; ++i) {
      const double t = static_cast<double>(i) / steps;
      const int x = static_cast<int>(std::lround(x0 + (x1 - x0) * t));
      const int y = static_cast<int>(std::lround(y0 + (y1 - y0) * t));
      for (int dy = 0; dy < thick; ++dy)
        for (int dx = 0; dx < thick; ++dx) put(x + dx, y + dy, c);
    }
  }
  void fill(int x0, int y0, int x1, int y1, Rgb c) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) put(x, y, c);
  }
  // stb_easy_font emits quads; `scale` enlarges its 7-pixel-high glyphs.
  void text(int x, int y, const std::string& s, Rgb c, int scale = 2) {
    std::vector<char> buf(s.size() * 300 + 64);
    std::string copy = s;
    const int quads = stb_easy_font_print(0, 0, copy.data(), nullptr, buf.data(),
                                          static_cast<int>(buf.size()));
    const int w = stb_easy_font_width(copy.data()) * scale;
    fill(x - 2, y - 2, x + w + 2, y + 7 * scale + 2, {0, 0, 0});
    for (int q = 0; q < quads; ++q) {
      const float* v0 = reinterpret_cast<const float*>(buf.data() + q * 4 * 16);
      const float* v2 = reinterpret_cast<const float*>(buf.data() + (q * 4 + 2) * 16);
      fill(x + static_cast<int>(v0[0] * scale), y + static_cast<int>(v0[1] * scale),
           x + static_cast<int>(v2[0] * scale), y + static_cast<int>(v2[1] * scale), c);
    }
  }
};

struct Projector {
  double fx, fy, cx, cy;
  std::array<double, 2> operator()(Vec3 p) const {
    if (p.z < 0.05) return {NAN, NAN};
    return {fx * p.x / p.z + cx, fy * p.y / p.z + cy};
  }
};

void polyline(Canvas& c, const Projector& proj, const std::vector<Vec3>& pts, Rgb col,
              bool closed) {
  for (size_t i = 0; i + 1 < pts.size() + (closed ? 1 : 0); ++i) {
    const auto a = proj(pts[i]);
    const auto b = proj(pts[(i + 1) % pts.size()]);
    c.line(a[0], a[1], b[0], b[1], col, 2);
  }
}

std::vector<Vec3> circle(Vec3 center, Vec3 u, Vec3 v, double r, int n = 48) {
  std::vector<Vec3> out;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * 3.14159265358979 * i / n;
    out.push_back(center + u * (r * std::cos(t)) + v * (r * std::sin(t)));
  }
  return out;
}

// A plane primitive's rectangle with its diagonals (so a panel reads as flat).
void draw_rectangle(Canvas& c, const Projector& proj, const PhysicalPrimitive& p, Rgb col) {
  if (p.dimensions_m.size() < 2) return;
  const Vec3 n = normalized(p.axis);
  Vec3 u = p.x_axis - n * dot(p.x_axis, n);
  if (norm(u) < 1e-9) u = rotate(rotation_from_z(n), {1, 0, 0});
  u = normalized(u);
  const Vec3 hx = u * (p.dimensions_m[0] / 2), hy = cross(n, u) * (p.dimensions_m[1] / 2);
  const std::vector<Vec3> corners = {p.center - hx - hy, p.center + hx - hy, p.center + hx + hy,
                                     p.center - hx + hy};
  polyline(c, proj, corners, col, true);
  polyline(c, proj, {corners[0], corners[2]}, col, false);
  polyline(c, proj, {corners[1], corners[3]}, col, false);
}

void draw_primitive(Canvas& c, const Projector& proj, const ShapeFit& fit, Rgb col) {
  const PhysicalPrimitive& p = fit.primitive;
  const Vec3 a = normalized(p.axis);
  Vec3 u = normalized(fit.x_axis - a * dot(fit.x_axis, a));
  if (norm(cross(u, a)) < 0.5) u = normalized(cross(a, std::abs(a.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
  const Vec3 v = cross(a, u);
  const auto& d = p.dimensions_m;
  switch (p.kind) {
    case ShapeKind::sphere: {
      polyline(c, proj, circle(p.center, u, v, d[0]), col, true);
      polyline(c, proj, circle(p.center, u, a, d[0]), col, true);
      polyline(c, proj, circle(p.center, v, a, d[0]), col, true);
      break;
    }
    case ShapeKind::cylinder:
    case ShapeKind::cone: {
      const double h = d[1];
      const Vec3 base = p.center - a * (h / 2), top = p.center + a * (h / 2);
      const double r_top = p.kind == ShapeKind::cone ? p.narrow_radius_m : d[0];
      polyline(c, proj, circle(base, u, v, d[0]), col, true);
      if (r_top > 0) polyline(c, proj, circle(top, u, v, r_top), col, true);
      for (int k = 0; k < 8; ++k) {
        const double t = 2 * 3.14159265358979 * k / 8;
        const Vec3 dir = u * std::cos(t) + v * std::sin(t);
        polyline(c, proj, {base + dir * d[0], top + dir * r_top}, col, false);
      }
      break;
    }
    case ShapeKind::torus: {
      polyline(c, proj, circle(p.center, u, v, d[0] + d[1]), col, true);
      polyline(c, proj, circle(p.center, u, v, d[0] - d[1]), col, true);
      polyline(c, proj, circle(p.center + a * d[1], u, v, d[0]), col, true);
      break;
    }
    case ShapeKind::plane: draw_rectangle(c, proj, p, col); break;
    case ShapeKind::box: {
      const Vec3 hx = u * (d[0] / 2), hy = v * (d[1] / 2), hz = a * (d[2] / 2);
      std::vector<Vec3> corners;
      for (int k = 0; k < 8; ++k)
        corners.push_back(p.center + hx * ((k & 1) ? 1 : -1) + hy * ((k & 2) ? 1 : -1) +
                          hz * ((k & 4) ? 1 : -1));
      for (int i = 0; i < 8; ++i)
        for (int bit : {1, 2, 4})
          if (!(i & bit)) polyline(c, proj, {corners[i], corners[i | bit]}, col, false);
      break;
    }
  }
}

// The overlay's labels: text `scale` times stb_easy_font's 7-pixel glyphs, each box
// laid out by layout_labels in the region [x0, x0 + width) of the canvas, whose
// coordinates the labels' bounds use.
template <typename Get>
void place_labels(Canvas& canvas, size_t count, Get get, int region_x0, int region_width) {
  const int scale = region_width >= 480 ? 2 : 1;  // 14 px glyphs on VGA, 7 px on QVGA
  std::vector<LabelRequest> requests;
  for (size_t i = 0; i < count; ++i) {
    const auto& l = get(i);
    std::string copy = l.text;
    requests.push_back({stb_easy_font_width(copy.data()) * scale + 4, 7 * scale + 4, l.top,
                        l.bottom, l.left, l.right});
  }
  const std::vector<LabelBox> boxes = layout_labels(requests, region_width, canvas.height);
  for (size_t i = 0; i < count; ++i)
    canvas.text(region_x0 + boxes[i].x0 + 2, boxes[i].y0 + 2, get(i).text, get(i).colour, scale);
}

}  // namespace

void draw_labels(std::uint8_t* pixels, int image_width, int image_height, int channels,
                 const std::vector<ImageLabel>& labels, int region_x0, int region_width) {
  if (pixels == nullptr || (channels != 3 && channels != 4) || image_width <= 0 ||
      image_height <= 0)
    return;
  if (region_width < 0) region_width = image_width - region_x0;
  region_x0 = std::clamp(region_x0, 0, image_width);
  region_width = std::clamp(region_width, 0, image_width - region_x0);
  if (region_width == 0) return;
  Canvas canvas(pixels, image_width, image_height, channels);
  place_labels(canvas, labels.size(), [&](size_t i) -> const ImageLabel& { return labels[i]; },
               region_x0, region_width);
}

namespace {

bool has_colour(const Frame& frame) {
  for (const PointXYZRGB& p : frame.points)
    if (std::isfinite(p.z) && (p.r | p.g | p.b)) return true;
  return false;
}

// The scene under the outlines: the sensor's colour dimmed, or, for a cloud without
// colour (a depth-only sensor, a model such as milk.pcd), its depth in grey (near is
// light), so the user still sees what was scanned. An unorganized cloud is drawn as the
// scanner re-organizes it: projected with the Kinect's intrinsics, the nearest point
// per pixel.
void paint_background(const Frame& frame, RgbImage& img) {
  img.rgb.assign(static_cast<size_t>(img.width) * img.height * 3, 0);
  const bool organized = frame.organized();
  if (organized && has_colour(frame)) {
    for (size_t i = 0; i < frame.points.size(); ++i) {
      const PointXYZRGB& p = frame.points[i];
      std::uint8_t* o = &img.rgb[i * 3];
      o[0] = p.r * 2 / 5;
      o[1] = p.g * 2 / 5;
      o[2] = p.b * 2 / 5;
    }
    return;
  }
  const CameraIntrinsics k;
  std::vector<float> depth(static_cast<size_t>(img.width) * img.height, 0.0f);
  float near = std::numeric_limits<float>::max(), far = 0;
  for (size_t i = 0; i < frame.points.size(); ++i) {
    const PointXYZRGB& p = frame.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !(p.z > 0)) continue;
    size_t at = i;
    if (!organized) {
      const long u = std::lround(k.fx * p.x / p.z + k.cx), v = std::lround(k.fy * p.y / p.z + k.cy);
      if (u < 0 || v < 0 || u >= img.width || v >= img.height) continue;
      at = static_cast<size_t>(v) * img.width + static_cast<size_t>(u);
    }
    if (depth[at] == 0 || p.z < depth[at]) depth[at] = p.z;
    near = std::min(near, p.z);
    far = std::max(far, p.z);
  }
  const float span = std::max(far - near, 1e-3f);
  for (size_t i = 0; i < depth.size(); ++i) {
    if (depth[i] == 0) continue;
    const auto grey = static_cast<std::uint8_t>(140 - 100 * (depth[i] - near) / span);
    img.rgb[i * 3] = img.rgb[i * 3 + 1] = img.rgb[i * 3 + 2] = grey;
  }
}

}  // namespace

RgbImage draw_scan_overlay(const Frame& frame, const ScanResult& scan,
                           const CameraIntrinsics& intrinsics) {
  RgbImage img;
  const bool organized = frame.organized();
  img.width = organized ? frame.width : 640;
  img.height = organized ? frame.height : 480;
  paint_background(frame, img);
  const double sx = static_cast<double>(img.width) / intrinsics.width;
  const double sy = static_cast<double>(img.height) / intrinsics.height;
  Projector proj{intrinsics.fx * sx, intrinsics.fy * sy, (intrinsics.cx + 0.5) * sx - 0.5,
                 (intrinsics.cy + 0.5) * sy - 0.5};
  // An organized cloud carries its own intrinsics, so outlines land on the image even
  // for sensors whose intrinsics differ from the Kinect defaults.
  if (organized)
    if (const Result<CameraIntrinsics> k = estimate_intrinsics(frame))
      proj = {k->fx, k->fy, k->cx, k->cy};
  Canvas canvas(img);
  // Each support's hull, its id at its first vertex (selected ones bright).
  for (const ScanSupport& sp : scan.supports) {
    const Rgb col = sp.selected ? Rgb{120, 220, 255} : Rgb{90, 110, 130};
    polyline(canvas, proj, sp.hull, col, true);
    for (const Vec3& q : sp.hull)
      if (q.z > 0.1) {
        const double u = proj.fx * q.x / q.z + proj.cx, v = proj.fy * q.y / q.z + proj.cy;
        if (u >= 0 && v >= 0 && u < img.width - 40 && v < img.height - 12) {
          canvas.text(static_cast<int>(u) + 3, static_cast<int>(v) + 3, sp.surface.id, col);
          break;
        }
      }
  }
  for (size_t k = 0; k < scan.clusters.size(); ++k) {
    const Rgb col = kPalette[k % std::size(kPalette)];
    for (int i : scan.clusters[k].pixels) {
      if (i < 0 || static_cast<size_t>(i) * 3 >= img.rgb.size()) continue;
      std::uint8_t* o = &img.rgb[static_cast<size_t>(i) * 3];
      for (int ch = 0; ch < 3; ++ch) o[ch] = static_cast<std::uint8_t>((o[ch] + col[ch]) / 2);
    }
  }
  // Outlines first, labels last: no wireframe is drawn over a label.
  std::vector<ImageLabel> labels;
  for (size_t k = 0; k < scan.clusters.size(); ++k) {
    const Rgb col = kPalette[k % std::size(kPalette)];
    const auto& prims = scan.clusters[k].shape.primitives;
    const bool partial = k < scan.scene.objects.size() && scan.scene.objects[k].partial;
    // Partial objects (cut by the border, too few points) in grey: they do not vote.
    for (size_t j = 0; j < prims.size(); ++j)
      draw_primitive(canvas, proj, prims[j],
                     partial ? Rgb{140, 140, 140} : j == 0 ? Rgb{255, 255, 255} : Rgb{255, 255, 0});
    int top = img.height, left = img.width, right = 0, bottom = 0;
    for (int i : scan.clusters[k].pixels) {
      top = std::min(top, i / img.width);
      bottom = std::max(bottom, i / img.width);
      left = std::min(left, i % img.width);
      right = std::max(right, i % img.width);
    }
    // "p2 cylinder, part cone": the salient primitive, then the secondary ones.
    std::string text = k < scan.scene.objects.size() ? scan.scene.objects[k].id : "?";
    if (prims.empty()) text.append(" unknown");
    for (size_t j = 0; j < prims.size(); ++j)
      text.append(j == 0 ? " " : (j == 1 ? ", part " : ", ")).append(shape_name(prims[j].primitive.kind));
    if (k < scan.scene.objects.size() && !scan.scene.objects[k].on_object.empty())
      text.append(" on ").append(scan.scene.objects[k].on_object);
    if (partial) text.append(" partial");
    labels.push_back({std::move(text), col, top, bottom, left, right});
  }
  // Flat surfaces for virtual panels: rectangles in green, labelled "s1.free plane".
  for (const PhysicalObject& surface : scan.surfaces) {
    if (surface.primitives.empty()) continue;
    const PhysicalPrimitive& p = surface.primitives.front();
    // A surface of a partial object does not vote: grey and unlabelled, like its object.
    const Rgb col = surface.partial ? Rgb{140, 140, 140} : Rgb{80, 255, 120};
    draw_rectangle(canvas, proj, p, col);
    if (surface.partial) continue;
    const auto at = proj(p.center);
    if (!std::isfinite(at[0]) || !std::isfinite(at[1])) continue;
    const int x = static_cast<int>(at[0]), y = static_cast<int>(at[1]);
    labels.push_back({surface.id + " plane", col, y, y, x, x});
  }
  draw_labels(img.rgb.data(), img.width, img.height, 3, labels);
  return img;
}

std::vector<LabelBox> layout_labels(const std::vector<LabelRequest>& labels, int image_width,
                                    int image_height) {
  std::vector<LabelBox> placed;
  for (const LabelRequest& l : labels) {
    const int w = l.width, h = l.height;
    const int cx = (l.left + l.right) / 2 - w / 2;
    std::vector<std::pair<int, int>> spots = {{cx, l.top - h - 4},  {cx, l.bottom + 4},
                                              {l.right + 4, l.top}, {l.left - w - 4, l.top},
                                              {cx, (l.top + l.bottom) / 2 - h / 2}};
    for (int k = 1; k < 2 * image_height / std::max(1, h); ++k) {  // then further up and down
      spots.push_back({cx, l.top - h - 4 - k * h});
      spots.push_back({cx, l.bottom + 4 + k * h});
    }
    LabelBox best{};
    int best_overlaps = -1;
    for (auto [x, y] : spots) {
      x = std::clamp(x, 0, std::max(0, image_width - w));
      y = std::clamp(y, 0, std::max(0, image_height - h));
      const LabelBox b{x, y, x + w, y + h};
      int overlaps = 0;
      for (const LabelBox& o : placed) overlaps += b.overlaps(o) ? 1 : 0;
      if (best_overlaps < 0 || overlaps < best_overlaps) {
        best = b;
        best_overlaps = overlaps;
      }
      if (overlaps == 0) break;
    }
    placed.push_back(best);
  }
  return placed;
}

std::string encode_png(const RgbImage& image) {
  if (image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3) return {};
  return encode_png(image.width, image.height, 3, image.rgb.data());
}

Status write_png(const std::filesystem::path& path, const RgbImage& image) {
  const std::string bytes = encode_png(image);
  if (bytes.empty()) return Error{"could not encode the PNG image", {path.string(), 0, 0}};
  return write_file_atomically(path, bytes);
}

}  // namespace annex
