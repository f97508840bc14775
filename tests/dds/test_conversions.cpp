// Messages from vifusion types: time splitting, frames of pose and twist, the ImuState's frame changes
// and covariances, the PointCloud2 layout of map chunks.

#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "vifusion/core/so3.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/dds/conversions.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::dds {
namespace {

TEST(DdsConversions, TimeSplitsIntoSecondsAndNanoseconds) {
  EXPECT_EQ(toTime(0).sec, 0);
  EXPECT_EQ(toTime(1'700'000'000'123'456'789).sec, 1'700'000'000);
  EXPECT_EQ(toTime(1'700'000'000'123'456'789).nanosec, 123'456'789u);
  // Negative times floor: −1 ns is −1 s + 999999999 ns, as rclcpp's Time does.
  EXPECT_EQ(toTime(-1).sec, -1);
  EXPECT_EQ(toTime(-1).nanosec, 999'999'999u);
  EXPECT_EQ(toTime(-2 * kNsPerSecond).sec, -2);
  EXPECT_EQ(toTime(-2 * kNsPerSecond).nanosec, 0u);
  for (const std::int64_t t_ns : {std::int64_t{0}, std::int64_t{-1}, std::int64_t{1'234'567'890'123},
                                  std::int64_t{std::numeric_limits<std::int32_t>::max()} * kNsPerSecond + 999'999'999,
                                  std::int64_t{std::numeric_limits<std::int32_t>::min()} * kNsPerSecond}) {
    EXPECT_EQ(toNs(toTime(t_ns)), t_ns);
  }
  vifusion::test::expectError(
      [] { toTime(std::int64_t{std::numeric_limits<std::int32_t>::max() + 1LL} * kNsPerSecond); },
      "does not fit builtin_interfaces/Time");
}

TEST(DdsConversions, PoseIsTheTransformOfTheChildInTheParent) {
  const SE3d T_W_C(Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ())), Eigen::Vector3d(1, 2, 3));
  const msg::PoseStamped pose = makePoseStamped(5, "world", T_W_C);
  EXPECT_STREQ(pose.header.frame_id, "world");
  EXPECT_EQ(pose.pose.position.x, 1.0);
  EXPECT_EQ(pose.pose.position.z, 3.0);
  EXPECT_EQ(pose.pose.orientation.w, T_W_C.quaternion().w());
  EXPECT_EQ(pose.pose.orientation.z, T_W_C.quaternion().z());

  const msg::TransformStamped tf = makeTransformStamped(5, "world", "camera", T_W_C);
  EXPECT_STREQ(tf.header.frame_id, "world");
  EXPECT_STREQ(tf.child_frame_id, "camera");
  EXPECT_EQ(tf.transform.translation.y, 2.0);
  EXPECT_EQ(tf.transform.rotation.z, T_W_C.quaternion().z());
}

TEST(DdsConversions, OdometryTwistIsInTheChildFrame) {
  // C is W turned by +90° about z: C's x axis is W's y axis.
  const SE3d T_W_C(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())), Eigen::Vector3d::Zero());
  Matrix6d pose_covariance = Matrix6d::Zero();
  pose_covariance(0, 1) = 1.5;  // row 0, column 1 → index 1 in row-major order
  pose_covariance(5, 4) = 2.5;  // → index 34
  const msg::Odometry odometry = makeOdometry(0, "world", "camera", T_W_C, Eigen::Vector3d(0, 2, 0),
                                              Eigen::Vector3d(0.1, 0.2, 0.3), pose_covariance, Matrix6d::Identity());
  EXPECT_STREQ(odometry.header.frame_id, "world");
  EXPECT_STREQ(odometry.child_frame_id, "camera");
  EXPECT_NEAR(odometry.twist.twist.linear.x, 2.0, 1e-15);  // moving along W's y = C's x
  EXPECT_NEAR(odometry.twist.twist.linear.y, 0.0, 1e-15);
  EXPECT_EQ(odometry.twist.twist.angular.z, 0.3);
  EXPECT_EQ(odometry.pose.covariance[1], 1.5);
  EXPECT_EQ(odometry.pose.covariance[34], 2.5);
  EXPECT_EQ(odometry.pose.covariance[6], 0.0);
  EXPECT_EQ(odometry.twist.covariance[7], 1.0);
}

