#pragma once
// Settings of the live ZR300 source (zr300_source.hpp), each defined once, with the range validate() enforces.
//
// Stream presets (issue 17): 640×480 and 320×240 at 30 Hz, 480×360 at 60 Hz. Colour (YUYV) streams at the
// preset's size. The depth node delivers the image without the DS4's 6-px padding plus one metadata row
// ("dinghy"), so a W×H preset asks the depth node for (W − 12)×(H − 11): 628×469 for 640×480, as
// sensors.md §1.2 documents; the other two sizes follow the same rule (not checked against a device).

#include <cstddef>
#include <cstdint>

#include "vifusion/core/live_imu_feed.hpp"
#include "vifusion/usb_imu/motion_module_options.hpp"

namespace vifusion::zr300 {

/// Pixels of padding the DS4 puts on every side of a depth image (ds_metadata.hpp).
inline constexpr int kDepthPaddingPx = 6;
/// Metadata rows at the end of a depth frame.
inline constexpr int kDepthMetadataRows = 1;

struct StreamPreset {
  int width_px = 640;
  int height_px = 480;
  int fps = 30;
};

struct Zr300Options {
  StreamPreset preset;  ///< one of kPresets below
  /// MMAP buffers per V4L2 stream [buffers], [2, 32]: one being filled, one with the assembler, the rest
  /// absorb a late consumer for (buffer_count − 2) frame periods before the driver drops frames.
  int buffer_count = 4;
  /// Assembled frames waiting for the SLAM thread [frames], [1, 64]. When it is full the camera thread stops
  /// dequeuing, so further frames are dropped by the driver and counted from the V4L2 sequence gaps.
  std::size_t frame_ring_capacity = 4;
  /// Depth unit written to the camera before streaming [µm per Z16 unit], 0 = keep the camera's (read back
  /// either way: the frames' depth_scale_m comes from the camera).
  std::uint32_t depth_units_um = 0;
  bool emitter = true;  ///< structured-light projector on (needed for depth on texture-less surfaces)
  /// Open and stream the motion module (IMU, depth-frame events). Modes rgbdi and gyro need it; without it
  /// frames take their kernel timestamps.
  bool imu = true;
  /// Longest wait for one buffer before the loop checks for stop or unplug [ns], [1 ms, 1 s].
  std::int64_t poll_timeout_ns = 100'000'000;
  /// Longest wait for the motion module's event of a depth frame before the frame falls back to its kernel
  /// mid-exposure time (counted) [ns], [0, 1 s]. Events travel in interrupt transfers a few ms apart. No wait
  /// while the device clock's mapping is still warming up (no events are published then).
  std::int64_t frame_event_wait_ns = 30'000'000;
  /// Largest |event time − kernel mid-exposure time| for an event to belong to the frame [ns], (0, 1 s].
  /// Frame numbers are 12-bit (they repeat every 136 s at 30 Hz); the two clocks agree to USB latency.
  std::int64_t frame_event_tolerance_ns = 100'000'000;
  /// Re-open attempts after an unplug start this far apart and double up to the maximum [ns]: uvcvideo binds
  /// the three nodes one after another after the USB device appears.
  std::int64_t reopen_backoff_min_ns = 100'000'000;
  std::int64_t reopen_backoff_max_ns = 2'000'000'000;

  usb_imu::MotionModuleOptions motion;
  LiveImuFeedOptions imu_feed;  ///< its time_shift_cam_imu_ns is taken from the calibration

  /// @throws vifusion::Error naming the first bad field and its allowed range (nested options too).
  void validate() const;

  /// The depth node's frame size for the preset: (W − 2·padding) × (H − 2·padding + metadata rows).
  int depthNodeWidthPx() const { return preset.width_px - 2 * kDepthPaddingPx; }
  int depthNodeHeightPx() const { return preset.height_px - 2 * kDepthPaddingPx + kDepthMetadataRows; }
};

inline constexpr StreamPreset kPresets[] = {{640, 480, 30}, {320, 240, 30}, {480, 360, 60}};

}  // namespace vifusion::zr300
