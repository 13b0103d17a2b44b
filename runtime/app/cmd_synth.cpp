// annex-runtime synth: writes synthetic tabletop frames (organized PCD) with their
// ground truth (.scene), for the scanner's accuracy tests, benchmarks and demos.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>

#include "annex/formats/scene_format.h"
#include "annex/runtime/depth_noise.h"
#include "annex/runtime/pcd_io.h"
#include "annex/runtime/synthetic_scene.h"
#include "commands.h"

namespace annex::cli {
namespace {

std::string numbered(int i) {
  char name[32];
  std::snprintf(name, sizeof name, "scene_%04d", i);
  return name;
}

// Writes DIR/scene_XXXX.pcd and DIR/scene_XXXX.scene.
bool write_frame(const std::filesystem::path& dir, int number, const SyntheticFrame& f) {
  const std::filesystem::path pcd = dir / (numbered(number) + ".pcd");
  const std::filesystem::path scene = dir / (numbered(number) + ".scene");
  if (Status s = write_pcd(pcd, f.frame); !s) {
    std::cerr << "annex-runtime synth: " << s.error().format() << "\n";
    return false;
  }
  if (Status s = write_scene_file(scene, f.truth); !s) {
    std::cerr << "annex-runtime synth: " << s.error().format() << "\n";
    return false;
  }
  std::cout << "wrote " << pcd.string() << " " << scene.string() << " (" << f.truth.objects.size()
            << " objects)\n";
  return true;
}

// A share from 0 to 1 (--stacked, --flying); empty, after the error, otherwise.
std::optional<double> parse_share(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !(v >= 0 && v <= 1)) {
    std::cerr << "annex-runtime synth: error: --" << option << " expects a share from 0 to 1, got '"
              << text << "'\n";
    return std::nullopt;
  }
  return v;
}

int run_synth(const std::vector<std::string>& args) {
  const auto parsed = parse_args("synth", args,
                                 {{"occluder", "no-noise"},
                                  {"seed", "objects", "out", "frames", "scenes", "kinds",
                                   "depth-noise", "stacked", "everyday", "lying", "flying"}});
  if (!parsed) return kExitBadInput;
  if (!parsed->positional.empty()) {
    std::cerr << "annex-runtime synth: error: unexpected argument '" << parsed->positional[0]
              << "' (see --help)\n";
    return kExitBadInput;
  }
  const auto out = parsed->get("out");
  if (!out || out->empty()) {
    std::cerr << "annex-runtime synth: error: --out DIR is required\n";
    return kExitBadInput;
  }
  SyntheticSceneParams params;
  long frames = 1, scenes = 1;
  if (auto v = parsed->get("seed")) {
    const auto n = parse_count("synth", "seed", *v);
    if (!n) return kExitBadInput;
    params.seed = static_cast<std::uint64_t>(*n);
  }
  if (auto v = parsed->get("objects")) {
    const auto n = parse_count("synth", "objects", *v);
    if (!n) return kExitBadInput;
    if (*n > 10) {
      std::cerr << "annex-runtime synth: error: --objects must be at most 10\n";
      return kExitBadInput;
    }
    params.object_count = static_cast<int>(*n);
  }
  for (auto [name, target] : {std::pair{"frames", &frames}, std::pair{"scenes", &scenes}}) {
    if (auto v = parsed->get(name)) {
      const auto n = parse_count("synth", name, *v);
      if (!n) return kExitBadInput;
      if (*n < 1 || *n > 10000) {
        std::cerr << "annex-runtime synth: error: --" << name << " must be 1 to 10000\n";
        return kExitBadInput;
      }
      *target = *n;
    }
  }
  if (frames > 1 && scenes > 1) {
    std::cerr << "annex-runtime synth: error: use --frames (one moving scene) or --scenes "
                 "(independent scenes), not both\n";
    return kExitBadInput;
  }
  if (auto v = parsed->get("kinds")) {
    params.kinds.clear();
    std::stringstream list(*v);
    for (std::string name; std::getline(list, name, ',');) {
      const auto kind = shape_from_name(name);
      if (!kind) {
        std::cerr << "annex-runtime synth: error: --kinds: unknown shape '" << name
                  << "' (sphere, cylinder, cone, torus, box)\n";
        return kExitBadInput;
      }
      params.kinds.push_back(*kind);
    }
    if (params.kinds.empty()) {
      std::cerr << "annex-runtime synth: error: --kinds needs at least one shape\n";
      return kExitBadInput;
    }
  }
  params.occluder = parsed->has("occluder");
  SensorNoiseParams noise;
  noise.enabled = !parsed->has("no-noise");
  if (auto v = parsed->get("depth-noise")) {
    const std::optional<DepthNoise> axial = depth_noise_named(*v);
    if (!axial) {
      std::cerr << "annex-runtime synth: error: --depth-noise expects one of " << kDepthNoiseNames
                << ", got '" << *v << "'\n";
      return kExitBadInput;
    }
    noise.axial = *axial;
  }
  for (auto [name, target] :
       {std::pair{"stacked", &params.stacked_share}, std::pair{"everyday", &params.everyday_share},
        std::pair{"lying", &params.lying_share}, std::pair{"flying", &noise.flying_share}}) {
    if (auto v = parsed->get(name)) {
      const std::optional<double> share = parse_share(name, *v);
      if (!share) return kExitBadInput;
      *target = *share;
    }
  }

  const std::filesystem::path dir(*out);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    std::cerr << "annex-runtime synth: " << dir.string()
              << ": error: cannot create directory: " << ec.message() << "\n";
    return kExitFailure;
  }

