// File-backed frame sources (one PCD, a directory of PCDs), the source factory and
// the depth-to-cloud conversion. The OpenNI2 sources live in frame_grabber_openni2.cpp.
#include "annex/runtime/frame_grabber.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <limits>
#include <string_view>
#include <system_error>
#include <thread>
#include <utility>

#include "annex/runtime/frame_grabber_depth_png.h"
#include "annex/runtime/pcd_io.h"
#include "pacer.h"

namespace annex {
namespace {

// "frame 12 (dir/x.pcd)": the origin every per-frame error carries.
Error frame_error(int index, const std::filesystem::path& path, const Error& cause) {
  // read_pcd names the file in its origin; it moves into ours, a header position
  // into the message.
  std::string message = cause.message;
  if (cause.location.line > 0)
    message += " (header line " + std::to_string(cause.location.line) + ", column " +
               std::to_string(cause.location.column) + ")";
  return Error{std::move(message),
               Location{"frame " + std::to_string(index) + " (" + path.string() + ")"}};
}

bool has_pcd_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".pcd";
}

class PcdFileGrabber final : public FrameGrabber {
 public:
  explicit PcdFileGrabber(std::filesystem::path path) : path_(std::move(path)) {}

  Result<std::optional<Frame>> next() override {
    if (done_) return std::optional<Frame>{};
    done_ = true;
    Result<Frame> frame = read_pcd(path_);
    if (!frame) return frame_error(0, path_, frame.error());
    frame->index = 0;
    frame->timestamp_s = 0;
    return std::optional<Frame>(std::move(frame).value());
  }

  std::string describe() const override { return "PCD file '" + path_.string() + "'"; }
  std::optional<int> frame_count() const override { return 1; }

 private:
  std::filesystem::path path_;
  bool done_ = false;
};

class PcdDirectoryGrabber final : public FrameGrabber {
 public:
  PcdDirectoryGrabber(std::filesystem::path dir, std::vector<std::filesystem::path> files,
                      std::vector<double> timestamps, bool named_timestamps,
                      FrameSourceParams params)
      : dir_(std::move(dir)),
        files_(std::move(files)),
        timestamps_(std::move(timestamps)),
        named_timestamps_(named_timestamps),
        params_(params) {}

  Result<std::optional<Frame>> next() override {
    if (next_ >= files_.size()) return std::optional<Frame>{};
    const std::size_t i = next_++;
    const int index = static_cast<int>(i);
    Result<Frame> frame = read_pcd(files_[i]);
    if (!frame) return frame_error(index, files_[i], frame.error());
    frame->index = index;
    frame->timestamp_s = timestamps_[i];
    if (params_.pacing == Pacing::recorded_rate) pacer_.wait_for(timestamps_[i]);
    return std::optional<Frame>(std::move(frame).value());
  }

  std::string describe() const override {
    return "PCD directory '" + dir_.string() + "' (" + std::to_string(files_.size()) +
           " frames, " +
           (params_.pacing == Pacing::as_fast_as_possible
                ? std::string("as fast as possible")
                : named_timestamps_ ? std::string("recorded rate from file names")
                                    : std::to_string(params_.default_rate_hz) + " Hz") +
           ")";
  }
  std::optional<int> frame_count() const override { return static_cast<int>(files_.size()); }

 private:
  std::filesystem::path dir_;
  std::vector<std::filesystem::path> files_;
  std::vector<double> timestamps_;  // seconds from the first frame
  bool named_timestamps_ = false;
  FrameSourceParams params_;
  std::size_t next_ = 0;
  Pacer pacer_;
};

bool all_digits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

int to_int(std::string_view s) {
  int v = 0;
  for (char c : s) v = v * 10 + (c - '0');
  return v;
}

// Days from 1970-01-01 to a proleptic Gregorian date (Hinnant's days_from_civil).
long days_from_civil(int y, int m, int d) {
  y -= m <= 2 ? 1 : 0;
  const int era = (y >= 0 ? y : y - 399) / 400;
  const int yoe = y - era * 400;
  const int doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const int doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return static_cast<long>(era) * 146097 + doe - 719468;
}

}  // namespace

std::optional<double> timestamp_from_frame_name(const std::string& file_name) {
  // Look for YYYYMMDDTHHMMSS[.ffffff] anywhere in the name.
  const std::string_view name(file_name);
  for (std::size_t t = name.find('T'); t != std::string_view::npos; t = name.find('T', t + 1)) {
    if (t < 8 || t + 7 > name.size()) continue;
    const std::string_view date = name.substr(t - 8, 8);
    const std::string_view time = name.substr(t + 1, 6);
    if (!all_digits(date) || !all_digits(time)) continue;
    const int year = to_int(date.substr(0, 4)), month = to_int(date.substr(4, 2)),
              day = to_int(date.substr(6, 2));
    const int hour = to_int(time.substr(0, 2)), minute = to_int(time.substr(2, 2)),
              second = to_int(time.substr(4, 2));
    if (month < 1 || month > 12 || day < 1 || day > 31 || hour > 23 || minute > 59 || second > 60)
      continue;
    double fraction = 0;
    std::size_t f = t + 7;
    if (f < name.size() && name[f] == '.') {
      double scale = 0.1;
      for (++f; f < name.size() && name[f] >= '0' && name[f] <= '9'; ++f, scale *= 0.1)
        fraction += (name[f] - '0') * scale;
    }
    return static_cast<double>(days_from_civil(year, month, day)) * 86400.0 + hour * 3600.0 +
           minute * 60.0 + second + fraction;
  }
  return std::nullopt;
}

Result<std::unique_ptr<FrameGrabber>> open_pcd_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return Error{"no such PCD file", Location{path.string()}};
  return std::unique_ptr<FrameGrabber>(std::make_unique<PcdFileGrabber>(path));
}

