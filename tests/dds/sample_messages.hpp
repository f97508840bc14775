#pragma once
// One message of every published type, filled with values that expose lost precision, truncated
// integers and misplaced fields, together with the storage the messages borrow.

#include <array>
#include <vector>

#include "vifusion/dds/conversions.hpp"

namespace vifusion::dds::test {

struct SampleMessages {
  SampleMessages();
  // The messages point into this object's own arrays.
  SampleMessages(const SampleMessages&) = delete;
  SampleMessages& operator=(const SampleMessages&) = delete;

  std::array<msg::TransformStamped, 2> transforms{};
  std::vector<MapPoint> points;
  std::array<msg::KeyValue, 2> key_values{};
  std::array<msg::DiagnosticStatus, 2> statuses{};

  msg::PoseStamped pose{};
  msg::Odometry odometry{};
  msg::TFMessage tf{};
  msg::PointCloud2 map{};
  msg::DiagnosticArray diagnostics{};
  msg::ImuState imu_state{};
  /// From marginal variances with held blocks (gyro mode): their variances go out as −1.
  msg::ImuState imu_state_from_variances{};
  /// The rgbdi odometry: pose covariance from the variances, twist from the estimator's velocity.
  msg::Odometry inertial_odometry{};
  msg::Status status{};
  msg::MapSaveRequest map_save_request{};
};

}  // namespace vifusion::dds::test
