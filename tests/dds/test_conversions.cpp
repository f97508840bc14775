// Messages from vifusion types: time splitting, frames of pose and twist, the ImuState's frame changes
// and covariances, the PointCloud2 layout of map chunks.

#include <gtest/gtest.h>

#include <cmath>
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

TEST(DdsConversions, ImuStateFromVariancesIsTheDiagonalCovariance) {
  NavState x;
  x.q_I_W = Eigen::Quaterniond(Eigen::AngleAxisd(0.9, Eigen::Vector3d(-1, 2, 0.3).normalized()));
  x.v_I_S = Eigen::Vector3d(0.4, -0.1, 0.25);
  Vector18d variance;
  for (int i = 0; i < kStateDim; ++i) variance(i) = 0.01 * (i + 1);
  const Matrix18d covariance = variance.asDiagonal();
  const msg::ImuState from_variances = makeImuStateFromVariances(3, "map", x, variance);
  const msg::ImuState from_covariance = makeImuState(3, "map", x, covariance);
  EXPECT_STREQ(from_variances.header.frame_id, "map");
  EXPECT_EQ(from_variances.velocity.x, from_covariance.velocity.x);
  EXPECT_EQ(from_variances.gravity_direction.z, from_covariance.gravity_direction.z);
  const Eigen::Matrix3d R_W_I = x.q_I_W.conjugate().toRotationMatrix();
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(from_variances.velocity_covariance[i], from_covariance.velocity_covariance[i]);
    EXPECT_EQ(from_variances.gravity_direction_covariance[i], from_covariance.gravity_direction_covariance[i]);
    EXPECT_EQ(from_variances.gyro_bias_covariance[i], variance(kIdxBg + i));
    EXPECT_EQ(from_variances.accel_bias_covariance[i], variance(kIdxBa + i));
    // Σ_j R_ij² σ²_j: the W-axis variance of R_W_I·δv with independent I-axis components.
    double expected = 0.0;
    for (int j = 0; j < 3; ++j) expected += R_W_I(i, j) * R_W_I(i, j) * variance(kIdxV + j);
    EXPECT_NEAR(from_variances.velocity_covariance[i], expected, 1e-15);
  }
}

TEST(DdsConversions, ImuStateMarksHeldBlocksAsNotEstimated) {
  // Gyro mode holds δv, δb_a and δg: their variances are exactly 0 (slam::FrameResult::state_variance).
  NavState x;
  Vector18d variance = Vector18d::Constant(1e-4);
  variance.segment<3>(kIdxV).setZero();
  variance.segment<3>(kIdxBa).setZero();
  variance.segment<3>(kIdxG).setZero();
  const msg::ImuState state = makeImuStateFromVariances(0, "map", x, variance);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(state.velocity_covariance[i], -1.0);
    EXPECT_EQ(state.accel_bias_covariance[i], -1.0);
    EXPECT_EQ(state.gravity_direction_covariance[i], -1.0);
    EXPECT_EQ(state.gyro_bias_covariance[i], 1e-4);
  }
  // One estimated axis is enough for the block to count as estimated: its zeros are then real zeros.
  variance(kIdxV + 1) = 2e-4;
  const msg::ImuState partly = makeImuStateFromVariances(0, "map", x, variance);
  EXPECT_EQ(partly.velocity_covariance[0], 0.0);
  EXPECT_EQ(partly.velocity_covariance[1], 2e-4);
}

TEST(DdsConversions, OdometryPoseCovarianceIsTheStateDiagonalInRosOrder) {
  Vector18d variance;
  for (int i = 0; i < kStateDim; ++i) variance(i) = 1.0 + i;
  const Matrix6d covariance = odometryPoseCovariance(variance);
  // ROS [x, y, z, rx, ry, rz] = the state's [δr (W), δα (W)].
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) EXPECT_EQ(covariance(r, c), r == c ? variance(kIdxR + r) : 0.0) << r << "," << c;
  }
  const msg::Odometry odometry = makeOdometry(0, "map", "camera", SE3d(), Eigen::Vector3d::Zero(),
                                              Eigen::Vector3d::Zero(), covariance, Matrix6d::Zero());
  EXPECT_EQ(odometry.pose.covariance[0], variance(kIdxR));           // x
  EXPECT_EQ(odometry.pose.covariance[14], variance(kIdxR + 2));      // z
  EXPECT_EQ(odometry.pose.covariance[21], variance(kIdxAlpha));      // rx
  EXPECT_EQ(odometry.pose.covariance[35], variance(kIdxAlpha + 2));  // rz
  EXPECT_EQ(odometry.pose.covariance[1], 0.0);
}

