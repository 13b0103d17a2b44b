// OpenNI2 sources (live Kinect/Xtion/Astra devices and .oni recordings), used
// directly rather than through PCL's grabber: the frames go through our own
// depth_to_frame, which is unit-tested without a sensor.
#include <openni2/OpenNI.h>

#include <cmath>
#include <string>
#include <system_error>
#include <utility>

#include "annex/runtime/frame_grabber.h"

namespace annex {
namespace {

// A frame that does not arrive in this time means the sensor is gone.
constexpr int kFrameTimeoutMs = 2000;

// OpenNI's extended error text, one line without its leading tab and trailing newline.
std::string openni_error() {
  std::string s = openni::OpenNI::getExtendedError();
  for (char& c : s)
    if (c == '\n' || c == '\t') c = ' ';
  const auto first = s.find_first_not_of(' ');
  const auto last = s.find_last_not_of(' ');
  if (first == std::string::npos) return "unknown OpenNI2 error";
  return s.substr(first, last - first + 1);
}

// Pinhole intrinsics from a stream's fields of view (OpenNI reports no focal length).
CameraIntrinsics intrinsics_from_fov(int width, int height, double hfov_rad, double vfov_rad) {
  CameraIntrinsics k;
  k.width = width;
  k.height = height;
  k.cx = (width - 1) * 0.5;
  k.cy = (height - 1) * 0.5;
  // Kinect-class defaults scaled to the resolution when the driver reports nothing.
  k.fx = hfov_rad > 0 ? width * 0.5 / std::tan(hfov_rad * 0.5) : 525.0 * width / 640.0;
  k.fy = vfov_rad > 0 ? height * 0.5 / std::tan(vfov_rad * 0.5) : 525.0 * height / 480.0;
  return k;
}

// Initializes OpenNI2 (idempotent) and deliberately never shuts it down: each
// shutdown unloads the drivers (dlclose) and leaks about 110 KB they allocated,
// which LeakSanitizer reports; initialized once, it lives until the process exits.
class OpenNiSession {
 public:
  OpenNiSession() : ok_(openni::OpenNI::initialize() == openni::STATUS_OK) {}
  bool ok() const { return ok_; }

 private:
  bool ok_;
};

class OpenNi2Grabber final : public FrameGrabber {
 public:
  OpenNi2Grabber(std::string name, bool is_file) : name_(std::move(name)), is_file_(is_file) {}

  ~OpenNi2Grabber() override {
    color_.stop();
    depth_.stop();
    color_.destroy();
    depth_.destroy();
    device_.close();
  }

  // Opens the device (uri empty: the first one) and starts its depth and colour streams.
  Status open(const std::string& uri, Pacing pacing) {
    if (!session_.ok()) return Error{"cannot initialize OpenNI2: " + openni_error(), {name_}};
    if (!is_file_ && uri.empty()) {
      openni::Array<openni::DeviceInfo> devices;
      openni::OpenNI::enumerateDevices(&devices);
      if (devices.getSize() == 0)
        return Error{"no OpenNI2 device found: is a Kinect, Xtion or Astra plugged in, and "
                     "may this user access it (udev rules)?",
                     {name_}};
    }
    if (device_.open(uri.empty() ? openni::ANY_DEVICE : uri.c_str()) != openni::STATUS_OK) {
      if (is_file_) return Error{"cannot open '" + uri + "': " + openni_error(), {}};
      return Error{"no OpenNI2 device found: " + openni_error(), {name_}};
    }
    if (!device_.hasSensor(openni::SENSOR_DEPTH))
      return Error{"the device has no depth stream", {name_}};
    if (depth_.create(device_, openni::SENSOR_DEPTH) != openni::STATUS_OK)
      return Error{"cannot create the depth stream: " + openni_error(), {name_}};

    if (!is_file_) {
      choose_mode(openni::SENSOR_DEPTH, depth_, openni::PIXEL_FORMAT_DEPTH_1_MM);
      depth_.setMirroringEnabled(false);
    }
    if (device_.hasSensor(openni::SENSOR_COLOR) &&
        color_.create(device_, openni::SENSOR_COLOR) == openni::STATUS_OK) {
      if (!is_file_) {
        choose_mode(openni::SENSOR_COLOR, color_, openni::PIXEL_FORMAT_RGB888);
        color_.setMirroringEnabled(false);
      }
      has_color_ = true;
    }
    // Registered colour: depth pixels re-projected to the colour camera's viewpoint.
    if (has_color_ && !is_file_ &&
        device_.isImageRegistrationModeSupported(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR))
      device_.setImageRegistrationMode(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR);
    if (has_color_) device_.setDepthColorSyncEnabled(true);

    if (is_file_) {
      openni::PlaybackControl* playback = device_.getPlaybackControl();
      if (!playback) return Error{"cannot open '" + uri + "': not a recording", {}};
      playback->setRepeatEnabled(false);
      // Speed -1: a frame advances only when read, i.e. as fast as we consume them.
      playback->setSpeed(pacing == Pacing::recorded_rate ? 1.0f : -1.0f);
      frame_count_ = playback->getNumberOfFrames(depth_);
    }
    if (depth_.start() != openni::STATUS_OK)
      return Error{"cannot start the depth stream: " + openni_error(), {name_}};
    if (has_color_ && color_.start() != openni::STATUS_OK) has_color_ = false;

    const openni::VideoMode mode = depth_.getVideoMode();
    const openni::VideoStream& geometry = has_color_ ? color_ : depth_;
    intrinsics_ = intrinsics_from_fov(mode.getResolutionX(), mode.getResolutionY(),
                                      geometry.getHorizontalFieldOfView(),
                                      geometry.getVerticalFieldOfView());
    return Ok{};
  }

