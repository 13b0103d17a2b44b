#pragma once
// The editor draws the same meshes the runtime's Renderer does: one assimp loader,
// shared through annex::mesh (formats/include/annex/formats/mesh_io.h).

#include "annex/formats/mesh_io.h"

namespace annex::authoring {

using annex::load_mesh;
using annex::MeshData;
using annex::update_bounds;

}  // namespace annex::authoring