TEST(DdsConversions, InertialOdometryTwistIsTheCameraOriginsVelocity) {
  // A rigid rig: S moves at v_W_S and the camera turns at ω_C; S sits at p_C_S in C.
  NavState x;
  x.r_W_C = Eigen::Vector3d(0.5, -1.0, 2.0);
  x.q_W_C = Eigen::Quaterniond(Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, 1, -2).normalized()));
  x.q_I_W = Eigen::Quaterniond(Eigen::AngleAxisd(-0.3, Eigen::Vector3d(0.2, 1, 0).normalized()));
  const Eigen::Vector3d v_W_S(0.3, -0.2, 0.15);
  x.v_I_S = x.q_I_W * v_W_S;
  const Eigen::Vector3d omega_C(0.4, -0.7, 1.1);
  const SE3d T_S_C(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX())),
                   Eigen::Vector3d(0.03, -0.05, 0.11));
  const Eigen::Vector3d p_C_S = T_S_C.inverse().translation();
  const Vector18d variance = Vector18d::Constant(1e-6);
  const msg::Odometry odometry = makeInertialOdometry(4, "map", "camera", SE3d(), x, variance, omega_C, T_S_C);

  // Independently: the camera's origin along the motion, r_W_C(t) = r_W_S(t) − R_W_C(t)·p_C_S with
  // R_W_C(t) = R_W_C·Exp(ω_C t), differentiated centrally.
  const Eigen::Matrix3d R_W_C = x.q_W_C.toRotationMatrix();
  const Eigen::Vector3d r_W_S = x.r_W_C + R_W_C * p_C_S;
  const auto r_W_C_at = [&](double t_s) -> Eigen::Vector3d {
    return r_W_S + v_W_S * t_s - R_W_C * expSO3(omega_C * t_s).toRotationMatrix() * p_C_S;
  };
  const double h_s = 1e-5;
  const Eigen::Vector3d v_C_expected = R_W_C.transpose() * (r_W_C_at(h_s) - r_W_C_at(-h_s)) / (2 * h_s);
  EXPECT_NEAR(odometry.twist.twist.linear.x, v_C_expected.x(), 1e-9);
  EXPECT_NEAR(odometry.twist.twist.linear.y, v_C_expected.y(), 1e-9);
  EXPECT_NEAR(odometry.twist.twist.linear.z, v_C_expected.z(), 1e-9);
  EXPECT_EQ(odometry.twist.twist.angular.y, omega_C.y());
  // The pose is the state's.
  EXPECT_EQ(odometry.pose.pose.position.x, x.r_W_C.x());
  EXPECT_NEAR(std::abs(odometry.pose.pose.orientation.w), std::abs(x.q_W_C.w()), 1e-15);
  EXPECT_STREQ(odometry.header.frame_id, "map");
  EXPECT_STREQ(odometry.child_frame_id, "camera");
}

TEST(DdsConversions, InertialOdometryTwistCovarianceIsTheVelocityVarianceInTheCamera) {
  NavState x;
  // C = W, and I is W turned by +90° about x: I's (x, y, z) are W's and C's (x, −z, y).
  x.q_I_W = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));
  Vector18d variance = Vector18d::Zero();
  variance.segment<6>(kIdxR) << 1, 2, 3, 4, 5, 6;
  variance.segment<3>(kIdxV) << 10, 20, 30;
  const msg::Odometry odometry =
      makeInertialOdometry(0, "map", "camera", SE3d(), x, variance, Eigen::Vector3d::Zero(), SE3d());
  EXPECT_NEAR(odometry.twist.covariance[0], 10.0, 1e-12);   // C x = I x
  EXPECT_NEAR(odometry.twist.covariance[7], 30.0, 1e-12);   // C y = I z
  EXPECT_NEAR(odometry.twist.covariance[14], 20.0, 1e-12);  // C z = −I y
  EXPECT_NEAR(odometry.twist.covariance[1], 0.0, 1e-12);
  for (int i = 3; i < 6; ++i) EXPECT_EQ(odometry.twist.covariance[7 * i], 0.0) << "angular: unknown";
  for (int i = 0; i < 6; ++i) EXPECT_EQ(odometry.pose.covariance[7 * i], 1.0 + i);
}

