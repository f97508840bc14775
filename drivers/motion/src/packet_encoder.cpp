#include "vifusion/motion/packet_encoder.hpp"

#include <algorithm>
#include <bit>
#include <string>

#include "little_endian.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::motion {
namespace {

using detail::writeI16;
using detail::writeU16;
using detail::writeU32;

/// Where a field lives, for the message; built only when a field does not fit, so encoding allocates nothing.
struct FieldName {
  const char* part;   ///< "header", "IMU slot" or "timestamp slot"
  std::size_t slot;   ///< slot index (unused for the header)
  const char* field;  ///< field name
};

void requireFits(unsigned value, unsigned mask, const FieldName& name) {
  if ((value & ~mask) == 0) return;
  std::string where = name.part;
  if (where != "header") where += " " + std::to_string(name.slot);
  throw Error("motion packet encoder: " + where + " " + name.field + " = " + std::to_string(value) +
              " does not fit its " + std::to_string(std::bit_width(mask)) + " bits");
}

std::uint16_t encodeTag(EventSource source, std::uint16_t counter, bool valid, const char* part, std::size_t slot,
                        const char* counter_field) {
  const auto code = static_cast<unsigned>(source);
  requireFits(code, kTagSourceMask, {part, slot, "tag source code"});
  requireFits(counter, kTagCounterMask, {part, slot, counter_field});
  return static_cast<std::uint16_t>(code | (static_cast<unsigned>(counter) << kTagCounterShift) |
                                    (valid ? kTagValidBit : 0u));
}

}  // namespace

void encodePacket(const MotionPacket& packet, std::span<std::uint8_t, kPacketBytes> out) {
  const PacketHeader& header = packet.header;
  requireFits(header.cx3_packet_counter, kCx3CounterMask, {"header", 0, "cx3_packet_counter"});
  const auto status =
      static_cast<std::uint16_t>((header.power_mode_change_done ? kStatusPowerModeDoneBit : 0u) |
                                 (static_cast<unsigned>(header.cx3_packet_counter) << kStatusCx3CounterShift));
  std::span<std::uint8_t> bytes(out);
  std::fill(bytes.begin(), bytes.end(), std::uint8_t{0});
  writeU16(bytes, kErrorBitmaskOffset, header.error_bitmask);
  writeU16(bytes, kStatusOffset, status);
  writeU16(bytes, kImuEntryCountOffset, header.imu_entry_count);
  writeU16(bytes, kTimestampEntryCountOffset, header.timestamp_entry_count);

  for (std::size_t slot = 0; slot < kImuSlotCount; ++slot) {
    const ImuEntry& entry = packet.imu[slot];
    const std::span<std::uint8_t> slot_bytes = bytes.subspan(kImuSlotsOffset + slot * kImuSlotBytes, kImuSlotBytes);
    writeU16(slot_bytes, kSlotTagOffset,
             encodeTag(entry.source, entry.sample_counter, entry.valid, "IMU slot", slot, "tag sample_counter"));
    writeU32(slot_bytes, kSlotTicksOffset, entry.ticks);
    for (std::size_t axis = 0; axis < kAxisCount; ++axis) {
      writeI16(slot_bytes, kImuSlotAxesOffset + axis * sizeof(std::int16_t), entry.raw_xyz[axis]);
    }
  }
  for (std::size_t slot = 0; slot < kTimestampSlotCount; ++slot) {
    const TimestampEntry& entry = packet.timestamps[slot];
    const std::span<std::uint8_t> slot_bytes =
        bytes.subspan(kTimestampSlotsOffset + slot * kTimestampSlotBytes, kTimestampSlotBytes);
    writeU16(slot_bytes, kSlotTagOffset,
             encodeTag(entry.source, entry.frame_counter, entry.valid, "timestamp slot", slot, "tag frame_counter"));
    writeU32(slot_bytes, kSlotTicksOffset, entry.ticks);
  }
}

std::size_t encodeTransfer(std::span<const MotionPacket> packets, std::span<std::uint8_t> out) {
  const std::size_t needed = packets.size() * kPacketBytes;
  if (out.size() < needed) {
    throw Error("motion packet encoder: " + std::to_string(packets.size()) + " packets need " + std::to_string(needed) +
                " B but the buffer holds " + std::to_string(out.size()) + " B");
  }
  for (std::size_t p = 0; p < packets.size(); ++p) {
    encodePacket(packets[p], out.subspan(p * kPacketBytes).first<kPacketBytes>());
  }
  return needed;
}

}  // namespace vifusion::motion