  Result<std::optional<Frame>> next() override {
    const int index = delivered_;
    const std::string origin = "frame " + std::to_string(index) + " (" + name_ + ")";
    if (frame_count_ && delivered_ >= *frame_count_) return std::optional<Frame>{};

    openni::VideoStream* streams[] = {&depth_};
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream(streams, 1, &ready, kFrameTimeoutMs) != openni::STATUS_OK) {
      if (is_file_) return std::optional<Frame>{};  // the recording ran out early
      return Error{"no depth frame within " + std::to_string(kFrameTimeoutMs) +
                       " ms (sensor unplugged?): " + openni_error(),
                   {origin}};
    }
    openni::VideoFrameRef depth_frame;
    if (depth_.readFrame(&depth_frame) != openni::STATUS_OK || !depth_frame.isValid())
      return Error{"cannot read the depth frame: " + openni_error(), {origin}};

    Result<DepthImage> depth = depth_image(depth_frame);
    if (!depth) return Error{depth.error().message, {origin}};

    ColorImage color;
    bool have_color = false;
    if (has_color_) {
      openni::VideoStream* color_streams[] = {&color_};
      openni::VideoFrameRef color_frame;
      if (openni::OpenNI::waitForAnyStream(color_streams, 1, &ready, kFrameTimeoutMs) ==
              openni::STATUS_OK &&
          color_.readFrame(&color_frame) == openni::STATUS_OK && color_frame.isValid())
        have_color = color_image(color_frame, color);
    }

    CameraIntrinsics k = intrinsics_;
    k.width = depth->width;
    k.height = depth->height;
    Result<Frame> frame = depth_to_frame(*depth, have_color ? &color : nullptr, k);
    if (!frame) return Error{frame.error().message, {origin}};
    frame->index = index;
    const double stamp_s = depth_frame.getTimestamp() * 1e-6;  // microseconds
    if (!first_stamp_s_) first_stamp_s_ = stamp_s;
    frame->timestamp_s = stamp_s - *first_stamp_s_;
    ++delivered_;
    return std::optional<Frame>(std::move(frame).value());
  }

  std::string describe() const override {
    if (is_file_)
      return "OpenNI2 recording '" + name_ + "' (" +
             (frame_count_ ? std::to_string(*frame_count_) : std::string("?")) + " frames)";
    return "OpenNI2 device '" + name_ + "'";
  }
  std::optional<int> frame_count() const override { return frame_count_; }

