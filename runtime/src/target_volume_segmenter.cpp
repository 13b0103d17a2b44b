// TargetVolumeSegmenter on the organized grid: project the cube, visit its rectangle.
#include "annex/runtime/target_volume_segmenter.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "annex/runtime/object_shape_recognizer.h"

namespace annex {
namespace {

bool valid(const PointXYZRGB& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && p.z > 0;
}

Vec3 to_vec(const PointXYZRGB& p) {
  return {p.x, p.y, p.z};
}

// Least-squares line y = a x + b.
bool fit_line(const std::vector<double>& x, const std::vector<double>& y, double& a, double& b) {
  const double n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  const double var = sxx - sx * sx / n;
  if (var <= 1e-12) return false;
  a = (sxy - sx * sy / n) / var;
  b = (sy - a * sx) / n;
  return true;
}

// Grid normal at pixel (u, v) from its neighbours `s` pixels away; zero when the
// neighbourhood is broken (dropouts, depth edges).
Vec3 grid_normal(const Frame& f, int u, int v, int s, Vec3 p) {
  auto at = [&](int uu, int vv, Vec3& out) {
    if (uu < 0 || vv < 0 || uu >= f.width || vv >= f.height) return false;
    const PointXYZRGB& q = f.points[static_cast<size_t>(vv) * f.width + uu];
    if (!valid(q)) return false;
    out = to_vec(q);
    return std::abs(out.z - p.z) < 0.02 + 0.02 * p.z * s;
  };
  Vec3 r, l, d, up;
  const bool hr = at(u + s, v, r), hl = at(u - s, v, l), hd = at(u, v + s, d),
             hu = at(u, v - s, up);
  if (!hr && !hl) return {0, 0, 0};
  if (!hd && !hu) return {0, 0, 0};
  const Vec3 dx = (hr ? r : p) - (hl ? l : p);
  const Vec3 dy = (hd ? d : p) - (hu ? up : p);
  Vec3 n = cross(dx, dy);
  const double len = norm(n);
  if (len <= 0) return {0, 0, 0};
  n = n * (1.0 / len);
  if (dot(n, p) > 0) n = n * -1.0;
  return n;
}

}  // namespace

Result<CameraIntrinsics> estimate_intrinsics(const Frame& frame) {
  const std::string origin = "frame " + std::to_string(frame.index);
  if (!frame.organized())
    return Error{"an unorganized frame has no pixel grid to recover intrinsics from", {origin}};
  std::vector<double> ax, au, ay, av;
  const int step = 8;
  for (int v = 0; v < frame.height; v += step) {
    for (int u = 0; u < frame.width; u += step) {
      const PointXYZRGB& p = frame.points[static_cast<size_t>(v) * frame.width + u];
      if (!valid(p)) continue;
      ax.push_back(p.x / p.z);
      au.push_back(u);
      ay.push_back(p.y / p.z);
      av.push_back(v);
    }
  }
  if (ax.size() < 50) return Error{"too few valid pixels to recover intrinsics", {origin}};
  CameraIntrinsics k;
  k.width = frame.width;
  k.height = frame.height;
  if (!fit_line(ax, au, k.fx, k.cx) || !fit_line(ay, av, k.fy, k.cy) || k.fx <= 0 || k.fy <= 0)
    return Error{"the frame's points do not follow a pinhole model", {origin}};
  return k;
}

Vec3 grid_normal_at(const Frame& frame, int u, int v, int step_px) {
  if (!frame.organized() || u < 0 || v < 0 || u >= frame.width || v >= frame.height)
    return {0, 0, 0};
  const PointXYZRGB& p = frame.points[static_cast<size_t>(v) * frame.width + u];
  if (!valid(p)) return {0, 0, 0};
  return grid_normal(frame, u, v, std::max(1, step_px), to_vec(p));
}

PixelRect project_cube(const CameraIntrinsics& k, Vec3 c, double h) {
  double umin = 1e9, umax = -1e9, vmin = 1e9, vmax = -1e9;
  for (int i = 0; i < 8; ++i) {
    const Vec3 p{c.x + ((i & 1) ? h : -h), c.y + ((i & 2) ? h : -h), c.z + ((i & 4) ? h : -h)};
    // A corner behind (or at) the camera: the cube spans the image edge on that side;
    // clamp its depth so the rectangle grows to the border instead of flipping.
    const double z = std::max(p.z, 0.05);
    const double u = k.fx * p.x / z + k.cx, v = k.fy * p.y / z + k.cy;
    umin = std::min(umin, u);
    umax = std::max(umax, u);
    vmin = std::min(vmin, v);
    vmax = std::max(vmax, v);
  }
  if (c.z + h <= 0) return {};
  PixelRect r;
  r.u0 = std::clamp(static_cast<int>(std::floor(umin)), 0, k.width);
  r.u1 = std::clamp(static_cast<int>(std::ceil(umax)) + 1, 0, k.width);
  r.v0 = std::clamp(static_cast<int>(std::floor(vmin)), 0, k.height);
  r.v1 = std::clamp(static_cast<int>(std::ceil(vmax)) + 1, 0, k.height);
  return r;
}

TargetCloud segment_target_volume(const Frame& frame, const std::optional<CameraIntrinsics>& camera,
                                  Vec3 c, double h, const std::optional<Plane>& support,
                                  const TargetVolumeParams& params) {
  TargetCloud out;
  const int stride = std::max(1, params.stride_px);
  auto inside = [&](const PointXYZRGB& p) {
    if (!valid(p)) return false;
    if (std::abs(p.x - c.x) > h || std::abs(p.y - c.y) > h || std::abs(p.z - c.z) > h) return false;
    if (support) {
      const double height = dot(support->normal, to_vec(p)) + support->d;
      if (height < std::max(params.min_height_m,
                            params.support_noise_sigmas * params.depth_noise.sigma_z(p.z)))
        return false;
    }
    return true;
  };
  const bool grid =
      frame.organized() && camera && camera->width == frame.width && camera->height == frame.height;
  if (!grid) {
    for (size_t i = 0; i < frame.points.size(); i += static_cast<size_t>(stride)) {
      ++out.visited_pixels;
      if (!inside(frame.points[i])) continue;
      out.points.push_back(to_vec(frame.points[i]));
      out.pixels.push_back(static_cast<int>(i));
    }
    return out;
  }
  const PixelRect r = project_cube(*camera, c, h);
  const double area = static_cast<double>(r.u1 - r.u0) * static_cast<double>(r.v1 - r.v0);
  int grid_stride = stride;
  if (params.max_visited_pixels > 0 && area > params.max_visited_pixels)
    grid_stride =
        std::max(stride, static_cast<int>(std::ceil(std::sqrt(area / params.max_visited_pixels))));
  for (int v = r.v0; v < r.v1; v += grid_stride) {
    for (int u = r.u0; u < r.u1; u += grid_stride) {
      ++out.visited_pixels;
      const int i = v * frame.width + u;
      const PointXYZRGB& p = frame.points[static_cast<size_t>(i)];
      if (!inside(p)) continue;
      const Vec3 q = to_vec(p);
      out.points.push_back(q);
      out.pixels.push_back(i);
      if (params.normals) out.normals.push_back(grid_normal(frame, u, v, params.normal_step_px, q));
    }
  }
  return out;
}

}  // namespace annex
