#pragma once
// Fitting a virtual object onto its prop (paper, Renderer): the model is posed so
// that its matched primitive coincides with the physical primitive, and scaled along
// the primitive's own axes (3 degrees of freedom), each factor clamped to the
// developer's limits.

#include <array>

#include "annex/common/geometry.h"
#include "annex/common/haptic_model.h"
#include "annex/common/physical_scene.h"

namespace annex {

// Row-major 3x4 affine transform [A | t]: p' = A p + t.
struct Affine {
  std::array<double, 12> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  Vec3 apply(Vec3 p) const {
    return {m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3],
            m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
            m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]};
  }
};

Affine operator*(const Affine& a, const Affine& b);
Affine affine_from_pose(const Pose& pose);
// Inverse of a rigid transform.
Affine inverse_rigid(const Pose& pose);

struct PropFit {
  // Scale factors along the primitive's local x, y, z (its axis is z), after clamping.
  Vec3 scale{1, 1, 1};
  // Factors the prop asked for before clamping, same axes.
  Vec3 wanted_scale{1, 1, 1};
  bool clamped = false;
  // Maps model coordinates to the physical primitive's frame (the sensor frame).
  Affine world_from_model;
};

// Per-dimension scale of a primitive to a set of physical sizes (same order as the
// virtual dimensions; boxes are matched largest to largest), clamped to the limits.
// Returns factors along the primitive's local x, y, z.
PropFit fit_to_prop(const Primitive& virtual_primitive, const PhysicalPrimitive& physical);

// Maps the visual mesh's coordinates to the model's (metres): its model_scale. The
// mesh is drawn at world_from_model * model_from_mesh(object).
Affine model_from_mesh(const VirtualObject& object);

// A physical plane's frame: z its normal, x its size_x side (x_axis), or x its size_y
// side when `swap_sides` (the virtual panel's size_x pairs with the physical size_y).
Quat plane_frame(const PhysicalPrimitive& plane, bool swap_sides);

// The same scaling with a chosen factor per dimension, for previews at the
// developer's limits (e.g. every dimension at its min_scale).
Vec3 local_scale_for(const Primitive& p, const std::vector<double>& factors);

}  // namespace annex
