#pragma once
// One interrupt transfer of the motion module as it came off the bus, for recordings: its packets keep every
// device tick and counter (the IMU samples' own device times among them) and the host time it arrived, from
// which a replay or the timestamp-sync check can redo the device→host clock mapping.

#include <array>
#include <cstddef>
#include <cstdint>

#include "vifusion/motion/packet_format.hpp"

namespace vifusion::usb_imu {

struct RawTransfer {
  std::int64_t host_receive_ns = 0;  ///< when the transfer completed, host CLOCK_MONOTONIC [ns]
  std::uint32_t index = 0;           ///< completed transfers since start(), 0-based (a gap: transfers lost here)
  std::size_t size = 0;              ///< bytes of `bytes` in use, [0, motion::kMaxTransferBytes]
  std::array<std::uint8_t, motion::kMaxTransferBytes> bytes{};
};

}  // namespace vifusion::usb_imu
