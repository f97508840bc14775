#pragma once
// What the live source counted, as a plain snapshot (Zr300Source::stats() copies it under a lock, so the
// service's status reporter reads it from another thread).

#include <cstdint>

#include "vifusion/usb_imu/motion_module_stats.hpp"

namespace vifusion::zr300 {

struct Zr300Stats {
  bool camera_present = false;          ///< streaming now (false between an unplug and the re-open)
  std::uint64_t frames = 0;             ///< assembled and handed to the consumer
  std::uint64_t rejected_frames = 0;    ///< refused by the driver or by their metadata (bad dinghy, short)
  std::uint64_t unpaired_depth = 0;     ///< depth frames without the colour frame of the same number
  std::uint64_t unpaired_colour = 0;    ///< colour frames without the depth frame of the same number
  std::uint64_t event_timestamps = 0;   ///< frames stamped by the motion module's frame event
  std::uint64_t kernel_timestamps = 0;  ///< frames that fell back to the kernel's mid-exposure time
  std::uint64_t time_regressions = 0;   ///< frames dropped because their time was not after the previous one
  std::int64_t depth_dropped = 0;       ///< depth frames missing from the V4L2 sequence and the DS4 counter
  std::int64_t colour_dropped = 0;      ///< colour frames missing from the V4L2 sequence
  std::uint64_t unplugs = 0;            ///< times the camera went away while streaming
  std::uint64_t reopens = 0;            ///< times it was opened again after that
  usb_imu::MotionModuleStats motion;    ///< IMU driver counters and the device→host clock (offset, drift)
};

}  // namespace vifusion::zr300
