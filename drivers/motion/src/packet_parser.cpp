#include "vifusion/motion/packet_parser.hpp"

#include <numeric>

#include "little_endian.hpp"

namespace vifusion::motion {
namespace {

using detail::readI16;
using detail::readU16;
using detail::readU32;

/// A 12-bit counter step of at most half the period is progress; more means the counter went back.
constexpr unsigned kMaxForwardCounterStep = kCounterModulus / 2 - 1;

struct DecodedTag {
  std::uint8_t source_code = 0;
  std::uint16_t counter = 0;
  bool valid = false;
};

DecodedTag decodeTag(std::uint16_t tag) {
  return {static_cast<std::uint8_t>(tag & kTagSourceMask),
          static_cast<std::uint16_t>((tag >> kTagCounterShift) & kTagCounterMask), (tag & kTagValidBit) != 0};
}

PacketHeader decodeHeader(std::span<const std::uint8_t> packet) {
  const std::uint16_t status = readU16(packet, kStatusOffset);
  PacketHeader header;
  header.error_bitmask = readU16(packet, kErrorBitmaskOffset);
  header.power_mode_change_done = (status & kStatusPowerModeDoneBit) != 0;
  header.cx3_packet_counter = static_cast<std::uint8_t>((status >> kStatusCx3CounterShift) & kCx3CounterMask);
  header.imu_entry_count = readU16(packet, kImuEntryCountOffset);
  header.timestamp_entry_count = readU16(packet, kTimestampEntryCountOffset);
  return header;
}

}  // namespace

std::uint64_t PacketParserStats::totalDrops() const {
  return std::accumulate(drop_counts.begin(), drop_counts.end(), std::uint64_t{0});
}

std::size_t PacketParser::parse(std::span<const std::uint8_t> transfer, ParsedTransfer& out) {
  out.clear();
  ++stats_.transfers;
  if (transfer.empty()) {
    ++stats_.empty_transfers;
    return 0;
  }
  const auto transfer_bytes = static_cast<std::uint32_t>(transfer.size());
  if (transfer.size() < kPacketBytes) {
    report({.reason = PacketDropReason::kShortTransfer, .value = transfer_bytes, .reference = kPacketBytes}, out);
    return out.problemCount();
  }
  const std::size_t packet_count = transfer.size() / kPacketBytes;
  const std::size_t trailing_bytes = transfer.size() % kPacketBytes;
  if (trailing_bytes != 0) {
    report({.reason = PacketDropReason::kPartialPacket,
            .value = transfer_bytes,
            .reference = static_cast<std::uint32_t>(trailing_bytes)},
           out);
  }
  for (std::size_t p = 0; p < packet_count; ++p) {
    const auto packet_index = static_cast<std::uint32_t>(p);
    const auto packets_after = static_cast<std::uint32_t>(packet_count - p - 1);
    ++stats_.packets;
    const std::span<const std::uint8_t> packet = transfer.subspan(p * kPacketBytes, kPacketBytes);
    const std::uint16_t error_bitmask = readU16(packet, kErrorBitmaskOffset);
    if (error_bitmask != 0) {
      for (std::size_t bit = 0; bit < kErrorFlagCount; ++bit)
        stats_.error_flag_counts[bit] += error_bitmask >> bit & 1u;
      report({.reason = PacketDropReason::kDeviceError,
              .packet_index = packet_index,
              .value = error_bitmask,
              .reference = packets_after},
             out);
      stats_.packets += packets_after;
      stats_.drop_counts[static_cast<std::size_t>(PacketDropReason::kAfterDeviceError)] += packets_after;
      break;
    }
    if (out.full()) {
      report({.reason = PacketDropReason::kOutputFull,
              .packet_index = packet_index,
              .value = packets_after + 1,
              .reference = static_cast<std::uint32_t>(out.maxPackets())},
             out);
      stats_.packets += packets_after;
      // The packets after it are counted under the same reason: each was dropped for lack of room.
      stats_.drop_counts[static_cast<std::size_t>(PacketDropReason::kOutputFull)] += packets_after;
      break;
    }
    parsePacket(packet, packet_index, out);
  }
  return out.problemCount();
}

void PacketParser::parsePacket(std::span<const std::uint8_t> packet, std::uint32_t packet_index, ParsedTransfer& out) {
  const PacketHeader header = decodeHeader(packet);
  if (header.imu_entry_count > kImuSlotCount) {
    report({.reason = PacketDropReason::kImuCountTooLarge,
            .packet_index = packet_index,
            .value = header.imu_entry_count,
            .reference = kImuSlotCount},
           out);
    return;
  }
  if (header.timestamp_entry_count > kTimestampSlotCount) {
    report({.reason = PacketDropReason::kTimestampCountTooLarge,
            .packet_index = packet_index,
            .value = header.timestamp_entry_count,
            .reference = kTimestampSlotCount},
           out);
    return;
  }
  ++stats_.packets_accepted;
  trackCx3Counter(header.cx3_packet_counter);
  out.addHeader(header);

  for (std::uint32_t slot = 0; slot < header.imu_entry_count; ++slot) {
    const std::span<const std::uint8_t> bytes = packet.subspan(kImuSlotsOffset + slot * kImuSlotBytes, kImuSlotBytes);
    const DecodedTag tag = decodeTag(readU16(bytes, kSlotTagOffset));
    if (!isImuSource(tag.source_code)) {
      report({.reason = PacketDropReason::kInvalidImuSource,
              .packet_index = packet_index,
              .slot_index = slot,
              .source = static_cast<EventSource>(tag.source_code),
              .value = tag.source_code},
             out);
      continue;
    }
    const auto source = static_cast<EventSource>(tag.source_code);
    if (!tag.valid) {
      report({.reason = PacketDropReason::kImuNotValid,
              .packet_index = packet_index,
              .slot_index = slot,
              .source = source},
             out);
      continue;
    }
    if (!acceptCounter(source, tag.counter, packet_index, slot, out)) continue;
    ImuEntry entry;
    entry.source = source;
    entry.sample_counter = tag.counter;
    entry.valid = tag.valid;
    entry.ticks = readU32(bytes, kSlotTicksOffset);
    for (std::size_t axis = 0; axis < kAxisCount; ++axis) {
      entry.raw_xyz[axis] = readI16(bytes, kImuSlotAxesOffset + axis * sizeof(std::int16_t));
    }
    out.addImu(entry);
    ++stats_.imu_entries;
  }

  for (std::uint32_t slot = 0; slot < header.timestamp_entry_count; ++slot) {
    const std::span<const std::uint8_t> bytes =
        packet.subspan(kTimestampSlotsOffset + slot * kTimestampSlotBytes, kTimestampSlotBytes);
    const DecodedTag tag = decodeTag(readU16(bytes, kSlotTagOffset));
    if (!isTimestampSource(tag.source_code)) {
      report({.reason = PacketDropReason::kInvalidTimestampSource,
              .packet_index = packet_index,
              .slot_index = slot,
              .source = static_cast<EventSource>(tag.source_code),
              .value = tag.source_code},
             out);
      continue;
    }
    const auto source = static_cast<EventSource>(tag.source_code);
    if (!acceptCounter(source, tag.counter, packet_index, slot, out)) continue;
    TimestampEntry entry;
    entry.source = source;
    entry.frame_counter = tag.counter;
    entry.valid = tag.valid;
    entry.ticks = readU32(bytes, kSlotTicksOffset);
    out.addTimestamp(entry);
    ++stats_.timestamp_entries;
  }
}

bool PacketParser::acceptCounter(EventSource source, std::uint16_t counter, std::uint32_t packet_index,
                                 std::uint32_t slot, ParsedTransfer& out) {
  const auto code = static_cast<std::size_t>(source);
  if (!has_counter_[code]) {
    has_counter_[code] = true;
    last_counter_[code] = counter;
    return true;
  }
  const std::uint16_t previous = last_counter_[code];
  const unsigned step = (counter + kCounterModulus - previous) % kCounterModulus;
  if (step == 0) {
    report({.reason = PacketDropReason::kCounterRepeated,
            .packet_index = packet_index,
            .slot_index = slot,
            .source = source,
            .value = counter,
            .reference = previous},
           out);
    return false;
  }
  last_counter_[code] = counter;  // a step back re-anchors here too (see the header)
  if (step > kMaxForwardCounterStep) {
    report({.reason = PacketDropReason::kCounterWentBack,
            .packet_index = packet_index,
            .slot_index = slot,
            .source = source,
            .value = counter,
            .reference = previous},
           out);
    return false;
  }
  return true;
}

void PacketParser::report(const PacketProblem& problem, ParsedTransfer& out) {
  ++stats_.drop_counts[static_cast<std::size_t>(problem.reason)];
  last_problem_ = problem;
  out.noteProblem(problem);
}

void PacketParser::trackCx3Counter(std::uint8_t counter) {
  if (has_cx3_counter_ && counter != (last_cx3_counter_ + 1) % kCx3CounterModulus) ++stats_.cx3_counter_skips;
  has_cx3_counter_ = true;
  last_cx3_counter_ = counter;
}

void PacketParser::reset() { *this = PacketParser{}; }

}  // namespace vifusion::motion
