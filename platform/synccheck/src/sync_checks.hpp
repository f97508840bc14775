#pragma once
// The pass/fail checks of a SyncReport against the limits in SyncCheckOptions. A value that could not be
// measured (NaN) fails its check and says why.

#include <vector>

#include "vifusion/synccheck/sync_check_options.hpp"
#include "vifusion/synccheck/sync_report.hpp"

namespace vifusion::synccheck {

/// "offset", "jitter", "drift" (frame_minus_edge), "dropped", "frame_rate", then "imu_rate" and "imu_gap"
/// unless the input has no IMU samples and options.require_imu is false.
std::vector<CheckResult> evaluateChecks(const SyncReport& report, const SyncCheckOptions& options);

}  // namespace vifusion::synccheck
