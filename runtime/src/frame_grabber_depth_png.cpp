// Depth PNG frame sources: TUM RGB-D sequences, folders of depth PNGs, one depth
// PNG. Each frame is read when it is asked for (depth_png.cpp decodes it) and
// back-projected through the intrinsics.
#include "annex/runtime/frame_grabber_depth_png.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <system_error>
#include <utility>

#include "annex/formats/file_io.h"
#include "annex/runtime/depth_png.h"
#include "pacer.h"

namespace annex {
namespace {

namespace fs = std::filesystem;

// Stored depth units per metre: millimetres unless told, and TUM RGB-D's own scale.
constexpr double kMillimetres = 1000.0;
constexpr double kTumScale = 5000.0;

// One frame of a sequence: its depth image, the colour paired with it, its time.
struct DepthItem {
  fs::path depth;
  std::optional<fs::path> color;
  double timestamp_s = 0;  // from the first frame
};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Natural order: runs of digits compare as numbers, so frame2 comes before frame10.
bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (is_digit(a[i]) && is_digit(b[j])) {
      std::size_t ie = i, je = j;
      while (ie < a.size() && is_digit(a[ie])) ++ie;
      while (je < b.size() && is_digit(b[je])) ++je;
      // Compare without leading zeros: longer is larger, then digit by digit.
      std::size_t is = i, js = j;
      while (is + 1 < ie && a[is] == '0') ++is;
      while (js + 1 < je && b[js] == '0') ++js;
      if (ie - is != je - js) return ie - is < je - js;
      const int c = a.compare(is, ie - is, b, js, je - js);
      if (c != 0) return c < 0;
      i = ie, j = je;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i, ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

std::optional<double> parse_seconds(std::string_view s) {
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v) || v < 0)
    return std::nullopt;
  return v;
}

std::string pixels(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

Error frame_error(int index, const fs::path& path, const Error& cause) {
  // The cause names the file it is about (depth or colour); keep that file.
  const std::string file = cause.location.origin.empty() ? path.string() : cause.location.origin;
  return Error{cause.message, Location{"frame " + std::to_string(index) + " (" + file + ")"}};
}

class DepthPngGrabber final : public FrameGrabber {
 public:
  DepthPngGrabber(std::string description, std::vector<DepthItem> items, FrameSourceParams params)
      : description_(std::move(description)), items_(std::move(items)), params_(std::move(params)) {}

  Result<std::optional<Frame>> next() override {
    if (next_ >= items_.size()) return std::optional<Frame>{};
    const std::size_t i = next_++;
    const int index = static_cast<int>(i);
    const DepthItem& item = items_[i];
    Result<Frame> frame = read(item);
    if (!frame) return frame_error(index, item.depth, frame.error());
    frame->index = index;
    frame->timestamp_s = item.timestamp_s;
    if (params_.pacing == Pacing::recorded_rate) pacer_.wait_for(item.timestamp_s);
    return std::optional<Frame>(std::move(frame).value());
  }

  std::string describe() const override { return description_; }
  std::optional<int> frame_count() const override { return static_cast<int>(items_.size()); }

 private:
  Result<Frame> read(const DepthItem& item) {
    Result<Frame> frame = read_depth_png_frame(item.depth, item.color, params_);
    if (!frame) return frame;
    // Every frame of a sequence comes from one camera: one size.
    if (!first_size_) first_size_ = std::pair(frame->width, frame->height);
    if (std::pair(frame->width, frame->height) != *first_size_)
      return Error{"depth image is " + std::to_string(frame->width) + "x" +
                       std::to_string(frame->height) + " but the sequence's first is " +
                       std::to_string(first_size_->first) + "x" +
                       std::to_string(first_size_->second),
                   Location{item.depth.string()}};
    return frame;
  }

  std::string description_;
  std::vector<DepthItem> items_;
  FrameSourceParams params_;
  std::size_t next_ = 0;
  std::optional<std::pair<int, int>> first_size_;
  Pacer pacer_;
};

Status check_params(const FrameSourceParams& params, const fs::path& origin) {
  if (params.depth_scale && (!(*params.depth_scale > 0) || !std::isfinite(*params.depth_scale)))
    return Error{"depth scale must be a positive number", Location{origin.string()}};
  if (params.intrinsics) {
    Result<CameraIntrinsics> k = intrinsics_for_image(params.intrinsics, 1 << 30, 1 << 30,
                                                      "--intrinsics");
    if (!k) return k.error();
  }
  return Ok{};
}

std::string pacing_text(const FrameSourceParams& params, const char* recorded) {
  return params.pacing == Pacing::as_fast_as_possible ? std::string("as fast as possible")
                                                      : std::string(recorded);
}

Result<std::vector<TumListEntry>> read_tum_list(const fs::path& path) {
  Result<std::string> text = read_text_file(path, std::size_t{64} << 20);
  if (!text) return text.error();
  return parse_tum_list(*text, path.string());
}

}  // namespace

Result<std::vector<TumListEntry>> parse_tum_list(std::string_view text, std::string_view origin) {
  std::vector<TumListEntry> out;
  int line_no = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    ++line_no;
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    auto fail = [&](std::size_t at, std::string message) {
      return Error{std::move(message),
                   Location{std::string(origin), line_no, static_cast<int>(at) + 1}};
    };
    // Words split on blanks, with their columns.
    std::vector<std::pair<std::size_t, std::string_view>> words;
    for (std::size_t i = 0; i < line.size();) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      const std::size_t start = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
      if (i > start) words.emplace_back(start, line.substr(start, i - start));
    }
    if (words.empty() || words[0].second[0] == '#') continue;
    const auto seconds = parse_seconds(words[0].second);
    if (!seconds)
      return fail(words[0].first, "expected a timestamp in seconds, got '" +
                                      std::string(words[0].second.substr(0, 40)) + "'");
    if (words.size() < 2)
      return fail(words[0].first + words[0].second.size(),
                  "expected 'timestamp filename': the file name is missing");
    if (words.size() > 2)
      return fail(words[2].first, "expected 'timestamp filename', got more after the file name");
    out.push_back({*seconds, std::string(words[1].second), line_no});
  }
  return out;
}

