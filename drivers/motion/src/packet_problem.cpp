#include "vifusion/motion/packet_problem.hpp"

namespace vifusion::motion {
namespace {

/// Prints a string_view (not NUL-terminated) through printf's "%.*s".
int width(std::string_view text) { return static_cast<int>(text.size()); }

void appendErrorFlags(ProblemText& text, std::uint32_t bitmask) {
  const char* separator = "";
  for (std::size_t bit = 0; bit < kErrorFlagCount; ++bit) {
    if ((bitmask >> bit & 1u) == 0) continue;
    const std::string_view name = errorFlagName(static_cast<ErrorFlag>(bit));
    text.append("%s%.*s", separator, width(name), name.data());
    separator = ", ";
  }
}

}  // namespace

std::string_view packetDropReasonName(PacketDropReason reason) {
  switch (reason) {
    case PacketDropReason::kShortTransfer:
      return "short_transfer";
    case PacketDropReason::kPartialPacket:
      return "partial_packet";
    case PacketDropReason::kDeviceError:
      return "device_error";
    case PacketDropReason::kAfterDeviceError:
      return "after_device_error";
    case PacketDropReason::kImuCountTooLarge:
      return "imu_count_too_large";
    case PacketDropReason::kTimestampCountTooLarge:
      return "timestamp_count_too_large";
    case PacketDropReason::kInvalidImuSource:
      return "invalid_imu_source";
    case PacketDropReason::kInvalidTimestampSource:
      return "invalid_timestamp_source";
    case PacketDropReason::kImuNotValid:
      return "imu_not_valid";
    case PacketDropReason::kCounterRepeated:
      return "counter_repeated";
    case PacketDropReason::kCounterWentBack:
      return "counter_went_back";
    case PacketDropReason::kOutputFull:
      return "output_full";
  }
  return "unknown_reason";
}

ProblemText describe(const PacketProblem& problem) {
  ProblemText text;
  const unsigned packet = problem.packet_index;
  const unsigned slot = problem.slot_index;
  const unsigned value = problem.value;
  const unsigned reference = problem.reference;
  const std::string_view source = eventSourceName(problem.source);
  const bool imu_slot = isImuSource(static_cast<std::uint8_t>(problem.source));
  const char* slot_kind = imu_slot ? "IMU" : "timestamp";
  const char* counter_field = imu_slot ? "sample_counter" : "frame_counter";
  switch (problem.reason) {
    case PacketDropReason::kShortTransfer:
      text.append("transfer of %u B is shorter than one %u-byte packet: transfer dropped", value, reference);
      break;
    case PacketDropReason::kPartialPacket:
      text.append("transfer of %u B is not a whole number of %zu-byte packets: trailing %u B dropped", value,
                  kPacketBytes, reference);
      break;
    case PacketDropReason::kDeviceError:
      text.append("packet %u header error_bitmask 0x%04x (", packet, value);
      appendErrorFlags(text, value);
      text.append("): packet and the %u after it in this transfer dropped", reference);
      break;
    case PacketDropReason::kAfterDeviceError:
      text.append("packet %u follows a packet with device errors in the same transfer: dropped", packet);
      break;
    case PacketDropReason::kImuCountTooLarge:
      text.append("packet %u header imu_entry_count %u is above the maximum %u: packet dropped", packet, value,
                  reference);
      break;
    case PacketDropReason::kTimestampCountTooLarge:
      text.append("packet %u header timestamp_entry_count %u is above the maximum %u: packet dropped", packet, value,
                  reference);
      break;
    case PacketDropReason::kInvalidImuSource:
      text.append("packet %u IMU slot %u tag source code %u is not accelerometer (1) or gyroscope (2): entry dropped",
                  packet, slot, value);
      break;
    case PacketDropReason::kInvalidTimestampSource:
      text.append("packet %u timestamp slot %u tag source code %u is not a frame or GPIO event (3..7): entry dropped",
                  packet, slot, value);
      break;
    case PacketDropReason::kImuNotValid:
      text.append("packet %u IMU slot %u (%.*s) tag valid bit 15 is clear: entry dropped", packet, slot, width(source),
                  source.data());
      break;
    case PacketDropReason::kCounterRepeated:
      text.append("packet %u %s slot %u %.*s %s %u repeats the previous one: entry dropped", packet, slot_kind, slot,
                  width(source), source.data(), counter_field, value);
      break;
    case PacketDropReason::kCounterWentBack:
      text.append("packet %u %s slot %u %.*s %s went back from %u to %u (12-bit): entry dropped", packet, slot_kind,
                  slot, width(source), source.data(), counter_field, reference, value);
      break;
    case PacketDropReason::kOutputFull:
      text.append("packet %u does not fit the output storage of %u packets: it and the rest of the transfer dropped",
                  packet, reference);
      break;
  }
  return text;
}

}  // namespace vifusion::motion
