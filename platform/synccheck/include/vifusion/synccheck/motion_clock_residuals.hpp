#pragma once
// The clock mapper's residuals from the motion module's transfers as received (a recording's
// /vifusion/motion_packets, or the live module's raw-transfer ring): the transfers are decoded again, their
// newest device tick unwrapped, and fed in order through the same device→host ClockMapper the driver uses
// (drivers/clock); each residual is the transfer's arrival time minus the mapping of its device time just
// after it was added, i.e. its USB latency above the fitted lower bound (≥ 0 on a healthy link; a negative
// one is a sample the mapper refused as early). Samples before the fit is valid are left out.

#include <cstdint>
#include <span>
#include <vector>

#include "vifusion/clock/clock_mapper_options.hpp"
#include "vifusion/synccheck/sync_input.hpp"

namespace vifusion::synccheck {

/// One transfer's bytes (whole 104-byte packets) and its host arrival time [ns].
struct MotionTransferBytes {
  std::int64_t host_receive_ns = 0;
  std::span<const std::uint8_t> bytes;
};

/// Residuals in arrival order. Transfers with no entry or a tick that steps back contribute none.
std::vector<ClockResidualSample> motionClockResiduals(std::span<const MotionTransferBytes> transfers,
                                                      const clock::ClockMapperOptions& options = {});

}  // namespace vifusion::synccheck