 private:
  // Picks the 640x480 (else the first) mode in the wanted pixel format, at 30 Hz if offered.
  void choose_mode(openni::SensorType type, openni::VideoStream& stream,
                   openni::PixelFormat format) {
    const openni::SensorInfo* info = device_.getSensorInfo(type);
    if (!info) return;
    const openni::Array<openni::VideoMode>& modes = info->getSupportedVideoModes();
    int best = -1, best_score = -1;
    for (int i = 0; i < modes.getSize(); ++i) {
      if (modes[i].getPixelFormat() != format) continue;
      const int score = (modes[i].getResolutionX() == 640 && modes[i].getResolutionY() == 480 ? 2 : 0) +
                        (modes[i].getFps() == 30 ? 1 : 0);
      if (score > best_score) best = i, best_score = score;
    }
    if (best >= 0) stream.setVideoMode(modes[best]);
  }

  static Result<DepthImage> depth_image(const openni::VideoFrameRef& f) {
    const openni::PixelFormat format = f.getVideoMode().getPixelFormat();
    if (format != openni::PIXEL_FORMAT_DEPTH_1_MM && format != openni::PIXEL_FORMAT_DEPTH_100_UM)
      return Error{"unsupported depth pixel format " + std::to_string(static_cast<int>(format)), {}};
    DepthImage d;
    d.width = f.getWidth();
    d.height = f.getHeight();
    if (d.width <= 0 || d.height <= 0 || f.getStrideInBytes() < d.width * 2 ||
        f.getDataSize() < f.getStrideInBytes() * d.height)
      return Error{"malformed depth frame from the driver", {}};
    d.depth_mm.resize(static_cast<std::size_t>(d.width) * d.height);
    const auto* bytes = static_cast<const std::uint8_t*>(f.getData());
    for (int v = 0; v < d.height; ++v) {
      const auto* row = reinterpret_cast<const std::uint16_t*>(bytes + v * f.getStrideInBytes());
      for (int u = 0; u < d.width; ++u) {
        const std::uint16_t raw = row[u];
        d.depth_mm[static_cast<std::size_t>(v) * d.width + u] =
            format == openni::PIXEL_FORMAT_DEPTH_100_UM ? static_cast<std::uint16_t>(raw / 10) : raw;
      }
    }
    return d;
  }

  // Only RGB888 is converted; other colour formats leave the cloud grey.
  static bool color_image(const openni::VideoFrameRef& f, ColorImage& out) {
    if (f.getVideoMode().getPixelFormat() != openni::PIXEL_FORMAT_RGB888) return false;
    out.width = f.getWidth();
    out.height = f.getHeight();
    if (out.width <= 0 || out.height <= 0 || f.getStrideInBytes() < out.width * 3 ||
        f.getDataSize() < f.getStrideInBytes() * out.height)
      return false;
    out.rgb.resize(static_cast<std::size_t>(out.width) * out.height * 3);
    const auto* bytes = static_cast<const std::uint8_t*>(f.getData());
    for (int v = 0; v < out.height; ++v)
      std::copy(bytes + v * f.getStrideInBytes(), bytes + v * f.getStrideInBytes() + out.width * 3,
                out.rgb.begin() + static_cast<std::ptrdiff_t>(v) * out.width * 3);
    return true;
  }

  OpenNiSession session_;  // first member: initialized before the device and streams
  std::string name_;
  bool is_file_ = false;
  openni::Device device_;
  openni::VideoStream depth_;
  openni::VideoStream color_;
  bool has_color_ = false;
  CameraIntrinsics intrinsics_;
  std::optional<int> frame_count_;
  std::optional<double> first_stamp_s_;
  int delivered_ = 0;
};

}  // namespace

Result<std::unique_ptr<FrameGrabber>> open_openni2_device(const std::string& uri) {
  auto grabber = std::make_unique<OpenNi2Grabber>(uri.empty() ? std::string("openni2") : uri,
                                                  /*is_file=*/false);
  if (Status s = grabber->open(uri, Pacing::as_fast_as_possible); !s) return s.error();
  return std::unique_ptr<FrameGrabber>(std::move(grabber));
}

Result<std::unique_ptr<FrameGrabber>> open_oni_file(const std::filesystem::path& path,
                                                    const FrameSourceParams& params) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return Error{"cannot open '" + path.string() + "': no such file", {}};
  auto grabber = std::make_unique<OpenNi2Grabber>(path.string(), /*is_file=*/true);
  if (Status s = grabber->open(path.string(), params.pacing); !s) return s.error();
  return std::unique_ptr<FrameGrabber>(std::move(grabber));
}

}  // namespace annex
