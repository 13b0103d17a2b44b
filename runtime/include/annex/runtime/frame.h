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

// The frame's intrinsics at its own resolution: as carried when they match the grid,
// else scaled to it (a frame resized without its intrinsics; pixel centres kept).
inline CameraIntrinsics grid_intrinsics(const Frame& f) {
  CameraIntrinsics k = f.intrinsics;
  if (f.width <= 0 || f.height <= 1 || (k.width == f.width && k.height == f.height)) return k;
  const double sx = double(f.width) / k.width, sy = double(f.height) / k.height;
  k.fx *= sx;
  k.fy *= sy;
  k.cx = (k.cx + 0.5) * sx - 0.5;
  k.cy = (k.cy + 0.5) * sy - 0.5;
  k.width = f.width;
  k.height = f.height;
  return k;
}

// Pixels per metre at unit depth across the frame's grid: a pixel's footprint at depth z
// is z / focal_px(f).
inline double focal_px(const Frame& f) {
  return grid_intrinsics(f).fx;
}

}  // namespace annex
