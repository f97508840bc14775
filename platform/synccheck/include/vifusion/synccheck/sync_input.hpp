#pragma once
// What the timestamp-sync analysis (analyse.hpp) reads: the times of camera frames, sync-line edges, IMU
// samples and the clock mapper's residuals, whatever produced them (a live ZR300 with a GPIO sync line, a
// recording, the simulator in clock_model.hpp). All times are host CLOCK_MONOTONIC [ns], as the drivers
// hand them over. This tool runs off the per-frame path, so plain vectors hold everything.

#include <cstdint>
#include <vector>

namespace vifusion::synccheck {

/// The times known about one camera frame (zr300_source.hpp says how a live frame is stamped).
struct CameraFrameTimes {
  /// Position in the delivered sequence (0, 1, 2, …), as RgbdFrame::index; named in reports only.
  std::int64_t index = 0;
  /// The device's own frame counter (the DS4 metadata row's frameCount), 0 when the source has none (then
  /// every frame of the input carries 0 and the counter checks are skipped). Wraps at
  /// SyncCheckOptions::frame_number_bits.
  std::uint32_t device_frame_number = 0;
  /// The stamp SLAM used: the motion-module event mapped to host time, else the kernel's [ns].
  std::int64_t t_ns = 0;
  /// The kernel's mid-exposure time of the depth buffer [ns]; 0 = unknown.
  std::int64_t kernel_mid_ns = 0;
  /// The motion module's frame event for this frame, mapped to host time [ns]; 0 = none arrived.
  std::int64_t device_event_ns = 0;
  /// true: t_ns came from device_event_ns; false: from kernel_mid_ns (no event within the wait).
  bool stamped_by_device_event = false;
};

/// One edge on the sync line (gpio_sync::SyncEdge without the driver's types).
struct SyncEdgeTime {
  std::int64_t t_ns = 0;  ///< kernel stamp of the edge interrupt [ns]
  bool rising = true;     ///< low → high (true) or high → low (false)
  /// Position among all edges the driver read (both polarities), 0-based: a gap is edges lost on our side.
  std::uint64_t sequence = 0;
};

/// One residual of the device→host clock mapping: host arrival time minus the mapped device time of a
/// transfer, i.e. the transfer's latency above the fitted line (>= 0 when the mapping is right).
struct ClockResidualSample {
  std::int64_t t_ns = 0;     ///< host arrival time of the transfer [ns]
  double residual_ns = 0.0;  ///< arrival − mapped device time [ns]; non-finite values are counted, not used
};

/// Everything analyse() reads. Frames, edges and IMU samples in the order the source delivered them.
struct SyncInput {
  std::vector<CameraFrameTimes> frames;
  std::vector<SyncEdgeTime> edges;
  std::vector<std::int64_t> imu_t_ns;  ///< IMU sample times [ns]
  std::vector<ClockResidualSample> clock_residuals;
};

}  // namespace vifusion::synccheck
