#pragma once
// Where the SLAM thread gets each frame's IMU samples in the inertial modes (rgbdi, gyro).
//
// Slam::process(frame, imu) wants a time-sorted span of samples on the IMU clock that reaches at
// least from the previous frame through this one (and, before the first frame, the estimator's gravity
// window); it finds the frame's part by binary search, so a longer span costs nothing. The feed hands
// out that span once per frame, on the SLAM thread, without allocating.
//
// Recorded sources (dataset:, sim:) hold the whole stream in memory: RecordedImuFeed returns the
// reader's imu() span every time. The span is the reader's and stays valid for the reader's lifetime,
// so the reader must outlive the SLAM thread (vifusiond's serve() joins the threads before it goes).
//
// A live IMU (the ZR300 motion module's driver thread pushing into an SpscRing<ImuSample>) fits the same
// call: LiveImuFeed (live_imu_feed.hpp) drains the ring into a window reserved at start and waits a bounded
// time for the sample that covers the frame. A frame whose samples do not arrive in time is refused by the
// pipeline's own checks (imu::checkSampleWindow → FrameResult::imu_issue), counted, never fatal — exactly
// like a gap in a recording.

#include <cstdint>
#include <span>

#include "vifusion/core/sensor_data.hpp"

namespace vifusion {

class ImuFeed {
 public:
  virtual ~ImuFeed() = default;
  /// The samples for the frame taken at `t_cam_ns` (camera clock): see above. The span stays valid
  /// until the next call. Called on the SLAM thread only; must not allocate.
  virtual std::span<const ImuSample> samplesThrough(std::int64_t t_cam_ns) = 0;
};

/// A recording's whole IMU stream, handed out unchanged for every frame.
class RecordedImuFeed final : public ImuFeed {
 public:
  /// `stream` is borrowed (DatasetReader::imu()): it must outlive this feed's use.
  explicit RecordedImuFeed(std::span<const ImuSample> stream) : stream_(stream) {}
  std::span<const ImuSample> samplesThrough(std::int64_t /*t_cam_ns*/) override { return stream_; }

 private:
  std::span<const ImuSample> stream_;
};

}  // namespace vifusion
