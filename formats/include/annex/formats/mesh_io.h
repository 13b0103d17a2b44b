#pragma once
/// \file
/// Visual meshes of virtual objects, read with assimp into our own flat triangle
/// list, shared by the runtime's Renderer and the editor. assimp stays out of this
/// header.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/result.h"

namespace annex {

/// What a mesh file says about its units. Game artists' meshes come in millimetres,
/// centimetres, inches or arbitrary units; glTF is metres by its specification, FBX
/// states a unit scale factor and COLLADA a `<unit meter="...">`.
struct MeshUnits {
  /// Metres per unit of the loaded coordinates, as the file states it (1 when it
  /// states none). A virtual object's model_scale starts from this.
  double metres_per_unit = 1.0;
  bool stated = false;  ///< the file states its unit
  /// What was found, for people: "COLLADA <unit name=\"centimeter\" meter=\"0.01\">,
  /// applied by the importer", "FBX UnitScaleFactor 100 (cm per unit)", "OBJ states no unit".
  std::string note;
};

/// Triangles with per-vertex normals and colours, flattened from whatever node
/// hierarchy the imported file had. Positions are in the model's own frame and
/// units (metres for our samples).
struct MeshData {
  std::vector<float> positions;        ///< x y z per vertex
  std::vector<float> normals;          ///< x y z per vertex, unit length
  std::vector<float> colors;           ///< r g b per vertex in [0, 1] (material diffuse colour)
  std::vector<std::uint32_t> indices;  ///< three per triangle, each < vertex_count()
  Vec3 min;                            ///< axis-aligned bounds of the positions
  Vec3 max;
  MeshUnits units;                     ///< the unit the file states (load_mesh fills it)

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t triangle_count() const { return indices.size() / 3; }
  Vec3 vertex(std::size_t i) const {
    return {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
  }
};

/// Colour of vertices whose file names no material colour.
inline constexpr float kDefaultMeshGrey[3] = {0.72f, 0.72f, 0.75f};

/// Reads any format assimp knows (OBJ, glTF/GLB, FBX, PLY, STL, DAE...), bakes the
/// node transforms into the vertices and merges all meshes into one. Polygons are
/// triangulated; point and line primitives are dropped. A missing file, a file
/// assimp cannot read, a file without triangles or with non-finite coordinates is
/// an Error naming the path.
Result<MeshData> load_mesh(const std::filesystem::path& path);

/// Recomputes min/max from the positions (both zero for an empty mesh).
void update_bounds(MeshData& mesh);

/// Checks the invariants above (array sizes agree, indices in range, finite
/// coordinates, at least one triangle); `origin` names the mesh in the message.
Status validate_mesh(const MeshData& mesh, const std::string& origin);

}  // namespace annex
