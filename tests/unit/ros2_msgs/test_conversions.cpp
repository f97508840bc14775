// vifusion's own types to and from the messages.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdint>

#include "vifusion/core/time.hpp"
#include "vifusion/ros2_msgs/conversions.hpp"

namespace vifusion::ros2_msgs {
namespace {

TEST(Conversions, ImuSampleBecomesAnImuWithoutOrientationAndBack) {
  ImuSample sample;
  sample.t_ns = 12 * kNsPerSecond + 345;
  sample.gyro_rad_s = Eigen::Vector3d(0.1, -0.2, 0.3);
  sample.accel_mps2 = Eigen::Vector3d(0.5, 9.81, -0.25);
  const Imu imu = imuFromSample(sample, "imu", ImuVariances{2.88e-4, 6.4e-3});
  EXPECT_EQ(imu.header.stamp, (Time{12, 345}));
  EXPECT_EQ(imu.header.frame_id, "imu");
  EXPECT_EQ(imu.orientation_covariance[0], kCovarianceNoEstimate);
  EXPECT_EQ(imu.angular_velocity.z, 0.3);
  EXPECT_EQ(imu.linear_acceleration.y, 9.81);
  EXPECT_EQ(imu.angular_velocity_covariance, (Imu::Covariance{2.88e-4, 0, 0, 0, 2.88e-4, 0, 0, 0, 2.88e-4}));
  EXPECT_EQ(imu.linear_acceleration_covariance[4], 6.4e-3);
  EXPECT_EQ(imu.linear_acceleration_covariance[1], 0.0);

  const ImuSample back = sampleFromImu(imu);
  EXPECT_EQ(back.t_ns, sample.t_ns);
  EXPECT_EQ(back.gyro_rad_s, sample.gyro_rad_s);
  EXPECT_EQ(back.accel_mps2, sample.accel_mps2);
}

TEST(Conversions, UnknownVariancesLeaveTheCovariancesZero) {
  const Imu imu = imuFromSample(ImuSample{}, "imu");
  EXPECT_EQ(imu.angular_velocity_covariance, Imu::Covariance{});
  EXPECT_EQ(imu.linear_acceleration_covariance, Imu::Covariance{});
}

TEST(Conversions, Se3RoundTripsThroughTransformInRosOrder) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const SE3d T_imu_depth(q, Eigen::Vector3d(0.02, -0.004, 0.01));
  const Transform transform = transformFromSe3(T_imu_depth);
  EXPECT_EQ(transform.rotation.w, q.w());  // not shuffled into Eigen's (w, x, y, z) constructor order
  EXPECT_EQ(transform.rotation.x, q.x());
  EXPECT_EQ(transform.translation.y, -0.004);
  const SE3d back = se3FromTransform(transform);
  const Eigen::Vector3d p(1.0, 2.0, 3.0);
  EXPECT_LT((back * p - T_imu_depth * p).norm(), 1e-15);
}

TEST(Conversions, PinholeBecomesAnUndistortedCameraInfo) {
  const PinholeCamera camera = PinholeCamera::create(640, 480, 617.25, 617.5, 318.875, 243.125);
  const CameraInfo info = cameraInfoFromPinhole(camera, makeHeader(kNsPerSecond, "depth"));
  EXPECT_EQ(info.width, 640u);
  EXPECT_EQ(info.height, 480u);
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  ASSERT_EQ(info.d_count, 5u);
  EXPECT_EQ(info.k, (std::array<double, 9>{617.25, 0, 318.875, 0, 617.5, 243.125, 0, 0, 1}));
  EXPECT_EQ(info.p[2], 318.875);
  EXPECT_EQ(info.p[6], 243.125);
  EXPECT_EQ(info.p[10], 1.0);
  EXPECT_EQ(info.r[4], 1.0);
}

TEST(Conversions, ImageViewsPointAtThePixelsWithoutCopying) {
  Image<std::uint16_t> depth(4, 3, 1500);
  depth(3, 2) = 0x1234;
  const ImageView depth_view = depthImageView(makeHeader(0, "depth"), depth);
  EXPECT_EQ(depth_view.encoding, "16UC1");
  EXPECT_EQ(depth_view.step, 8u);
  ASSERT_EQ(depth_view.data.size(), 24u);
  EXPECT_EQ(static_cast<const void*>(depth_view.data.data()), static_cast<const void*>(depth.data()));
  EXPECT_EQ(depth_view.data[22], 0x34);  // little-endian uint16: low byte first
  EXPECT_EQ(depth_view.data[23], 0x12);

  Image<Rgb8> rgb(2, 2, Rgb8{1, 2, 3});
  const ImageView rgb_view = rgbImageView(makeHeader(0, "colour"), rgb);
  EXPECT_EQ(rgb_view.encoding, "rgb8");
  EXPECT_EQ(rgb_view.step, 6u);
  EXPECT_EQ(rgb_view.data.size(), 12u);
  EXPECT_EQ(rgb_view.data[5], 3);
}

}  // namespace
}  // namespace vifusion::ros2_msgs
