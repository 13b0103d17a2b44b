// The OpenNI2 sources of a build configured with ANNEX_WITH_OPENNI2=OFF: opening a
// device or an .oni recording is an error saying so (frame_grabber_openni2.cpp is the
// real implementation).
#include "annex/runtime/frame_grabber.h"

namespace annex {

Result<std::unique_ptr<FrameGrabber>> open_openni2_device(const std::string& uri) {
  return Error{"cannot open OpenNI2 device" + (uri.empty() ? std::string() : " '" + uri + "'") +
                   ": this Annex was built without OpenNI2 (ANNEX_WITH_OPENNI2=OFF)",
               {}};
}

Result<std::unique_ptr<FrameGrabber>> open_oni_file(const std::filesystem::path& path,
                                                    const FrameSourceParams&) {
  return Error{"cannot open '" + path.string() +
                   "': this Annex was built without OpenNI2 (ANNEX_WITH_OPENNI2=OFF)",
               {path.string(), 0, 0}};
}

}  // namespace annex