TEST(DdsConversions, InertialOdometryInTheOdomFrameIsTheMapOdometryMovedByMapToOdom) {
  // After loop closures have moved the map by T_W_O, odometry in O: the pose is T_O_W·T_W_C, the twist (in C) is
  // unchanged, and the pose covariance turns with R_O_W (position and rotation blocks alike).
  NavState x;
  x.q_W_C = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()));
  x.r_W_C = Eigen::Vector3d(1.0, -2.0, 0.5);
  x.q_I_W = Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  x.v_I_S = Eigen::Vector3d(0.3, 0.1, -0.2);
  const SE3d T_W_O(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())),
                   Eigen::Vector3d(0.05, -0.02, 0.01));
  Vector18d variance = Vector18d::Zero();
  variance.segment<6>(kIdxR) << 1, 2, 3, 4, 5, 6;
  const Eigen::Vector3d omega_C(0.1, -0.2, 0.3);
  const msg::Odometry in_map = makeInertialOdometry(0, "map", "camera", SE3d(), x, variance, omega_C, SE3d());
  const msg::Odometry in_odom =
      makeInertialOdometry(0, "odom", "camera", T_W_O.inverse(), x, variance, omega_C, SE3d());
  EXPECT_STREQ(in_odom.header.frame_id, "odom");
  const Eigen::Vector3d r_O_C = T_W_O.inverse() * x.r_W_C;
  EXPECT_NEAR(in_odom.pose.pose.position.x, r_O_C.x(), 1e-12);
  EXPECT_NEAR(in_odom.pose.pose.position.y, r_O_C.y(), 1e-12);
  EXPECT_NEAR(in_odom.pose.pose.position.z, r_O_C.z(), 1e-12);
  const Eigen::Quaterniond q_O_C = T_W_O.quaternion().conjugate() * x.q_W_C;
  const Eigen::Quaterniond q(in_odom.pose.pose.orientation.w, in_odom.pose.pose.orientation.x,
                             in_odom.pose.pose.orientation.y, in_odom.pose.pose.orientation.z);
  EXPECT_NEAR(std::abs(q.dot(q_O_C)), 1.0, 1e-12);
  EXPECT_NEAR(in_odom.twist.twist.linear.x, in_map.twist.twist.linear.x, 1e-12);
  EXPECT_NEAR(in_odom.twist.twist.linear.y, in_map.twist.twist.linear.y, 1e-12);
  EXPECT_NEAR(in_odom.twist.twist.linear.z, in_map.twist.twist.linear.z, 1e-12);
  // R_O_W turns W's x onto O's −y and W's y onto O's x: the x and y variances swap, in both blocks.
  EXPECT_NEAR(in_odom.pose.covariance[0], 2.0, 1e-12);
  EXPECT_NEAR(in_odom.pose.covariance[7], 1.0, 1e-12);
  EXPECT_NEAR(in_odom.pose.covariance[14], 3.0, 1e-12);
  EXPECT_NEAR(in_odom.pose.covariance[21], 5.0, 1e-12);
  EXPECT_NEAR(in_odom.pose.covariance[28], 4.0, 1e-12);
  EXPECT_NEAR(in_odom.pose.covariance[35], 6.0, 1e-12);
  for (int i = 0; i < 36; ++i) {
    if (i % 7 != 0) {
      EXPECT_NEAR(in_odom.pose.covariance[i], 0.0, 1e-12) << i;
    }
  }
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