Result<CameraIntrinsics> intrinsics_for_image(const std::optional<CameraIntrinsics>& given,
                                              int width, int height, std::string_view origin) {
  CameraIntrinsics k;
  if (given) {
    k = *given;
    if (!(k.fx > 0) || !(k.fy > 0) || !std::isfinite(k.fx) || !std::isfinite(k.fy))
      return Error{"focal lengths fx and fy must be positive", Location{std::string(origin)}};
    if (!(k.cx >= 0 && k.cx <= width) || !(k.cy >= 0 && k.cy <= height))
      return Error{"the principal point " + pixels(k.cx) + "," + pixels(k.cy) +
                       " lies outside the " + std::to_string(width) + "x" +
                       std::to_string(height) + " image",
                   Location{std::string(origin)}};
  } else if (width != 640 || height != 480) {
    // The Kinect's field of view over another resolution.
    const double s = width / 640.0;
    k.fx = k.fy = 525.0 * s;
    k.cx = (width - 1) / 2.0;
    k.cy = (height - 1) / 2.0;
  }
  k.width = width;
  k.height = height;
  return k;
}

Result<Frame> read_depth_png_frame(const fs::path& depth_path, const std::optional<fs::path>& color_path,
                                   const FrameSourceParams& params) {
  const DepthPngParams png{.depth_scale = params.depth_scale.value_or(kMillimetres)};
  Result<DepthImage> depth = read_depth_png(depth_path, png);
  if (!depth) return depth.error();
  Result<CameraIntrinsics> k =
      intrinsics_for_image(params.intrinsics, depth->width, depth->height, depth_path.string());
  if (!k) return Error{k.error().message + " (--intrinsics)", k.error().location};
  std::optional<ColorImage> color;
  if (color_path) {
    Result<ColorImage> c = read_color_png(*color_path, png);
    if (!c) return c.error();
    if (c->width * depth->height != c->height * depth->width)
      return Error{"colour image is " + std::to_string(c->width) + "x" +
                       std::to_string(c->height) + " but its depth image " +
                       depth_path.filename().string() + " is " + std::to_string(depth->width) +
                       "x" + std::to_string(depth->height),
                   Location{color_path->string()}};
    color = std::move(*c);
  }
  Result<Frame> frame = depth_to_frame(*depth, color ? &*color : nullptr, *k);
  if (!frame) return Error{frame.error().message, Location{depth_path.string()}};
  return frame;
}

