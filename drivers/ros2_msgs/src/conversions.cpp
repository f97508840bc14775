#include "vifusion/ros2_msgs/conversions.hpp"

#include <array>

namespace vifusion::ros2_msgs {
namespace {

/// Row-major 3×3 indices of the diagonal.
constexpr std::array<std::size_t, 3> kDiagonal3x3{0, 4, 8};
/// Plumb-bob coefficients of a camera without distortion: k1, k2, p1, p2, k3 all zero.
constexpr std::array<double, 5> kNoPlumbBobDistortion{};

Imu::Covariance diagonalCovariance(double variance) {
  Imu::Covariance covariance{};
  for (std::size_t index : kDiagonal3x3) covariance[index] = variance;
  return covariance;
}

std::span<const std::uint8_t> bytesOf(const void* data, std::size_t byte_count) {
  return {static_cast<const std::uint8_t*>(data), byte_count};
}

}  // namespace

Imu imuFromSample(const ImuSample& sample, std::string_view frame_id, const ImuVariances& variances) {
  Imu imu;
  imu.header = makeHeader(sample.t_ns, frame_id);
  imu.angular_velocity = Vector3{sample.gyro_rad_s.x(), sample.gyro_rad_s.y(), sample.gyro_rad_s.z()};
  imu.linear_acceleration = Vector3{sample.accel_mps2.x(), sample.accel_mps2.y(), sample.accel_mps2.z()};
  imu.angular_velocity_covariance = diagonalCovariance(variances.gyro_rad2_s2);
  imu.linear_acceleration_covariance = diagonalCovariance(variances.accel_m2_s4);
  return imu;
}

ImuSample sampleFromImu(const Imu& imu) {
  ImuSample sample;
  sample.t_ns = imu.header.stamp.toNs();
  sample.gyro_rad_s = Eigen::Vector3d(imu.angular_velocity.x, imu.angular_velocity.y, imu.angular_velocity.z);
  sample.accel_mps2 = Eigen::Vector3d(imu.linear_acceleration.x, imu.linear_acceleration.y, imu.linear_acceleration.z);
  return sample;
}

Transform transformFromSe3(const SE3d& T_a_b) {
  const Eigen::Vector3d& t = T_a_b.translation();
  const Eigen::Quaterniond& q = T_a_b.quaternion();
  return Transform{Vector3{t.x(), t.y(), t.z()}, Quaternion{q.x(), q.y(), q.z(), q.w()}};
}

SE3d se3FromTransform(const Transform& transform) {
  const Quaternion& q = transform.rotation;
  const Vector3& t = transform.translation;
  // Eigen's constructor takes w first.
  return SE3d(Eigen::Quaterniond(q.w, q.x, q.y, q.z), Eigen::Vector3d(t.x, t.y, t.z));
}

CameraInfo cameraInfoFromPinhole(const PinholeCamera& camera, const Header& header) {
  CameraInfo info;
  info.header = header;
  info.width = static_cast<std::uint32_t>(camera.width);
  info.height = static_cast<std::uint32_t>(camera.height);
  info.distortion_model = distortion_models::kPlumbBob;
  info.setDistortion(kNoPlumbBobDistortion);
  info.k = {camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0};
  info.r = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info.p = {camera.fx, 0.0, camera.cx, 0.0, 0.0, camera.fy, camera.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
  return info;
}

ImageView depthImageView(const Header& header, const Image<std::uint16_t>& depth) {
  ImageView view;
  view.header = header;
  view.width = static_cast<std::uint32_t>(depth.width());
  view.height = static_cast<std::uint32_t>(depth.height());
  view.encoding = image_encodings::kDepth16;
  view.step = view.width * static_cast<std::uint32_t>(sizeof(std::uint16_t));
  view.data = bytesOf(depth.data(), depth.pixelCount() * sizeof(std::uint16_t));
  return view;
}

ImageView rgbImageView(const Header& header, const Image<Rgb8>& rgb) {
  ImageView view;
  view.header = header;
  view.width = static_cast<std::uint32_t>(rgb.width());
  view.height = static_cast<std::uint32_t>(rgb.height());
  view.encoding = image_encodings::kRgb8;
  view.step = view.width * static_cast<std::uint32_t>(sizeof(Rgb8));
  view.data = bytesOf(rgb.data(), rgb.pixelCount() * sizeof(Rgb8));
  return view;
}

}  // namespace vifusion::ros2_msgs
