#pragma once
// One motion-module packet with every documented field decoded (layout: packet_format.hpp). The parser
// produces these fields; the encoder takes them, so tests and the scripted device build byte fixtures from
// the same description. Values stay raw: ticks are not unwrapped or mapped to host time (clock module),
// counters are not unwrapped, axes are not scaled (imu_scaling.hpp).

#include <array>
#include <cstdint>

#include "vifusion/motion/packet_format.hpp"

namespace vifusion::motion {

struct PacketHeader {
  std::uint16_t error_bitmask = 0;          ///< bit i set = ErrorFlag i reported
  bool power_mode_change_done = false;      ///< status bit 1
  std::uint8_t cx3_packet_counter = 0;      ///< status bits 2–5, 0…15
  std::uint16_t imu_entry_count = 0;        ///< slots in use, valid 0…kImuSlotCount
  std::uint16_t timestamp_entry_count = 0;  ///< slots in use, valid 0…kTimestampSlotCount
};

/// An accelerometer or gyroscope reading as sent.
struct ImuEntry {
  EventSource source = EventSource::kAccelerometer;
  std::uint16_t sample_counter = 0;  ///< 12-bit, wraps at kCounterModulus
  bool valid = true;                 ///< tag bit 15
  std::uint32_t ticks = 0;           ///< device clock at the sample, 32 MHz, wraps at 2^32
  /// Raw axis words. Gyro: counts of gyro full scale / 32767. Accelerometer: the reading is in the
  /// 12 most significant bits (ImuScaler shifts it).
  std::array<std::int16_t, kAxisCount> raw_xyz{};
};

/// A frame or GPIO event stamped on the IMU's clock.
struct TimestampEntry {
  EventSource source = EventSource::kDepthFrame;
  std::uint16_t frame_counter = 0;  ///< 12-bit frame or edge number, wraps at kCounterModulus
  /// Tag bit 15. Kept but not checked: librealsense reads it for IMU entries only, so its meaning on
  /// timestamp entries is unconfirmed.
  bool valid = true;
  std::uint32_t ticks = 0;  ///< device clock at the event, 32 MHz
};

/// A whole packet: the header and all slots, including unused ones (count fields say which are used).
struct MotionPacket {
  PacketHeader header;
  std::array<ImuEntry, kImuSlotCount> imu{};
  std::array<TimestampEntry, kTimestampSlotCount> timestamps{};
};

}  // namespace vifusion::motion
