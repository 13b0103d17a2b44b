#pragma once
// "Fit to selection": sizes and places a primitive of a chosen shape around mesh
// vertices (all of a mesh, or those in a box), from their principal axes.

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

// Axis choice: for axial shapes (cylinder, cone) the principal axis whose two
// perpendicular spreads are the most alike (a round cross-section); for a torus the
// axis of least spread; a box takes all three principal axes. Needs 4 points.
Result<FitResult> fit_primitive(std::span<const Vec3> points, ShapeKind kind);

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
