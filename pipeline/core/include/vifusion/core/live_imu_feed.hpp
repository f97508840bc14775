#pragma once
// ImuFeed over a live driver's ring (imu_feed.hpp): the SLAM thread drains the SpscRing<ImuSample> that a
// driver thread fills into a window reserved at construction, waits a bounded time for the sample that
// covers the frame, and hands the window out.
//
// Per frame at camera time t_cam (IMU time t = t_cam + time_shift_cam_imu_ns):
//  1. drain the ring into the window's end; a sample not later than the window's newest is dropped and
//     counted (out_of_order): the ring's producer stamps on one monotonic clock, so this is a driver bug or a
//     device restart, and keeping it would make the pipeline refuse every later frame;
//  2. until the window's newest sample is at or after t, or max_wait_ns has passed, wait in short steps and
//     drain again: the frame is interpolated, never extrapolated; a frame whose samples do not come in time is
//     counted (late_frames) and handed what there is, so the pipeline's own check refuses it (kNotCovered);
//  3. drop from the front what precedes the last sample at or before t_prev − retain_ns, t_prev being the
//     previous frame's IMU time (t itself at the first frame): the retained history is what the estimator reads when it
//     (re)starts (its gravity window ends at the frame), so retain_ns must exceed that window.
// When the window is full while draining, its oldest samples make room and are counted (window_drops).
//
// Threads: samplesThrough() and stats() on the consumer (SLAM) thread only. No allocation after
// construction: the window is a vector reserved to its capacity and only erased from the front.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "vifusion/core/imu_feed.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/core/spsc_ring.hpp"

namespace vifusion {

struct LiveImuFeedOptions {
  /// Samples the window holds [samples], ≥ 16. It must hold retain_ns plus the longest frame interval of
  /// samples: 4096 at a 250 Hz merged stream is 16 s.
  std::size_t window_capacity = 4096;
  /// History kept before the previous frame's IMU time [ns], [0, 60 s]. 1 s covers the estimator's gravity
  /// window (estimator_options.hpp, 0.2 s by default) with room for a slower first frame.
  std::int64_t retain_ns = 1'000'000'000;
  /// Longest wait for the sample at or after the frame's IMU time [ns], [0, 10 s]. The motion module sends a
  /// transfer every few ms and the frame reaches the SLAM thread tens of ms after its exposure, so the sample
  /// is normally there already; 50 ms tolerates a late USB transfer without stalling tracking for long.
  std::int64_t max_wait_ns = 50'000'000;
  /// The calibration's camera-to-IMU clock offset [ns]: t_imu = t_cam + this (RigCalibration).
  std::int64_t time_shift_cam_imu_ns = 0;

  /// @throws vifusion::Error naming the field out of range.
  void validate() const;
};

struct LiveImuFeedStats {
  std::uint64_t samples = 0;       ///< drained from the ring into the window
  std::uint64_t out_of_order = 0;  ///< dropped: not later than the newest sample before them
  std::uint64_t window_drops = 0;  ///< oldest samples pushed out by a full window
  std::uint64_t late_frames = 0;   ///< frames whose covering sample had not come within max_wait_ns
  std::uint64_t frames = 0;        ///< samplesThrough() calls
};

class LiveImuFeed final : public ImuFeed {
 public:
  /// `ring` is borrowed: the driver that fills it must outlive this feed's use. @throws as validate().
  LiveImuFeed(SpscRing<ImuSample>& ring, const LiveImuFeedOptions& options);

  std::span<const ImuSample> samplesThrough(std::int64_t t_cam_ns) override;

  const LiveImuFeedStats& stats() const { return stats_; }
  const LiveImuFeedOptions& options() const { return options_; }

 private:
  /// Moves whatever the ring holds into the window. Returns true when the newest sample is at or after t.
  bool drainUntil(std::int64_t t_imu_ns);
  void trimBefore(std::int64_t t_keep_ns);

  SpscRing<ImuSample>& ring_;
  LiveImuFeedOptions options_;
  std::vector<ImuSample> window_;
  ImuSample incoming_;
  bool have_previous_ = false;
  std::int64_t previous_t_imu_ns_ = 0;
  LiveImuFeedStats stats_;
};

}  // namespace vifusion