Result<std::unique_ptr<FrameGrabber>> open_tum_sequence(const fs::path& dir,
                                                        const FrameSourceParams& given) {
  if (Status s = check_params(given, dir); !s) return s.error();
  FrameSourceParams params = given;
  params.depth_scale = given.depth_scale.value_or(kTumScale);
  const fs::path depth_list = dir / "depth.txt";
  Result<std::vector<TumListEntry>> depth = read_tum_list(depth_list);
  if (!depth) return depth.error();
  if (depth->empty()) return Error{"the list names no depth image", Location{depth_list.string()}};
  std::vector<TumListEntry> rgb;
  std::error_code ec;
  const fs::path rgb_list = dir / "rgb.txt";
  if (fs::exists(rgb_list, ec)) {
    Result<std::vector<TumListEntry>> r = read_tum_list(rgb_list);
    if (!r) return r.error();
    rgb = std::move(*r);
  }
  // Every listed file must exist: say which one, at its line, before the run starts.
  for (const auto& [list, entries] :
       {std::pair<const fs::path&, const std::vector<TumListEntry>&>{depth_list, *depth},
        {rgb_list, rgb}})
    for (const TumListEntry& e : entries)
      if (!fs::is_regular_file(dir / e.file, ec))
        return Error{"no such file '" + (dir / e.file).string() + "'",
                     Location{list.string(), e.line, 1}};
  auto by_time = [](const TumListEntry& a, const TumListEntry& b) {
    return a.timestamp_s < b.timestamp_s;
  };
  std::stable_sort(depth->begin(), depth->end(), by_time);
  std::stable_sort(rgb.begin(), rgb.end(), by_time);

  std::vector<DepthItem> items;
  int paired = 0;
  const double t0 = depth->front().timestamp_s;
  for (const TumListEntry& d : *depth) {
    DepthItem item{dir / d.file, std::nullopt, d.timestamp_s - t0};
    // The colour image nearest in time, if near enough (TUM's associate.py rule).
    auto it = std::lower_bound(rgb.begin(), rgb.end(), d, by_time);
    const TumListEntry* best = nullptr;
    if (it != rgb.end()) best = &*it;
    if (it != rgb.begin() &&
        (!best || d.timestamp_s - std::prev(it)->timestamp_s < best->timestamp_s - d.timestamp_s))
      best = &*std::prev(it);
    if (best && std::abs(best->timestamp_s - d.timestamp_s) <= params.max_color_gap_s) {
      item.color = dir / best->file;
      ++paired;
    }
    items.push_back(std::move(item));
  }
  const std::string description =
      "TUM RGB-D sequence '" + dir.string() + "' (" + std::to_string(items.size()) +
      " depth frames, " + std::to_string(paired) + " with colour, depth scale " +
      pixels(*params.depth_scale) + ", " + pacing_text(params, "recorded rate") + ")";
  return std::unique_ptr<FrameGrabber>(
      std::make_unique<DepthPngGrabber>(description, std::move(items), params));
}

Result<std::unique_ptr<FrameGrabber>> open_depth_png_directory(const fs::path& dir,
                                                               const FrameSourceParams& params) {
  if (Status s = check_params(params, dir); !s) return s.error();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return Error{"no such directory", Location{dir.string()}};
  std::vector<std::string> names;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    if (it->is_regular_file(type_ec) && lower(it->path().extension().string()) == ".png")
      names.push_back(it->path().filename().string());
  }
  if (ec) return Error{"cannot list directory: " + ec.message(), Location{dir.string()}};
  if (names.empty()) return Error{"no depth PNGs in the directory", Location{dir.string()}};
  std::sort(names.begin(), names.end(), natural_less);
  const bool named_depth = std::any_of(names.begin(), names.end(), [](const std::string& n) {
    return lower(n).find("depth") != std::string::npos;
  });
  std::vector<DepthItem> items;
  int paired = 0;
  for (const std::string& name : names) {
    const std::size_t at = lower(name).find("depth");
    if (named_depth && at == std::string::npos) continue;
    DepthItem item{dir / name, std::nullopt, 0};
    if (named_depth)
      for (const char* colour : {"color", "colour", "rgb"}) {
        std::string candidate = name;
        candidate.replace(at, 5, colour);
        if (fs::is_regular_file(dir / candidate, ec)) {
          item.color = dir / candidate;
          ++paired;
          break;
        }
      }
    items.push_back(std::move(item));
  }
  // Recorded times when every name carries one (TUM-style seconds, or the PCL
  // grabber's date and time) and they increase; else a fixed rate.
  std::vector<double> times;
  for (const DepthItem& item : items) {
    std::optional<double> t = parse_seconds(item.depth.stem().string());
    if (!t) t = timestamp_from_frame_name(item.depth.filename().string());
    if (!t || (!times.empty() && *t < times.back())) break;
    times.push_back(*t);
  }
  const bool named_times = times.size() == items.size();
  const double rate = params.default_rate_hz > 0 ? params.default_rate_hz : 30.0;
  for (std::size_t i = 0; i < items.size(); ++i)
    items[i].timestamp_s = named_times ? times[i] - times[0] : static_cast<double>(i) / rate;
  const std::string description =
      "depth PNG directory '" + dir.string() + "' (" + std::to_string(items.size()) +
      " frames, " + std::to_string(paired) + " with colour, depth scale " +
      pixels(params.depth_scale.value_or(kMillimetres)) + ", " +
      pacing_text(params, named_times ? "recorded rate from file names"
                                      : (std::to_string(rate) + " Hz").c_str()) +
      ")";
  return std::unique_ptr<FrameGrabber>(
      std::make_unique<DepthPngGrabber>(description, std::move(items), params));
}

Result<std::unique_ptr<FrameGrabber>> open_depth_png_file(const fs::path& path,
                                                          const FrameSourceParams& params) {
  if (Status s = check_params(params, path); !s) return s.error();
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Error{"no such depth PNG", Location{path.string()}};
  std::vector<DepthItem> items{{path, std::nullopt, 0}};
  return std::unique_ptr<FrameGrabber>(std::make_unique<DepthPngGrabber>(
      "depth PNG '" + path.string() + "'", std::move(items), params));
}

}  // namespace annex
