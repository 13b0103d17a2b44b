// annex-make-recording: writes the bundled synthetic recording (samples/recordings/)
// as binary_compressed PCD frames, the smallest form read_pcd reads. Deterministic for
// its seed on one toolchain. Not built by default (EXCLUDE_FROM_ALL).
//   annex-make-recording OUT_DIR [--seed N] [--frames F] [--width W] [--occluder]
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "annex/runtime/synthetic_scene.h"

namespace {

bool parse_int(const std::string& text, long& out) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && end == text.data() + text.size() && out > 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help") {
    std::cerr
        << "usage: annex-make-recording OUT_DIR [--seed N] [--frames F] [--width W] [--occluder]\n";
    return args.empty() ? 2 : 0;
  }
  long seed = 8, frames = 12, width = 320;
  bool occluder = false;
  for (size_t i = 1; i < args.size(); ++i) {
    long* target = args[i] == "--seed"     ? &seed
                   : args[i] == "--frames" ? &frames
                   : args[i] == "--width"  ? &width
                                           : nullptr;
    if (args[i] == "--occluder") {
      occluder = true;
    } else if (!target || i + 1 >= args.size() || !parse_int(args[i + 1], *target)) {
      std::cerr << "annex-make-recording: error: bad argument '" << args[i] << "'\n";
      return 2;
    } else {
      ++i;
    }
  }
  annex::SyntheticSceneParams p;
  p.seed = static_cast<std::uint64_t>(seed);
  p.object_count = 3;
  p.kinds = {annex::ShapeKind::cylinder, annex::ShapeKind::sphere, annex::ShapeKind::torus};
  p.occluder = occluder;
  // Kinect intrinsics scaled to the width (320: QVGA, a quarter of the bytes).
  const double s = static_cast<double>(width) / 640.0;
  p.camera = {
      static_cast<int>(width), static_cast<int>(480 * s), 525.0 * s, 525.0 * s, 320.0 * s - 0.5,
      240.0 * s - 0.5};
  const auto scene = annex::generate_scene(p);
  if (!scene) {
    std::cerr << scene.error().format() << "\n";
    return 1;
  }
  const std::filesystem::path out = args[0];
  std::filesystem::create_directories(out);
  for (long k = 0; k < frames; ++k) {
    const annex::Frame f = annex::render_scene(*scene, {}, static_cast<int>(k)).frame;
    pcl::PointCloud<pcl::PointXYZRGBA> c(static_cast<std::uint32_t>(f.width),
                                         static_cast<std::uint32_t>(f.height));
    for (size_t i = 0; i < f.points.size(); ++i) {
      const annex::PointXYZRGB& q = f.points[i];
      pcl::PointXYZRGBA& o = c[i];
      o.x = q.x;
      o.y = q.y;
      o.z = q.z;
      o.r = q.r;
      o.g = q.g;
      o.b = q.b;
      o.a = 255;
    }
    c.is_dense = false;
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04ld.pcd", k);
    if (pcl::io::savePCDFileBinaryCompressed((out / name).string(), c) != 0) {
      std::cerr << "annex-make-recording: error: cannot write " << (out / name) << "\n";
      return 1;
    }
  }
  for (const annex::SyntheticObject& o : scene->objects) {
    std::cout << annex::shape_name(o.kind);
    for (double d : o.dimensions_m) std::cout << " " << d;
    std::cout << "\n";
  }
  return 0;
}
