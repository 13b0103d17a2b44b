#pragma once
// "Fit to selection": sizes and places a primitive of a chosen shape around mesh
// vertices (all of a mesh, or those in a box), from their principal axes.

#include <optional>
#include <span>
#include <vector>

#include "annex/authoring/mesh.h"
#include "annex/common/geometry.h"
#include "annex/common/haptic_model.h"
#include "annex/common/result.h"

namespace annex::authoring {

struct FitResult {
  Pose pose;                       // centre of the shape; local +Z its axis
  std::vector<double> dimensions;  // dimension_names(kind) order
};

struct FitOptions {
  // The shape's axis (local +Z) fixed to this direction ("snap the axis"), the other
  // axes and every size then fitted around it; unset: chosen from the points.
  std::optional<Vec3> axis;
  // Outward normals of the points (same count), e.g. of a box selection's visible
  // surface. A cylinder or cone then takes its axis from them: the line their normal
  // lines all meet, which holds for half a bottle as for all of it and for a curved
  // neck, where the points' spread alone picks the depth of a half-shell.
  std::span<const Vec3> normals;
};

// Axis choice: for axial shapes (cylinder, cone) the principal axis whose two
// perpendicular spreads are the most alike (a round cross-section); for a torus the
// axis of least spread; a box takes all three principal axes. Centres across a round
// axis come from a least-squares circle (sphere: sphere) through the points, so part
// of a round surface (what a box selection sees of a bottle) fits as well as all of
// it. Needs 4 points.
Result<FitResult> fit_primitive(std::span<const Vec3> points, ShapeKind kind,
                                const FitOptions& options = {});

// Where a snapped fit's axis points: the object's up (+Y, as the meshes are authored)
// or the axis a cylinder fit to the whole mesh takes (its principal axis).
enum class AxisSnap { none, object_up, mesh_principal };
std::optional<Vec3> snap_axis(AxisSnap snap, const MeshData& mesh);

// An axis-aligned box in the object frame.
struct Box3 {
  Vec3 min;
  Vec3 max;
  bool contains(Vec3 p) const {
    return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z &&
           p.z <= max.z;
  }
};

// Vertices of `mesh`, optionally only those inside `box`.
std::vector<Vec3> mesh_points(const MeshData& mesh, const Box3* box = nullptr);

// Applies a fit to a primitive, keeping its name, weights and limits.
Primitive with_fit(Primitive p, const FitResult& fit);

// Symmetric 3x3 eigen-decomposition (Jacobi): eigenvalues descending, eigenvectors
// as unit columns matching them.
struct Eigen3 {
  double values[3];
  Vec3 vectors[3];
};
Eigen3 symmetric_eigen(const double m[3][3]);

// Rotation whose columns are the right-handed frame (x, y, z).
Quat quat_from_frame(Vec3 x, Vec3 y, Vec3 z);

}  // namespace annex::authoring
