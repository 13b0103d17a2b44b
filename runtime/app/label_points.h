#pragma once
// Where an overlay's label goes (overlay_labels.h): points of the virtual object in
// model coordinates, shared by run and render.

#include <filesystem>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/haptic_model.h"

namespace annex::cli {

// The mesh's vertices (a spread sample), or those of the primitives drawn in its place
// when the object names no mesh or it cannot be read.
std::vector<Vec3> object_label_points(const std::filesystem::path& spec_dir,
                                      const VirtualObject& object);

}  // namespace annex::cli
