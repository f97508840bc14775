#pragma once
// Why the packet parser dropped some input, as plain data (cheap to record on the driver thread) plus a
// describe() that names the field and what is wrong, e.g.
//   "packet 2 header imu_entry_count 5 is above the maximum 4: packet dropped".

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "vifusion/motion/packet_format.hpp"
#include "vifusion/motion/problem_text.hpp"

namespace vifusion::motion {

enum class PacketDropReason : std::uint8_t {
  kShortTransfer,           ///< fewer bytes than one packet: the transfer is dropped
  kPartialPacket,           ///< bytes after the last whole packet: those bytes are dropped
  kDeviceError,             ///< error_bitmask ≠ 0: the packet and the rest of its transfer are dropped
  kAfterDeviceError,        ///< a packet dropped because an earlier one in its transfer had an error
  kImuCountTooLarge,        ///< imu_entry_count > kImuSlotCount: packet dropped
  kTimestampCountTooLarge,  ///< timestamp_entry_count > kTimestampSlotCount: packet dropped
  kInvalidImuSource,        ///< IMU slot with a source code other than 1 or 2: entry dropped
  kInvalidTimestampSource,  ///< timestamp slot with a source code outside 3…7: entry dropped
  kImuNotValid,             ///< IMU slot with the valid bit clear: entry dropped
  kCounterRepeated,         ///< same 12-bit counter as the source's previous entry: entry dropped
  kCounterWentBack,         ///< 12-bit counter stepped backwards: entry dropped
  kOutputFull,              ///< the caller's ParsedTransfer holds fewer packets than the transfer
};
inline constexpr std::size_t kPacketDropReasonCount = static_cast<std::size_t>(PacketDropReason::kOutputFull) + 1;

/// snake_case name of a reason, e.g. "counter_went_back" (for status reports and logs).
std::string_view packetDropReasonName(PacketDropReason reason);

/// One dropped input. Which members are meaningful depends on the reason (see describe()).
struct PacketProblem {
  PacketDropReason reason = PacketDropReason::kShortTransfer;
  std::uint32_t packet_index = 0;  ///< packet within its transfer, from 0
  std::uint32_t slot_index = 0;    ///< IMU or timestamp slot within the packet, for entry-level reasons
  EventSource source = EventSource::kAccelerometer;  ///< for kImuNotValid and the counter reasons
  /// The offending value: transfer bytes, error_bitmask, entry count, source code or the new counter.
  std::uint32_t value = 0;
  /// What `value` was checked against: packet size, maximum count or the previous counter; for
  /// kDeviceError and kPartialPacket what was dropped with it (packets after it, trailing bytes).
  std::uint32_t reference = 0;
};

/// The problem in words, naming the field and what is wrong with it. Never allocates.
ProblemText describe(const PacketProblem& problem);

}  // namespace vifusion::motion
