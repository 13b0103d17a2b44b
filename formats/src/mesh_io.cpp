#include "annex/formats/mesh_io.h"

#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string_view>
#include <limits>
#include <string>

namespace annex {
namespace {

bool finite3(const aiVector3D& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Diffuse colour of a mesh's material, or the default grey.
aiColor4D diffuse_of(const aiScene& scene, const aiMesh& mesh) {
  aiColor4D diffuse(kDefaultMeshGrey[0], kDefaultMeshGrey[1], kDefaultMeshGrey[2], 1.0f);
  if (mesh.mMaterialIndex < scene.mNumMaterials) {
    aiColor4D c;
    if (scene.mMaterials[mesh.mMaterialIndex]->Get(AI_MATKEY_COLOR_DIFFUSE, c) == aiReturn_SUCCESS)
      diffuse = c;
  }
  return diffuse;
}

// The value of attribute `name` in an XML start tag's text, or "".
std::string attribute(std::string_view tag, std::string_view name) {
  const std::string key = " " + std::string(name) + "=";
  const std::size_t at = tag.find(key);
  if (at == std::string_view::npos || at + key.size() >= tag.size()) return {};
  const char quote = tag[at + key.size()];
  if (quote != '"' && quote != '\'') return {};
  const std::size_t end = tag.find(quote, at + key.size() + 1);
  if (end == std::string_view::npos) return {};
  return std::string(tag.substr(at + key.size() + 1, end - at - key.size() - 1));
}

// COLLADA's <asset><unit name=... meter=...>, from the head of the file (assimp applies
// it to the scene but does not report it).
std::string collada_unit(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(64 * 1024, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const std::size_t asset_end = head.find("</asset>");
  const std::size_t at = head.find("<unit");
  if (at == std::string::npos || (asset_end != std::string::npos && at > asset_end)) return {};
  const std::size_t close = head.find('>', at);
  if (close == std::string::npos) return {};
  return head.substr(at, close - at);
}

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

MeshUnits units_of(const std::filesystem::path& path, const aiScene& scene) {
  MeshUnits u;
  const std::string ext = lower_extension(path);
  if (ext == ".gltf" || ext == ".glb") {
    u.stated = true;
    u.note = "glTF: metres by its specification";
    return u;
  }
  if (ext == ".fbx" && scene.mMetaData != nullptr) {
    // assimp stores it as a float (a double in some versions).
    double factor = 0;
    float factor_f = 0;
    if (scene.mMetaData->Get("UnitScaleFactor", factor_f))
      factor = factor_f;
    else
      scene.mMetaData->Get("UnitScaleFactor", factor);
    {
      if (std::isfinite(factor) && factor > 0) {
        u.stated = true;
        u.metres_per_unit = factor / 100;  // FBX states centimetres per unit
        char buf[96];
        std::snprintf(buf, sizeof buf, "FBX UnitScaleFactor %g (centimetres per unit)", factor);
        u.note = buf;
        return u;
      }
    }
  }
  if (ext == ".dae") {
    const std::string tag = collada_unit(path);
    const std::string metres = attribute(tag, "meter");
    if (!metres.empty()) {
      u.stated = true;  // assimp has scaled the coordinates to metres already
      u.note = "COLLADA <unit";
      const std::string name = attribute(tag, "name");
      if (!name.empty()) u.note += " name=\"" + name + "\"";
      u.note += " meter=\"" + metres + "\">, applied by the importer";
      return u;
    }
  }
  u.note = (ext.empty() ? std::string("the file") : ext.substr(1)) + " states no unit";
  return u;
}

}  // namespace

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

Status validate_mesh(const MeshData& mesh, const std::string& origin) {
  const Location where{origin, 0, 0};
  const std::size_t n = mesh.positions.size();
  if (n % 3 != 0 || mesh.normals.size() != n || mesh.colors.size() != n)
    return Error{"invalid mesh: positions, normals and colours must have 3 floats per vertex",
                 where};
  if (mesh.indices.empty() || mesh.indices.size() % 3 != 0)
    return Error{"invalid mesh: it has no triangles", where};
  for (float f : mesh.positions)
    if (!std::isfinite(f))
      return Error{"invalid mesh: a vertex has a non-finite coordinate", where};
  const std::size_t vertices = mesh.vertex_count();
  for (std::uint32_t i : mesh.indices)
    if (i >= vertices)
      return Error{"invalid mesh: triangle index " + std::to_string(i) + " is out of range (" +
                       std::to_string(vertices) + " vertices)",
                   where};
  return Ok{};
}

Result<MeshData> load_mesh(const std::filesystem::path& path) {
  const Location where{path.string(), 0, 0};
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return Error{"cannot open mesh: no such file", where};
  Assimp::Importer importer;
  // Points and lines are dropped by SortByPType + the ignore list; what remains is
  // triangulated. Pre-transforming bakes the node hierarchy in: a static visual
  // model needs nothing else.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(
      path.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_GenSmoothNormals | aiProcess_PreTransformVertices |
                         aiProcess_SortByPType | aiProcess_FindDegenerates);
  if (scene == nullptr) {
    const std::string why = importer.GetErrorString();
    return Error{"cannot read mesh: " + (why.empty() ? std::string("unknown assimp error") : why),
                 where};
  }
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || scene->mNumMeshes == 0)
    return Error{"cannot read mesh: it has no triangles", where};

  MeshData out;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (mesh == nullptr || (mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;
    const aiColor4D diffuse = diffuse_of(*scene, *mesh);
    const auto base = static_cast<std::uint32_t>(out.vertex_count());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      if (!finite3(p))
        return Error{"cannot read mesh: vertex " + std::to_string(v) + " of mesh " +
                         std::to_string(m) + " has a non-finite coordinate",
                     where};
      out.positions.insert(out.positions.end(), {p.x, p.y, p.z});
      aiVector3D n(0.f, 1.f, 0.f);
      if (mesh->HasNormals() && finite3(mesh->mNormals[v]) &&
          mesh->mNormals[v].SquareLength() > 0.f)
        n = mesh->mNormals[v].NormalizeSafe();
      out.normals.insert(out.normals.end(), {n.x, n.y, n.z});
      if (mesh->HasVertexColors(0)) {
        const aiColor4D& c = mesh->mColors[0][v];
        out.colors.insert(out.colors.end(), {c.r, c.g, c.b});
      } else {
        out.colors.insert(out.colors.end(), {diffuse.r, diffuse.g, diffuse.b});
      }
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      // Triangulate leaves only triangles in a triangle mesh; anything else is skipped.
      if (face.mNumIndices != 3) continue;
      bool in_range = true;
      for (int k = 0; k < 3; ++k) in_range = in_range && face.mIndices[k] < mesh->mNumVertices;
      if (!in_range) continue;
      for (int k = 0; k < 3; ++k) out.indices.push_back(base + face.mIndices[k]);
    }
  }
  if (out.indices.empty()) return Error{"cannot read mesh: it has no triangles", where};
  update_bounds(out);
  out.units = units_of(path, *scene);
  return out;
}

}  // namespace annex
