#pragma once
// TargetVolumeSegmenter (paper, "Object Tracking"): the points of the current frame
// inside a cube around an object's last pose, the only points its ICP looks at. On
// an organized frame the cube is projected into the image and only the pixels of its
// bounding rectangle are visited, so the cost follows the object's size on screen,
// not the frame's.

#include <optional>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/physical_scene.h"
#include "annex/common/result.h"
#include "annex/runtime/depth_noise.h"
#include "annex/runtime/frame.h"

namespace annex {

// The pinhole model of an organized frame, recovered from its points
// (u = fx x / z + cx, v = fy y / z + cy) by least squares over a grid of valid
// pixels. Errors for unorganized frames or frames with too few valid points.
Result<CameraIntrinsics> estimate_intrinsics(const Frame& frame);

struct TargetVolumeParams {
  int stride_px = 1;  // visit every n-th pixel in each direction (at least)
  // A near or large object covers many pixels: the stride grows so that about this
  // many are visited (ICP needs a few thousand points, not tens of thousands).
  int max_visited_pixels = 8000;
  double min_height_m = 0.006;  // drop points this close to (or below) the support plane
  // ... or within this many of the depth noise's sigmas at the point's depth (the
  // Kinect's by default: 1.9 mm at 1 m, 6 mm at 2 m), so the band follows the support's
  // scatter on a far table without callers scaling it (0: the fixed height only). More
  // cuts the bottom of props whose model still has it (with 3, a prop hidden by an
  // occluder was not re-found, PoseTracker.RecoversAfterOcclusion).
  double support_noise_sigmas = 2;
  DepthNoise depth_noise;       // the camera's (depth_noise.h); a session gives it its scan's
  bool normals = true;          // estimate normals on the grid (point-to-plane ICP needs them)
  int normal_step_px = 2;       // neighbour offset of the grid normal estimate
};

// Points of the frame within the cube, with grid normals (oriented to the camera;
// zero where they could not be estimated) and their pixel indices.
struct TargetCloud {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;  // empty when normals were not requested or the frame is unorganized
  std::vector<int> pixels;
  int visited_pixels = 0;  // pixels examined (the cost of the segmentation)
};

// The axis-aligned cube (sensor frame) of half size `half_size_m` around `center`.
// Unorganized frames (or no intrinsics) are scanned in full.
TargetCloud segment_target_volume(const Frame& frame, const std::optional<CameraIntrinsics>& camera,
                                  Vec3 center, double half_size_m,
                                  const std::optional<Plane>& support,
                                  const TargetVolumeParams& params = {});

// Pixel rectangle [u0, u1) x [v0, v1) covering the cube's projection, clipped to the image;
// empty (u0 >= u1) when the cube lies behind the camera or off screen.
struct PixelRect {
  int u0 = 0, v0 = 0, u1 = 0, v1 = 0;
};
PixelRect project_cube(const CameraIntrinsics& camera, Vec3 center, double half_size_m);

// The grid normal at pixel (u, v) of an organized frame: the cross product of the
// neighbours `step_px` left/right and up/down, turned towards the camera; zero across
// depth edges, at dropouts and outside the image (the normals of TargetCloud).
Vec3 grid_normal_at(const Frame& frame, int u, int v, int step_px);

}  // namespace annex
