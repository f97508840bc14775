#pragma once
// A depth-camera frame as the motion module saw it: its 12-bit frame number and the host time of the
// event. The camera side matches V4L2 frames to these by frame number (the DS metadata counter).

#include <cstdint>

namespace vifusion::usb_imu {

struct DepthFrameEvent {
  std::uint16_t frame_counter = 0;  ///< the 12-bit number as sent, wraps at 4096
  std::int64_t device_ns = 0;       ///< unwrapped device time of the event [ns, 32 MHz ticks]
  std::int64_t t_ns = 0;            ///< the event mapped onto host CLOCK_MONOTONIC [ns]
};

}  // namespace vifusion::usb_imu
