#include "annex/authoring/mesh.h"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <limits>

namespace annex::authoring {

void update_bounds(MeshData& mesh) {
  if (mesh.positions.empty()) {
    mesh.min = mesh.max = {};
    return;
  }
  constexpr double inf = std::numeric_limits<double>::infinity();
  Vec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
    const Vec3 v = mesh.vertex(i);
    lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
    hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
  }
  mesh.min = lo;
  mesh.max = hi;
}

Result<MeshData> load_mesh(const std::filesystem::path& path) {
  const Location where{path.string(), 0, 0};
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return Error{"cannot open mesh: no such file", where};
  Assimp::Importer importer;
  // Pre-transforming bakes the node hierarchy into the vertices, which is what a
  // static visual model needs; the editor never animates.
  const aiScene* scene =
      importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                           aiProcess_GenSmoothNormals |
                                           aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (scene == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 ||
      scene->mNumMeshes == 0)
    return Error{std::string("cannot read mesh: ") + importer.GetErrorString(), where};

  MeshData out;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if ((mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;
    aiColor4D diffuse(0.72f, 0.72f, 0.75f, 1.0f);
    if (mesh->mMaterialIndex < scene->mNumMaterials) {
      aiColor4D c;
      if (scene->mMaterials[mesh->mMaterialIndex]->Get(AI_MATKEY_COLOR_DIFFUSE, c) ==
          aiReturn_SUCCESS)
        diffuse = c;
    }
    const auto base = static_cast<std::uint32_t>(out.vertex_count());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      out.positions.insert(out.positions.end(), {p.x, p.y, p.z});
      if (mesh->HasNormals()) {
        const aiVector3D& n = mesh->mNormals[v];
        out.normals.insert(out.normals.end(), {n.x, n.y, n.z});
      } else {
        out.normals.insert(out.normals.end(), {0.f, 1.f, 0.f});
      }
      if (mesh->HasVertexColors(0)) {
        const aiColor4D& c = mesh->mColors[0][v];
        out.colors.insert(out.colors.end(), {c.r, c.g, c.b});
      } else {
        out.colors.insert(out.colors.end(), {diffuse.r, diffuse.g, diffuse.b});
      }
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (int k = 0; k < 3; ++k) out.indices.push_back(base + face.mIndices[k]);
    }
  }
  if (out.indices.empty()) return Error{"cannot read mesh: it has no triangles", where};
  update_bounds(out);
  return out;
}

}  // namespace annex::authoring
