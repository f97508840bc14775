#pragma once
// What MotionModule counted, as a plain snapshot (stats() copies it out of atomics, so another thread,
// e.g. the service's status reporter, reads it without locking the driver thread).

#include <array>
#include <cstdint>

#include "vifusion/clock/clock_mapper.hpp"
#include "vifusion/motion/packet_problem.hpp"

namespace vifusion::usb_imu {

enum class ModuleState : std::uint8_t {
  kClosed,     ///< not started, or stopped
  kStreaming,  ///< the interrupt stream is running
  kUnplugged,  ///< the device went away; stop() then wait for hotplug and start() again
  kFailed,     ///< a USB error other than unplug ended the stream (see lastError())
};

/// "closed", "streaming", "unplugged", "failed".
const char* moduleStateName(ModuleState state);

struct MotionModuleStats {
  ModuleState state = ModuleState::kClosed;
  std::uint64_t transfers = 0;        ///< completed interrupt transfers decoded
  std::uint64_t empty_transfers = 0;  ///< zero-byte transfers
  std::uint64_t packets_accepted = 0;
  std::array<std::uint64_t, motion::kPacketDropReasonCount> parse_drops{};  ///< per PacketDropReason
  std::uint64_t tick_backward = 0;     ///< transfers whose newest tick stepped back (not applied)
  std::uint64_t clock_rejected = 0;    ///< transfers the clock mapper did not accept (early, backwards…)
  std::uint64_t unmapped_samples = 0;  ///< entries not published because the clock was not valid yet
  std::uint64_t merge_drops = 0;       ///< ImuMerger drops, all reasons
  std::uint64_t imu_samples = 0;       ///< ImuSamples pushed
  std::uint64_t imu_overruns = 0;      ///< ImuSamples lost to a full ring
  std::uint64_t frame_events = 0;      ///< depth-frame events pushed
  std::uint64_t frame_event_overruns = 0;
  clock::ClockMapperState clock_state = clock::ClockMapperState::kEmpty;
  std::int64_t clock_offset_ns = 0;  ///< host − device at the newest sample [ns]
  double clock_skew_ppm = 0.0;       ///< host rate / device rate − 1 [ppm]

  std::uint64_t parseDrops(motion::PacketDropReason reason) const {
    return parse_drops[static_cast<std::size_t>(reason)];
  }
};

}  // namespace vifusion::usb_imu