TEST(DdsConversions, ImuStateIsExpressedInTheWorld) {
  NavState x;
  // I is W turned by +90° about x, so W's −y axis is I's −z axis (gravity).
  x.q_I_W = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));
  x.v_I_S = Eigen::Vector3d(0, 0, 1);  // upwards in I
  x.b_g = Eigen::Vector3d(1e-3, 2e-3, 3e-3);
  x.b_a = Eigen::Vector3d(0.1, 0.2, 0.3);
  Matrix18d covariance = Matrix18d::Zero();
  covariance.block<3, 3>(kIdxV, kIdxV).diagonal() << 1, 2, 3;
  covariance.block<3, 3>(kIdxBg, kIdxBg).diagonal() << 4, 5, 6;
  covariance.block<3, 3>(kIdxBa, kIdxBa).diagonal() << 7, 8, 9;
  covariance.block<3, 3>(kIdxG, kIdxG).diagonal() << 0.01, 0.02, 0.03;
  const msg::ImuState state = makeImuState(9, "world", x, covariance);

  // R_W_I maps I's z to W's y.
  EXPECT_NEAR(state.velocity.y, 1.0, 1e-15);
  EXPECT_NEAR(state.velocity.z, 0.0, 1e-15);
  EXPECT_NEAR(state.gravity_direction.x, 0.0, 1e-15);
  EXPECT_NEAR(state.gravity_direction.y, -1.0, 1e-15);
  EXPECT_NEAR(state.gravity_direction.z, 0.0, 1e-15);
  EXPECT_EQ(state.gyro_bias.z, 3e-3);
  EXPECT_EQ(state.accel_bias.x, 0.1);
  // Velocity variances follow the axes: I's (x, y, z) are W's (x, −z, y).
  EXPECT_NEAR(state.velocity_covariance[0], 1.0, 1e-12);
  EXPECT_NEAR(state.velocity_covariance[1], 3.0, 1e-12);
  EXPECT_NEAR(state.velocity_covariance[2], 2.0, 1e-12);
  EXPECT_EQ(state.gyro_bias_covariance[1], 5.0);
  EXPECT_EQ(state.accel_bias_covariance[2], 9.0);
  // Tilting gravity (0, 0, −1)_I about I's x moves it along I's y (W's −z), about I's y along I's x
  // (W's x); rotations about I's z leave it alone.
  EXPECT_NEAR(state.gravity_direction_covariance[0], 0.02, 1e-12);
  EXPECT_NEAR(state.gravity_direction_covariance[1], 0.0, 1e-12);
  EXPECT_NEAR(state.gravity_direction_covariance[2], 0.01, 1e-12);
}

TEST(DdsConversions, ImuStateGravityCovarianceMatchesAPerturbation) {
  NavState x;
  x.q_I_W = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, -2, 0.5).normalized()));
  const Eigen::Vector3d dg(1e-7, -2e-7, 3e-7);
  // ⊞ perturbs q_I_W on the left in I (state.hpp).
  NavState perturbed = x;
  perturbed.q_I_W = Eigen::Quaterniond(expSO3(dg)) * x.q_I_W;
  Matrix18d covariance = Matrix18d::Zero();
  for (int i = 0; i < 3; ++i) covariance(kIdxG + i, kIdxG + i) = 1.0;
  const msg::ImuState at_x = makeImuState(0, "world", x, covariance);
  const msg::ImuState at_perturbed = makeImuState(0, "world", perturbed, covariance);
  // Unit δg variances: each diagonal entry is the squared norm of a row of ∂g_W/∂δg; the finite
  // difference along δg checks the Jacobian's direction through g_W(x ⊞ δg) − g_W(x) = J·δg.
  const Eigen::Vector3d g_W(at_x.gravity_direction.x, at_x.gravity_direction.y, at_x.gravity_direction.z);
  const Eigen::Vector3d g_W_perturbed(at_perturbed.gravity_direction.x, at_perturbed.gravity_direction.y,
                                      at_perturbed.gravity_direction.z);
  const Eigen::Matrix3d R_W_I = x.q_I_W.conjugate().toRotationMatrix();
  const Eigen::Matrix3d J = R_W_I * hat(Eigen::Vector3d(0, 0, -1));
  EXPECT_LT((g_W_perturbed - g_W - J * dg).norm(), 1e-12);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(at_x.gravity_direction_covariance[i], J.row(i).squaredNorm(), 1e-12);
  EXPECT_NEAR(g_W.norm(), 1.0, 1e-15);
}

TEST(DdsConversions, PointCloud2DescribesMapPoints) {
  const MapPoint points[2] = {{1.0f, 2.0f, 3.0f, MapPoint::packRgb(255, 128, 1), 0.0f, 0.0f, 1.0f, 0.01f, 7.0f}, {}};
  const msg::PointCloud2 cloud = makePointCloud2(3, "world", points);
  EXPECT_STREQ(cloud.header.frame_id, "world");
  EXPECT_EQ(cloud.height, 1u);
  EXPECT_EQ(cloud.width, 2u);
  EXPECT_EQ(cloud.point_step, 36u);
  EXPECT_EQ(cloud.row_step, 72u);
  EXPECT_EQ(cloud.data._length, 72u);
  EXPECT_FALSE(cloud.is_bigendian);
  EXPECT_TRUE(cloud.is_dense);
  EXPECT_FALSE(cloud.data._release);

  const char* names[] = {"x", "y", "z", "rgb", "normal_x", "normal_y", "normal_z", "radius", "confidence"};
  ASSERT_EQ(cloud.fields._length, 9u);
  for (std::uint32_t i = 0; i < 9; ++i) {
    EXPECT_STREQ(cloud.fields._buffer[i].name, names[i]);
    EXPECT_EQ(cloud.fields._buffer[i].offset, 4 * i);
    EXPECT_EQ(cloud.fields._buffer[i].datatype, sensor_msgs_msg_PointField_Constants_FLOAT32);
    EXPECT_EQ(cloud.fields._buffer[i].count, 1u);
  }
  // Little-endian bytes: z = 3.0f at offset 8, rgb 0x00ff8001 at 12 (PCL: B, G, R, 0 in memory).
  const std::uint8_t* data = cloud.data._buffer;
  float z = 0;
  std::memcpy(&z, data + 8, 4);
  EXPECT_EQ(z, 3.0f);
  EXPECT_EQ(data[12], 0x01);
  EXPECT_EQ(data[13], 0x80);
  EXPECT_EQ(data[14], 0xff);
  EXPECT_EQ(data[15], 0x00);
  float confidence = 0;
  std::memcpy(&confidence, data + 32, 4);
  EXPECT_EQ(confidence, 7.0f);
}

}  // namespace
}  // namespace vifusion::dds
