#pragma once
// The motion module's depth-frame events, kept for the camera thread to stamp frames with: a frame whose
// DS4 metadata counter is n takes the event whose 12-bit number is n mod 4096 and whose time is within a
// tolerance of the frame's kernel mid-exposure time (the numbers repeat every 4096 frames, 136 s at 30 Hz,
// and restart with the device). A fixed table of the newest events; no allocation.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "vifusion/usb_imu/frame_event.hpp"

namespace vifusion::zr300 {

class FrameEventTable {
 public:
  /// Events kept: 2 s at 30 Hz, 1 s at 60 Hz, far more than the USB latency between event and frame.
  static constexpr std::size_t kCapacity = 64;

  void add(const usb_imu::DepthFrameEvent& event);
  /// The event for a frame with `frame_counter` whose kernel time is `kernel_ns` (its t_ns within
  /// `tolerance_ns` of it), or nullopt when no kept event matches. The closest in time wins.
  std::optional<usb_imu::DepthFrameEvent> find(std::uint32_t frame_counter, std::int64_t kernel_ns,
                                               std::int64_t tolerance_ns) const;
  void clear() { count_ = 0; }

 private:
  std::array<usb_imu::DepthFrameEvent, kCapacity> events_{};
  std::size_t next_ = 0;   ///< slot the next event goes to
  std::size_t count_ = 0;  ///< slots in use
};

}  // namespace vifusion::zr300
