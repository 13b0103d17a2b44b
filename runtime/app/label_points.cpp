#include "label_points.h"

#include "annex/common/prop_fit.h"
#include "annex/formats/mesh_io.h"
#include "annex/runtime/overlay_labels.h"
#include "annex/runtime/renderer.h"

namespace annex::cli {

std::vector<Vec3> object_label_points(const std::filesystem::path& spec_dir,
                                      const VirtualObject& object) {
  if (!object.mesh.empty())
    if (auto mesh = load_mesh(spec_dir / object.mesh)) return label_points(*mesh);
  std::vector<Vec3> out;
  for (const Primitive& p : object.primitives) {
    std::vector<double> dims;
    for (const Dimension& d : p.dimensions) dims.push_back(d.value_m);
    const Affine model_from_part = affine_from_pose(p.pose);
    for (const Vec3& v : label_points(primitive_mesh(p.kind, dims, 16), 200))
      out.push_back(model_from_part.apply(v));
  }
  return out;
}

}  // namespace annex::cli
