#pragma once
// A visual mesh as the editor draws it: triangles with per-vertex normals and
// colours, flattened from whatever node hierarchy the imported file had.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/result.h"

namespace annex::authoring {

struct MeshData {
  std::vector<float> positions;        // x y z per vertex, metres, object frame
  std::vector<float> normals;          // x y z per vertex
  std::vector<float> colors;           // r g b per vertex (material diffuse colour)
  std::vector<std::uint32_t> indices;  // three per triangle
  Vec3 min;                            // axis-aligned bounds of the positions
  Vec3 max;

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t triangle_count() const { return indices.size() / 3; }
  Vec3 vertex(std::size_t i) const {
    return {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
  }
};

// Reads any format assimp knows (OBJ, glTF/GLB, FBX, PLY, STL, DAE...), applies the
// node transforms and merges all meshes into one. Errors name the path.
Result<MeshData> load_mesh(const std::filesystem::path& path);

// Recomputes min/max from the positions.
void update_bounds(MeshData& mesh);

}  // namespace annex::authoring
