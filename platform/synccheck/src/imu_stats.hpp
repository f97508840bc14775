#pragma once
// Rate, gaps and order of the IMU sample times.

#include <cstdint>
#include <span>

#include "problem_log.hpp"
#include "vifusion/synccheck/sync_report.hpp"

namespace vifusion::synccheck {

/// Samples not after their predecessor are counted and noted in `problems`.
ImuStats measureImu(std::span<const std::int64_t> imu_t_ns, ProblemLog& problems);

}  // namespace vifusion::synccheck
