#pragma once
// The publisher thread: reads the output ring and publishes, per frame, rt/vifusion/odometry,
// rt/vifusion/pose and rt/tf, and in the inertial modes rt/vifusion/imu_state; every
// status_period_s rt/vifusion/status; and each map snapshot as rt/vifusion/map (PointCloud2,
// transient-local). All messages borrow buffers allocated here at start-up; only a growing map
// enlarges the point buffer.
//
// Frames as REP-105 has them (map → odom → camera): rt/tf carries map → odom (slam::FrameResult::T_W_O, which
// jumps only when a loop closure moves the map) and odom → camera; rt/vifusion/odometry is in odom, continuous
// across closures, so a consumer fusing it never sees a closure's jump; rt/vifusion/pose, rt/vifusion/imu_state
// and rt/vifusion/map are in map, the best estimate now.
//
// Odometry twist.angular is always the finite difference of consecutive poses (the estimator has no
// angular-velocity state). The rest depends on what the frame carries (PoseResult::inertial):
//  - rgbd mode, and inertial-mode frames without an estimator state (before it starts): the pose
//    covariance is a PLACEHOLDER, a fixed diagonal of (1 cm)² for position and (0.01 rad)² for
//    rotation; twist.linear is the finite difference of consecutive poses; twist covariance zero
//    (unknown). A lost frame (slam/tracking_state.hpp; its pose is a guess) gets a variance of 10⁶ m²
//    and rad² instead: no information, so a consumer that fuses odometry ignores it.
//  - rgbdi: pose covariance from the estimator's marginal variances (dds::odometryPoseCovariance:
//    diagonal only); twist.linear is the estimator's velocity moved to the camera's origin, with its
//    covariance rotated into C (dds::makeInertialOdometry); angular twist covariance zero (unknown).
//    While the IMU carries the pose the estimator's variances grow with the dead reckoning, and they are
//    what is published, lost or not.
//  - gyro: pose covariance from the estimator as in rgbdi; velocity is held, not estimated, so the
//    twist is as in rgbd mode.
// rt/vifusion/imu_state (dds::makeImuStateFromVariances) goes out for every frame with an estimator
// state, stamped like the odometry.
//
// A loaded map's relocalising frames (PoseResult::relocalising) publish nothing but the status
// (TRACKING_RELOCALISING): until a frame is located in the saved map there is no pose in its W to give.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "vifusion/config/daemon_config.hpp"
#include "vifusion/core/latency_window.hpp"
#include "vifusion/daemon/shared_state.hpp"
#include "vifusion/dds/conversions.hpp"
#include "vifusion/dds/participant.hpp"
#include "vifusion/dds/topics.hpp"
#include "vifusion/dds/writer.hpp"

namespace vifusion::daemon {

class Publisher {
 public:
  /// Creates the writers; throws vifusion::Error on a DDS failure.
  /// `T_S_C` (camera → IMU, the calibration's) places the IMU velocity at the camera's origin.
  Publisher(const dds::Participant& participant, const config::DaemonConfig& config, float map_confidence_threshold,
            const SE3d& T_S_C, SharedState& state);
  /// The thread body: runs until the SLAM thread is done and the output ring is drained.
  void run();

 private:
  void publishPose(const PoseResult& result);
  void publishStatus(std::int64_t now_ns);
  void publishMap(std::int64_t t_ns);

  const config::DaemonConfig& config_;
  float map_confidence_threshold_;
  SE3d T_S_C_;
  bool velocity_estimated_;  ///< mode rgbdi: the estimator's velocity feeds the odometry twist
  SharedState& state_;
  dds::Writer<dds::msg::Odometry> odometry_;
  dds::Writer<dds::msg::PoseStamped> pose_;
  dds::Writer<dds::msg::TFMessage> tf_;
  dds::Writer<dds::msg::ImuState> imu_state_;
  dds::Writer<dds::msg::Status> status_;
  dds::Writer<dds::msg::PointCloud2> map_;

  std::uint64_t heartbeat_ = 0;
  PoseResult last_{};
  SE3d last_T_O_C_;  ///< the odometry pose of last_
  bool have_last_ = false;
  bool relocalising_ = false;               ///< the newest result was a loaded map's relocalising frame
  std::uint32_t relocalising_surfels_ = 0;  ///< the loaded map's surfels, while relocalising
  LatencyWindow latency_;                   ///< sensor time → pose published, the last frames [ms]
  /// (host time [ns], frames processed) at the last status messages, for a ~1 s frame-rate window.
  static constexpr std::size_t kRateWindow = 32;
  std::array<std::pair<std::int64_t, std::uint64_t>, kRateWindow> rate_samples_{};
  std::size_t rate_count_ = 0;
  std::vector<map::Surfel> surfels_;
  std::vector<dds::MapPoint> points_;
};

}  // namespace vifusion::daemon