Result<std::unique_ptr<FrameGrabber>> open_pcd_directory(const std::filesystem::path& dir,
                                                         const FrameSourceParams& params) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    return Error{"no such directory", Location{dir.string()}};
  std::vector<std::filesystem::path> files;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    if (it->is_regular_file(type_ec) && has_pcd_extension(it->path())) files.push_back(it->path());
  }
  if (ec) return Error{"cannot list directory: " + ec.message(), Location{dir.string()}};
  if (files.empty()) return Error{"no .pcd files in the directory", Location{dir.string()}};
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) {
    return a.filename().string() < b.filename().string();
  });

  // Recorded times when every name carries one and they increase; else a fixed rate.
  std::vector<double> timestamps;
  bool named = true;
  for (const auto& f : files) {
    const std::optional<double> t = timestamp_from_frame_name(f.filename().string());
    if (!t || (!timestamps.empty() && *t < timestamps.back())) {
      named = false;
      break;
    }
    timestamps.push_back(*t);
  }
  if (named) {
    const double t0 = timestamps.front();
    for (double& t : timestamps) t -= t0;
  } else {
    const double rate = params.default_rate_hz > 0 ? params.default_rate_hz : 30.0;
    timestamps.clear();
    for (std::size_t i = 0; i < files.size(); ++i) timestamps.push_back(static_cast<double>(i) / rate);
  }
  return std::unique_ptr<FrameGrabber>(std::make_unique<PcdDirectoryGrabber>(
      dir, std::move(files), std::move(timestamps), named, params));
}

Result<std::unique_ptr<FrameGrabber>> open_frame_source(const std::string& spec,
                                                        const FrameSourceParams& params) {
  if (spec.empty()) return Error{"empty frame source (want a .pcd, a depth .png, a directory, a .oni or openni2)", {}};
  if (spec == "openni2") return open_openni2_device();
  if (spec.rfind("openni2:", 0) == 0) return open_openni2_device(spec.substr(8));
  const std::filesystem::path path(spec);
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    // A TUM RGB-D sequence, else PCD frames, else depth PNGs.
    if (std::filesystem::is_regular_file(path / "depth.txt", ec))
      return open_tum_sequence(path, params);
    Result<std::unique_ptr<FrameGrabber>> pcd = open_pcd_directory(path, params);
    if (pcd) return pcd;
    Result<std::unique_ptr<FrameGrabber>> png = open_depth_png_directory(path, params);
    if (png) return png;
    return Error{"no .pcd files, depth PNGs or TUM depth.txt in the directory",
                 Location{path.string()}};
  }
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".oni") return open_oni_file(path, params);
  if (ext == ".pcd") return open_pcd_file(path);
  if (ext == ".png") return open_depth_png_file(path, params);
  if (!std::filesystem::exists(path, ec))
    return Error{"no such file or directory (want a .pcd, a depth .png, a directory, a .oni or openni2)",
                 Location{spec}};
  return Error{"unknown frame source type (want a .pcd, a depth .png, a directory, a .oni or openni2)",
               Location{spec}};
}

Result<Frame> depth_to_frame(const DepthImage& depth, const ColorImage* color,
                             const CameraIntrinsics& intrinsics) {
  if (depth.width <= 0 || depth.height <= 0)
    return Error{"empty depth image", Location{"depth_to_frame"}};
  if (depth.width != intrinsics.width || depth.height != intrinsics.height)
    return Error{"depth image is " + std::to_string(depth.width) + "x" +
                     std::to_string(depth.height) + " but the intrinsics are for " +
                     std::to_string(intrinsics.width) + "x" + std::to_string(intrinsics.height),
                 Location{"depth_to_frame"}};
  const std::size_t count = static_cast<std::size_t>(depth.width) * depth.height;
  if (depth.depth_mm.size() < count)
    return Error{"depth buffer holds fewer than width x height pixels", Location{"depth_to_frame"}};
  if (!(intrinsics.fx > 0) || !(intrinsics.fy > 0))
    return Error{"focal lengths must be positive", Location{"depth_to_frame"}};
  if (color && (color->width <= 0 || color->height <= 0 ||
                color->rgb.size() < static_cast<std::size_t>(color->width) * color->height * 3))
    return Error{"colour buffer is empty or shorter than width x height x 3",
                 Location{"depth_to_frame"}};

  Frame frame;
  frame.width = depth.width;
  frame.height = depth.height;
  frame.intrinsics = intrinsics;
  frame.points.resize(count);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const double inv_fx = 1.0 / intrinsics.fx, inv_fy = 1.0 / intrinsics.fy;
  for (int v = 0; v < depth.height; ++v) {
    // Colour row for this depth row (nearest pixel when resolutions differ).
    const int cv = color ? std::min(color->height - 1, v * color->height / depth.height) : 0;
    for (int u = 0; u < depth.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * depth.width + u;
      PointXYZRGB& p = frame.points[i];
      if (color) {
        const int cu = std::min(color->width - 1, u * color->width / depth.width);
        const std::uint8_t* c = &color->rgb[(static_cast<std::size_t>(cv) * color->width + cu) * 3];
        p.r = c[0];
        p.g = c[1];
        p.b = c[2];
      } else {
        p.r = p.g = p.b = 128;
      }
      const std::uint16_t d = depth.depth_mm[i];
      if (d == 0) {
        p.x = p.y = p.z = nan;
        continue;
      }
      const double z = d * 0.001;
      p.x = static_cast<float>((u - intrinsics.cx) * z * inv_fx);
      p.y = static_cast<float>((v - intrinsics.cy) * z * inv_fy);
      p.z = static_cast<float>(z);
    }
  }
  return frame;
}

}  // namespace annex
