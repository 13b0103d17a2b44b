// Rays against the generators' primitive solids in their own frame (centred, axis +z):
// analytic roots, sphere tracing for the torus. Shared by synthetic_scene.cpp and
// synthetic_motion.cpp; internal to the runtime library.
#pragma once

#include <limits>

#include "annex/common/geometry.h"

namespace annex::shape_rays {

// The nearest hit beyond kMinT: ray parameter t (infinite when none) and the outward
// normal in the solid's frame.
struct LocalHit {
  double t = std::numeric_limits<double>::infinity();
  Vec3 normal;
};

LocalHit hit_sphere(Vec3 o, Vec3 d, double r);
LocalHit hit_cylinder(Vec3 o, Vec3 d, double r, double height);
// Base (radius r) at z = -height/2 narrowing towards z = +height/2: to its apex there,
// or to a top cap of radius `narrow` (a frustum).
LocalHit hit_cone(Vec3 o, Vec3 d, double r, double height, double narrow = 0);
LocalHit hit_torus(Vec3 o, Vec3 d, double major, double minor);
LocalHit hit_box(Vec3 o, Vec3 d, Vec3 half);

}  // namespace annex::shape_rays
