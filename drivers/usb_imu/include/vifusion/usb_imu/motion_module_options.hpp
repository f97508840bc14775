#pragma once
// Settings of MotionModule (motion_module.hpp), each defined once, with the range validate() enforces.

#include <cstddef>
#include <cstdint>

#include "vifusion/clock/clock_mapper_options.hpp"
#include "vifusion/motion/imu_merger.hpp"
#include "vifusion/motion/imu_scaling.hpp"

namespace vifusion::usb_imu {

struct MotionModuleOptions {
  /// Merged ImuSamples the driver can hold for the consumer [samples], >= 1. 2048 at ≈200 Hz is ≈10 s:
  /// a consumer that stalls that long has lost tracking anyway; beyond it samples are dropped as overruns.
  std::size_t imu_ring_capacity = 2048;
  /// Depth-frame timestamp events held for the camera side [events], >= 1. 256 at 30–60 Hz is 4–8 s.
  std::size_t frame_event_ring_capacity = 256;
  /// Raw transfers kept for a recorder [transfers], 0 = none kept (rawTransferRing() then stays empty). 512 at the
  /// module's ≈100 transfers/s is ≈5 s; a recorder further behind loses them as overruns (counted).
  std::size_t raw_transfer_ring_capacity = 0;
  static constexpr std::size_t kMaxRawTransferRingCapacity = 1 << 16;  ///< 64 MiB of 1 KiB transfers
  /// Interrupt transfers kept in flight [transfers], [1, kMaxTransfersInFlight]. More than one, so the
  /// endpoint is polled again while a completed transfer is being decoded (none is lost between them).
  std::size_t transfers_in_flight = 4;
  static constexpr std::size_t kMaxTransfersInFlight = 32;
  /// Timeout of each adapter command's bulk write and reply read [ms], (0, 10000]. Replies come after
  /// ≈20 ms (motion::kReplyDelayNs); 1 s tolerates a busy hub.
  int command_timeout_ms = 1000;
  /// How long one wait for interrupt completions lasts [ms], (0, 1000]: bounds how soon stop() is seen.
  int pump_timeout_ms = 100;
  /// Publish samples only once the clock mapper's fit is valid (ClockMapperState::kValid). Before that
  /// the mapping rests on one sample and may still move by the USB latency (hundreds of µs), so times
  /// published then could step back when the fit arrives. true costs the first min_span_s of IMU data.
  bool require_valid_clock = true;

  motion::ImuRangeOptions ranges;   ///< the module's configured full-scale ranges
  motion::ImuMergerOptions merger;  ///< accelerometer/gyro merge
  clock::ClockMapperOptions clock;  ///< device→host mapping

  /// @throws vifusion::Error naming the first bad field and its allowed range (nested options too).
  void validate() const;
};

}  // namespace vifusion::usb_imu
