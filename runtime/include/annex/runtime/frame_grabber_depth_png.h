#pragma once
// FrameGrabber sources made of depth PNGs, the form most recorders and datasets use:
// a TUM RGB-D sequence (depth.txt and rgb.txt listing timestamped images), a folder
// of depth PNGs, or one depth PNG. open_frame_source opens them from a path.

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "annex/common/result.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/frame_grabber.h"

namespace annex {

// One line of a TUM RGB-D list file (rgb.txt, depth.txt): "timestamp filename",
// '#' starting a comment line, the file name relative to the list's folder.
struct TumListEntry {
  double timestamp_s = 0;
  std::string file;
  int line = 0;  // 1-based, for errors about this entry
};

// Parses a TUM list; pure. Errors as origin:line:col for a line that is not
// "timestamp filename" (a missing name, a timestamp that is not a finite number,
// more than two words). Extra blanks and CRLF line ends are accepted.
Result<std::vector<TumListEntry>> parse_tum_list(std::string_view text, std::string_view origin);

// The intrinsics for a width x height depth image: `given` (its own width and height
// ignored) with cx, cy checked to lie inside the image, or by default the Kinect's
// 525, 525, 319.5, 239.5, scaled to the image when it is not 640x480. Errors are
// located at `origin`.
Result<CameraIntrinsics> intrinsics_for_image(const std::optional<CameraIntrinsics>& given,
                                              int width, int height, std::string_view origin);

// One depth PNG (and the colour PNG registered to it) as a frame, through
// params.intrinsics and params.depth_scale: what every frame of the sources below
// is. Errors name the file: missing, 8-bit, not a PNG, a colour image of another
// shape, intrinsics whose principal point lies outside the image.
Result<Frame> read_depth_png_frame(const std::filesystem::path& depth,
                                   const std::optional<std::filesystem::path>& color,
                                   const FrameSourceParams& params);

// A TUM RGB-D sequence folder: every depth.txt entry is a frame at its timestamp
// (seconds from the first), its colour the rgb.txt entry nearest in time when one is
// within params.max_color_gap_s (otherwise grey). Every listed file must exist.
Result<std::unique_ptr<FrameGrabber>> open_tum_sequence(const std::filesystem::path& dir,
                                                        const FrameSourceParams& params = {});

// A folder of 16-bit depth PNGs in natural name order (frame2 before frame10). When
// some names contain "depth", only those are frames, and the PNG whose name has
// "color" or "rgb" in its place is the frame's colour (OSD's learn0_depth.png and
// learn0_color.png).
Result<std::unique_ptr<FrameGrabber>> open_depth_png_directory(const std::filesystem::path& dir,
                                                               const FrameSourceParams& params = {});

// One depth PNG as a one-frame source.
Result<std::unique_ptr<FrameGrabber>> open_depth_png_file(const std::filesystem::path& path,
                                                          const FrameSourceParams& params = {});

}  // namespace annex
