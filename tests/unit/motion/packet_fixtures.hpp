#pragma once
// Motion packets for the tests, described field by field (the encoder turns them into bytes).

#include <cstdint>
#include <span>
#include <vector>

#include "vifusion/motion/motion_packet.hpp"
#include "vifusion/motion/packet_encoder.hpp"

namespace vifusion::motion::test {

inline ImuEntry imuEntry(EventSource source, std::uint16_t counter, std::uint32_t ticks,
                         std::array<std::int16_t, kAxisCount> raw_xyz = {}) {
  ImuEntry entry;
  entry.source = source;
  entry.sample_counter = counter;
  entry.valid = true;
  entry.ticks = ticks;
  entry.raw_xyz = raw_xyz;
  return entry;
}

inline TimestampEntry timestampEntry(EventSource source, std::uint16_t counter, std::uint32_t ticks) {
  TimestampEntry entry;
  entry.source = source;
  entry.frame_counter = counter;
  entry.valid = true;
  entry.ticks = ticks;
  return entry;
}

/// A packet holding one accelerometer and one gyro entry with counter `counter`, and nothing else.
inline MotionPacket accelGyroPacket(std::uint16_t counter, std::uint8_t cx3_counter = 0) {
  MotionPacket packet;
  packet.header.cx3_packet_counter = cx3_counter;
  packet.header.imu_entry_count = 2;
  packet.imu[0] = imuEntry(EventSource::kAccelerometer, counter, 1000u * counter, {16, -32, 48});
  packet.imu[1] = imuEntry(EventSource::kGyroscope, counter, 1000u * counter + 7, {1, -2, 3});
  return packet;
}

inline std::vector<std::uint8_t> encode(std::span<const MotionPacket> packets) {
  std::vector<std::uint8_t> bytes(packets.size() * kPacketBytes);
  encodeTransfer(packets, bytes);
  return bytes;
}

inline std::vector<std::uint8_t> encode(const MotionPacket& packet) { return encode(std::span(&packet, 1)); }

}  // namespace vifusion::motion::test
