#pragma once
// Checks of the parameter structs that code (not a config file) fills in, run when a
// scan, tracker or session is created: a negative size or a zero count is an Error
// naming the field ("SessionParams.scan.max_height_m must be greater than 0, got -1"),
// never an exception or a silent misbehaviour deep inside an algorithm.

#include <string_view>

#include "annex/common/result.h"
#include "annex/runtime/annex_session.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/pose_tracker.h"
#include "annex/runtime/scanner.h"

namespace annex {

// `prefix` names the struct in messages ("ScanParams", "SessionParams.scan").
Status validate_scan_params(const ScanParams& params, std::string_view prefix = "ScanParams");
Status validate_tracker_params(const PoseTrackerParams& params,
                               std::string_view prefix = "PoseTrackerParams");
Status validate_intrinsics(const CameraIntrinsics& camera,
                           std::string_view prefix = "CameraIntrinsics");
Status validate_session_params(const SessionParams& params);

}  // namespace annex
