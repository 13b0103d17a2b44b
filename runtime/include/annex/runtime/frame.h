#pragma once
// One depth frame as every FrameGrabber delivers it: an organized XYZRGB cloud in
// the camera frame (x right, y down, z forward, metres), invalid pixels NaN.
// Our own type, so public headers never expose PCL.

#include <cmath>
#include <cstdint>
#include <vector>

namespace annex {

struct PointXYZRGB {
  float x = 0, y = 0, z = 0;
  std::uint8_t r = 0, g = 0, b = 0;
};

// Pinhole intrinsics of the depth camera (Kinect defaults).
struct CameraIntrinsics {
  int width = 640;
  int height = 480;
  double fx = 525.0, fy = 525.0;
  double cx = 319.5, cy = 239.5;
};

struct Frame {
  int width = 0;   // organized: width x height pixels; unorganized: width = size, height = 1
  int height = 0;
  double timestamp_s = 0;  // seconds since the source started (or recorded time)
  int index = 0;           // frame number within its source, for error messages
  std::vector<PointXYZRGB> points;
  // The camera the points were back-projected with: every rule that counts pixels (a
  // body's footprint, the noise of a pixel's neighbours) needs its focal length. Sources
  // set it; the default is the Kinect's, which a frame of another size scales from.
  CameraIntrinsics intrinsics;
  bool organized() const { return height > 1; }
};

// Whether a pixel holds a returned depth (invalid pixels are NaN, or 0 from some
// recorders).
inline bool has_depth(const PointXYZRGB& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && p.z > 0;
}

// The camera's intrinsics for the same field of view at width x height pixels (the image
// resized; pixel centres kept).
inline CameraIntrinsics resized_intrinsics(CameraIntrinsics k, int width, int height) {
  const double sx = double(width) / k.width, sy = double(height) / k.height;
  k.fx *= sx;
  k.fy *= sy;
  k.cx = (k.cx + 0.5) * sx - 0.5;
  k.cy = (k.cy + 0.5) * sy - 0.5;
  k.width = width;
  k.height = height;
  return k;
}

// The frame's intrinsics at its own resolution: as carried when they match the grid,
// else resized to it (a frame resized without its intrinsics).
inline CameraIntrinsics grid_intrinsics(const Frame& f) {
  const CameraIntrinsics& k = f.intrinsics;
  if (f.width <= 0 || f.height <= 1 || (k.width == f.width && k.height == f.height)) return k;
  return resized_intrinsics(k, f.width, f.height);
}

// Pixels per metre at unit depth across the frame's grid: a pixel's footprint at depth z
// is z / focal_px(f).
inline double focal_px(const Frame& f) {
  return grid_intrinsics(f).fx;
}

// Every n-th pixel of every n-th row of a width x height image's per-pixel values (its
// points, its labels), from the first.
template <typename T>
std::vector<T> every_nth_pixel(const std::vector<T>& pixels, int width, int height, int n) {
  std::vector<T> out;
  if (n < 1 || width < 1 || height < 1) return out;
  out.reserve(static_cast<size_t>(width / n) * static_cast<size_t>(height / n));
  for (int y = 0; y < height / n; ++y)
    for (int x = 0; x < width / n; ++x)
      out.push_back(pixels[static_cast<size_t>(y * n) * static_cast<size_t>(width) +
                           static_cast<size_t>(x * n)]);
  return out;
}

// What a sensor of 1/n the resolution sees of an organized frame (a 320 x 240 stream of
// a 640 x 480 one, at n = 2): every n-th pixel of every n-th row, with the intrinsics of
// that grid. The points keep their depth noise (a binned sensor would average it).
inline Frame subsampled(const Frame& f, int n) {
  if (n <= 1 || !f.organized()) return f;
  Frame out = f;
  out.points = every_nth_pixel(f.points, f.width, f.height, n);
  out.width = f.width / n;
  out.height = f.height / n;
  CameraIntrinsics& k = out.intrinsics = grid_intrinsics(f);
  k.width = out.width;
  k.height = out.height;
  k.fx /= n, k.fy /= n, k.cx /= n, k.cy /= n;
  return out;
}

}  // namespace annex
