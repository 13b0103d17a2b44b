#pragma once
// The paper's FrameGrabber: one interface for every depth source (a PCD file, a
// directory of recorded frames, an OpenNI2 device or .oni recording), so the
// scanner and tracker run the same with or without a sensor.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "annex/common/result.h"
#include "annex/runtime/frame.h"

namespace annex {

class FrameGrabber {
 public:
  virtual ~FrameGrabber() = default;

  // The next frame; std::nullopt at the end of a finite source (a file, a directory,
  // a recording); an Error when this frame cannot be delivered (corrupt file, lost
  // sensor). After an error from a file source the next call moves on to the next frame.
  virtual Result<std::optional<Frame>> next() = 0;

  // One line for logs: "PCD directory 'frames/' (3 frames, recorded rate)".
  virtual std::string describe() const = 0;

  // Frames in a finite source; std::nullopt for a live device.
  virtual std::optional<int> frame_count() const = 0;
};

enum class Pacing {
  as_fast_as_possible,  // deliver each frame as soon as it is read
  recorded_rate,        // sleep so frames arrive at their recorded timestamps
};

struct FrameSourceParams {
  Pacing pacing = Pacing::as_fast_as_possible;
  // Frame rate assumed for directories whose file names carry no timestamps.
  double default_rate_hz = 30.0;
  // Depth PNG sources (frame_grabber_depth_png.h): stored value / depth_scale =
  // metres, when unset 1000 (millimetres) or, for a TUM RGB-D sequence, the 5000 its
  // format defines; the camera's fx, fy, cx, cy (width and height are the images'),
  // the Kinect's when unset; the largest gap between a depth image and the colour
  // image paired with it.
  std::optional<double> depth_scale;
  std::optional<CameraIntrinsics> intrinsics;
  double max_color_gap_s = 0.02;
};

// Opens a source from a command-line spec:
//   path/to/cloud.pcd    one frame
//   path/to/dir/         every *.pcd in name order; a TUM RGB-D sequence (depth.txt,
//                        rgb.txt); else every depth PNG (frame_grabber_depth_png.h)
//   path/to/depth.png    one 16-bit depth image
//   path/to/take.oni     an OpenNI2 recording
//   openni2              the first OpenNI2 device
//   openni2:URI          the OpenNI2 device with this URI
Result<std::unique_ptr<FrameGrabber>> open_frame_source(const std::string& spec,
                                                        const FrameSourceParams& params = {});

Result<std::unique_ptr<FrameGrabber>> open_pcd_file(const std::filesystem::path& path);
Result<std::unique_ptr<FrameGrabber>> open_pcd_directory(const std::filesystem::path& dir,
                                                         const FrameSourceParams& params = {});
// An empty uri opens the first device found.
Result<std::unique_ptr<FrameGrabber>> open_openni2_device(const std::string& uri = {});
Result<std::unique_ptr<FrameGrabber>> open_oni_file(const std::filesystem::path& path,
                                                    const FrameSourceParams& params = {});

// Seconds encoded in a recorded frame's name, e.g. frame_20121214T142255.814212.pcd
// (the PCL grabber's naming): seconds since 1970-01-01 of that date and time as
// written (no time zone); std::nullopt when the name carries no such timestamp.
std::optional<double> timestamp_from_frame_name(const std::string& file_name);

// A depth image as sensors deliver it: millimetres, 0 where the sensor saw nothing.
struct DepthImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint16_t> depth_mm;  // row-major, width * height
};

// A colour image registered to the depth image (same viewpoint); it may have another
// resolution, it is then sampled at the corresponding pixel.
struct ColorImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // row-major, 3 bytes per pixel
};

// Back-projects every depth pixel through the pinhole model: z = depth, x = (u - cx) z / fx,
// y = (v - cy) z / fy (camera frame: x right, y down, z forward). Zero depth gives a NaN
// point. Without colour every point is grey. Errors when the sizes disagree with
// the intrinsics or the buffers are short.
Result<Frame> depth_to_frame(const DepthImage& depth, const ColorImage* color,
                             const CameraIntrinsics& intrinsics);

}  // namespace annex