  for (long i = 0; i < scenes; ++i) {
    SyntheticSceneParams p = params;
    p.seed = params.seed + static_cast<std::uint64_t>(i);
    const Result<SyntheticScene> scene = generate_scene(p);
    if (!scene) {
      std::cerr << "annex-runtime synth: " << scene.error().format() << "\n";
      return kExitFailure;
    }
    for (long k = 0; k < frames; ++k) {
      const SyntheticFrame f = render_scene(*scene, noise, static_cast<int>(k));
      if (!write_frame(dir, static_cast<int>(scenes > 1 ? i : k), f)) return kExitFailure;
    }
  }
  return kExitOk;
}

}  // namespace

extern const Command kSynthCommand;
const Command kSynthCommand{
    "synth", "write synthetic tabletop frames with ground truth",
    "usage: annex-runtime synth --out DIR [--seed N] [--objects K] [--frames F | --scenes C]\n"
    "                           [--kinds sphere,cylinder,...] [--occluder] [--no-noise]\n"
    "                           [--depth-noise NAME] [--stacked SHARE] [--everyday SHARE]\n"
    "                           [--lying SHARE] [--flying SHARE]\n"
    "\n"
    "Renders tabletop scenes as a Kinect would see them (640x480, fx = fy = 525, axial\n"
    "noise 0.0012 + 0.0019 (z - 0.4)^2 m, lateral jitter, dropout) and writes\n"
    "DIR/scene_XXXX.pcd (organized, binary) with DIR/scene_XXXX.scene, the ground truth\n"
    "in the camera frame (table plane, one primitive per object).\n"
    "\n"
    "  --out DIR      output directory (created if missing)\n"
    "  --seed N       random seed (default 1); the same seed gives the same files\n"
    "  --objects K    objects on the table, 0 to 10 (default 4)\n"
    "  --frames F     F frames of one scene whose objects drift and turn a few mm and\n"
    "                 degrees per frame (30 Hz), for tracking\n"
    "  --scenes C     C independent scenes, seeds N, N+1, ...\n"
    "  --kinds LIST   shapes to draw from (default all: sphere,cylinder,cone,torus,box)\n"
    "  --occluder     a box crossing the view between camera and table (with --frames)\n"
    "  --no-noise     exact depths: no noise, jitter or dropout\n"
    "  --depth-noise NAME  another camera's axial noise: stereo (a RealSense D400,\n"
    "                 0.0037 z^2 m) or tof (a Kinect v2, an Azure Kinect); kinect, the\n"
    "                 default (scan these with 'scan --depth-noise NAME')\n"
    "  --stacked SHARE  that share (0 to 1) of the boxes and cylinders carry a box,\n"
    "                 cylinder or cone on their top; the .scene names what each stands on\n"
    "                 ('on_object')\n"
    "  --everyday SHARE  that share of the cylinders are mugs (a handle) or bottles (a\n"
    "                 shoulder, neck and cap), of the cones narrowing down cups with a\n"
    "                 handle; the .scene holds their bodies\n"
    "  --lying SHARE    that share of the plain cylinders on the table or a furniture\n"
    "                 top rest on their side, their axis level\n"
    "  --flying SHARE   that share of the pixels kept at depth edges return a depth\n"
    "                 between their two surfaces (a time-of-flight or stereo camera's\n"
    "                 flying pixels; the Kinect, the default, drops most of them: 0)\n"
    "\n"
    "Exit 0 on success, 1 when a scene cannot be laid out or a file cannot be written,\n"
    "2 on bad arguments.\n",
    run_synth};

}  // namespace annex::cli
