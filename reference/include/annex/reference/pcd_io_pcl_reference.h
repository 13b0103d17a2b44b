#pragma once
// PCL's own PCD reader and writer, the reference our decoder (annex/runtime/pcd_io.h)
// is tested against; read_pcd does not use them, so the runtime library carries no
// PCL reader that allocates for whatever a header promises.

#include <filesystem>

#include "annex/common/result.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/pcd_io.h"

namespace annex {

Result<Frame> read_pcd_pcl(const std::filesystem::path& path);
Status write_pcd_pcl(const std::filesystem::path& path, const Frame& frame, PcdHeader::Data data);

}  // namespace annex
