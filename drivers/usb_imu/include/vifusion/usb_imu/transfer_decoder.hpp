#pragma once
// One interrupt transfer → ImuSamples and depth-frame events on host time, the driver thread's whole
// per-transfer path, kept free of USB and threads so it is tested on bytes alone:
//
//   parse (motion::PacketParser: error bits, counts, sources, 12-bit counters)
//   → unwrap the 32-bit ticks against the transfer's newest tick (one CounterUnwrapper for every source,
//     so accelerometer, gyro and frame events share one time base across a wrap)
//   → feed (newest device ns, host arrival ns) to the ClockMapper, then map each entry's device time
//   → scale (motion::ImuScaler) → merge (motion::ImuMerger: gyro times, accelerometer interpolated)
//   → push into the SpscRings (full ring: the sample is dropped and counted as an overrun).
//
// A transfer whose newest tick steps back is dropped whole (its entries cannot be placed in time) and
// counted; after clock.step_confirm_samples such transfers in a row the device is taken to have restarted
// its counter and the unwrapper starts afresh (the clock mapper then confirms the step on its own).
//
// Threads: decode() and reset() on the driver thread only; stats() from any thread (relaxed atomics, each
// counter exact, the set not one instant). No allocation after construction.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>

#include "vifusion/clock/clock_mapper.hpp"
#include "vifusion/clock/counter_unwrapper.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/core/spsc_ring.hpp"
#include "vifusion/motion/imu_merger.hpp"
#include "vifusion/motion/imu_scaling.hpp"
#include "vifusion/motion/packet_parser.hpp"
#include "vifusion/motion/parsed_transfer.hpp"
#include "vifusion/usb_imu/frame_event.hpp"
#include "vifusion/usb_imu/motion_module_options.hpp"
#include "vifusion/usb_imu/motion_module_stats.hpp"

namespace vifusion::usb_imu {

class TransferDecoder {
 public:
  /// @throws vifusion::Error if options.validate() does.
  TransferDecoder(const MotionModuleOptions& options, SpscRing<ImuSample>& imu_ring,
                  SpscRing<DepthFrameEvent>& frame_ring);

  /// Decodes one transfer that completed at host CLOCK_MONOTONIC `host_receive_ns`. Never throws.
  void decode(std::span<const std::uint8_t> transfer, std::int64_t host_receive_ns);

  /// Counters and clock state (state field: kClosed; MotionModule fills it in).
  MotionModuleStats stats() const;
  /// The parser's most recent problem, for the log (driver thread only).
  const motion::PacketParser& parser() const { return parser_; }
  const clock::ClockMapper& clockMapper() const { return mapper_; }

  /// Forgets counters' history, the clock fit and buffered samples (a re-opened device). Stats stay.
  void reset();

 private:
  using Counter = std::atomic<std::uint64_t>;

  /// Unwraps every entry's ticks against the transfer's newest; false when the transfer must be dropped.
  bool unwrapTicks(const motion::ParsedTransfer& parsed);
  void publishImu(const motion::ParsedTransfer& parsed);
  void publishFrameEvents(const motion::ParsedTransfer& parsed);
  /// Host time of an entry's raw ticks, or false while the clock may not be used yet.
  bool mapTicks(std::uint32_t raw_ticks, std::int64_t& device_ns, std::int64_t& host_ns);
  void publishClockState();
  static void bump(Counter& counter, std::uint64_t by = 1) { counter.fetch_add(by, std::memory_order_relaxed); }

  bool require_valid_clock_;
  std::size_t step_confirm_transfers_;
  SpscRing<ImuSample>& imu_ring_;
  SpscRing<DepthFrameEvent>& frame_ring_;
  motion::PacketParser parser_;
  motion::ParsedTransfer parsed_;
  clock::CounterUnwrapper ticks_;
  clock::ClockMapper mapper_;
  motion::ImuScaler scaler_;
  motion::ImuMerger merger_;

  Counter transfers_{0};
  Counter empty_transfers_{0};
  Counter packets_accepted_{0};
  std::array<Counter, motion::kPacketDropReasonCount> parse_drops_{};
  Counter tick_backward_{0};
  Counter clock_rejected_{0};
  Counter unmapped_samples_{0};
  Counter merge_drops_{0};
  Counter imu_samples_{0};
  Counter imu_overruns_{0};
  Counter frame_events_{0};
  Counter frame_event_overruns_{0};
  std::atomic<clock::ClockMapperState> clock_state_{clock::ClockMapperState::kEmpty};
  std::atomic<std::int64_t> clock_offset_ns_{0};
  std::atomic<double> clock_skew_ppm_{0.0};
  std::uint64_t merger_drops_seen_ = 0;  ///< merger_.stats().totalDrops() already added to merge_drops_
};

}  // namespace vifusion::usb_imu
