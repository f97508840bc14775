#pragma once
// Summary of the clock mapper's residuals (each transfer's latency above the device→host mapping).

#include <span>

#include "problem_log.hpp"
#include "vifusion/synccheck/sync_input.hpp"
#include "vifusion/synccheck/sync_report.hpp"

namespace vifusion::synccheck {

/// Non-finite residuals are counted and noted in `problems`.
ClockResidualStats measureClockResiduals(std::span<const ClockResidualSample> residuals, ProblemLog& problems);

}  // namespace vifusion::synccheck
