#include "vifusion/dds/conversions.hpp"

#include <array>
#include <cstddef>
#include <limits>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::dds {
namespace {

// Messages hold `char*` and non-const buffers because Cyclone's C structs serve reading and writing
// alike; on the writing side Cyclone only reads them, so pointing them at const storage is sound.
char* borrow(const char* text) { return const_cast<char*>(text); }

msg::Vector3 toVector3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

/// The diagonal of J·Σ·Jᵀ for the 3×3 block of δx starting at `index`; all −1 when that block is all
/// zero (held: conversions.hpp).
void copyDiagonal(const Eigen::Matrix3d& J, const Matrix18d& covariance, int index, double (&out)[3]) {
  const Eigen::Matrix3d block = covariance.block<3, 3>(index, index);
  const bool held = (block.array() == 0.0).all();
  const Eigen::Matrix3d mapped = J * block * J.transpose();
  for (int i = 0; i < 3; ++i) out[i] = held ? -1.0 : mapped(i, i);
}

void copyRowMajor(const Matrix6d& covariance, double (&out)[36]) {
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) out[6 * r + c] = covariance(r, c);
  }
}

constexpr std::uint8_t kFloat32 = sensor_msgs_msg_PointField_Constants_FLOAT32;

const std::array<msg::PointField, 9> kMapPointFields = {{
    {borrow("x"), offsetof(MapPoint, x), kFloat32, 1},
    {borrow("y"), offsetof(MapPoint, y), kFloat32, 1},
    {borrow("z"), offsetof(MapPoint, z), kFloat32, 1},
    {borrow("rgb"), offsetof(MapPoint, rgb), kFloat32, 1},
    {borrow("normal_x"), offsetof(MapPoint, normal_x), kFloat32, 1},
    {borrow("normal_y"), offsetof(MapPoint, normal_y), kFloat32, 1},
    {borrow("normal_z"), offsetof(MapPoint, normal_z), kFloat32, 1},
    {borrow("radius"), offsetof(MapPoint, radius), kFloat32, 1},
    {borrow("confidence"), offsetof(MapPoint, confidence), kFloat32, 1},
}};

}  // namespace

msg::Time toTime(std::int64_t t_ns) {
  std::int64_t sec = t_ns / kNsPerSecond;
  std::int64_t nanosec = t_ns % kNsPerSecond;
  if (nanosec < 0) {  // C++ division truncates toward zero; Time wants the floor
    --sec;
    nanosec += kNsPerSecond;
  }
  if (sec < std::numeric_limits<std::int32_t>::min() || sec > std::numeric_limits<std::int32_t>::max()) {
    throw Error("time " + std::to_string(t_ns) + " ns does not fit builtin_interfaces/Time (int32 seconds)");
  }
  return {static_cast<std::int32_t>(sec), static_cast<std::uint32_t>(nanosec)};
}

std::int64_t toNs(const msg::Time& time) {
  return static_cast<std::int64_t>(time.sec) * kNsPerSecond + static_cast<std::int64_t>(time.nanosec);
}

msg::Header makeHeader(std::int64_t t_ns, const char* frame_id) { return {toTime(t_ns), borrow(frame_id)}; }

msg::Pose toPose(const SE3d& T_a_b) {
  const Eigen::Vector3d& t = T_a_b.translation();
  const Eigen::Quaterniond& q = T_a_b.quaternion();
  return {{t.x(), t.y(), t.z()}, {q.x(), q.y(), q.z(), q.w()}};
}

msg::Transform toTransform(const SE3d& T_a_b) {
  const Eigen::Quaterniond& q = T_a_b.quaternion();
  return {toVector3(T_a_b.translation()), {q.x(), q.y(), q.z(), q.w()}};
}

msg::PoseStamped makePoseStamped(std::int64_t t_ns, const char* world_frame_id, const SE3d& T_W_C) {
  return {makeHeader(t_ns, world_frame_id), toPose(T_W_C)};
}

msg::TransformStamped makeTransformStamped(std::int64_t t_ns, const char* parent_frame_id, const char* child_frame_id,
                                           const SE3d& T_parent_child) {
  return {makeHeader(t_ns, parent_frame_id), borrow(child_frame_id), toTransform(T_parent_child)};
}

msg::TFMessage makeTfMessage(std::span<msg::TransformStamped> transforms) {
  msg::TFMessage message{};
  message.transforms._maximum = message.transforms._length = static_cast<std::uint32_t>(transforms.size());
  message.transforms._buffer = transforms.data();
  message.transforms._release = false;
  return message;
}

msg::Odometry makeOdometry(std::int64_t t_ns, const char* world_frame_id, const char* camera_frame_id,
                           const SE3d& T_W_C, const Eigen::Vector3d& v_W_mps, const Eigen::Vector3d& omega_C_radps,
                           const Matrix6d& pose_covariance, const Matrix6d& twist_covariance) {
  msg::Odometry message{};
  message.header = makeHeader(t_ns, world_frame_id);
  message.child_frame_id = borrow(camera_frame_id);
  message.pose.pose = toPose(T_W_C);
  copyRowMajor(pose_covariance, message.pose.covariance);
  const Eigen::Vector3d v_C_mps = T_W_C.rotationMatrix().transpose() * v_W_mps;
  message.twist.twist = {toVector3(v_C_mps), toVector3(omega_C_radps)};
  copyRowMajor(twist_covariance, message.twist.covariance);
  return message;
}

msg::ImuState makeImuState(std::int64_t t_ns, const char* world_frame_id, const NavState& x,
                           const Matrix18d& covariance) {
  const Eigen::Matrix3d R_W_I = x.q_I_W.conjugate().toRotationMatrix();
  const Eigen::Vector3d down_I(0.0, 0.0, -1.0);
  const Eigen::Matrix3d J_gravity_dg = R_W_I * hat(down_I);
  msg::ImuState message{};
  message.header = makeHeader(t_ns, world_frame_id);
  message.velocity = toVector3(R_W_I * x.v_I_S);
  message.gyro_bias = toVector3(x.b_g);
  message.accel_bias = toVector3(x.b_a);
  message.gravity_direction = toVector3(R_W_I * down_I);
  copyDiagonal(R_W_I, covariance, kIdxV, message.velocity_covariance);
  copyDiagonal(Eigen::Matrix3d::Identity(), covariance, kIdxBg, message.gyro_bias_covariance);
  copyDiagonal(Eigen::Matrix3d::Identity(), covariance, kIdxBa, message.accel_bias_covariance);
  copyDiagonal(J_gravity_dg, covariance, kIdxG, message.gravity_direction_covariance);
  return message;
}

msg::ImuState makeImuStateFromVariances(std::int64_t t_ns, const char* world_frame_id, const NavState& x,
                                        const Vector18d& variance) {
  const Matrix18d covariance = variance.asDiagonal();  // 2.6 KB on the stack, no heap
  return makeImuState(t_ns, world_frame_id, x, covariance);
}

Matrix6d odometryPoseCovariance(const Vector18d& variance) {
  static_assert(kIdxAlpha == kIdxR + 3, "δr and δα are adjacent in δx, as x, y, z and rx, ry, rz in ROS");
  Matrix6d covariance = Matrix6d::Zero();
  covariance.diagonal() = variance.segment<6>(kIdxR);
  return covariance;
}

Matrix6d rotatePoseCovariance(const Matrix6d& covariance, const Eigen::Matrix3d& R_new_old) {
  Matrix6d R = Matrix6d::Zero();
  R.topLeftCorner<3, 3>() = R_new_old;
  R.bottomRightCorner<3, 3>() = R_new_old;
  return R * covariance * R.transpose();
}

msg::Odometry makeInertialOdometry(std::int64_t t_ns, const char* odom_frame_id, const char* camera_frame_id,
                                   const SE3d& T_O_W, const NavState& x, const Vector18d& variance,
                                   const Eigen::Vector3d& omega_C_radps, const SE3d& T_S_C) {
  const SE3d T_W_C(x.q_W_C, x.r_W_C);
  const Eigen::Matrix3d R_W_C = T_W_C.rotationMatrix();
  const Eigen::Matrix3d R_W_I = x.q_I_W.conjugate().toRotationMatrix();
  const Eigen::Vector3d p_C_S = T_S_C.inverse().translation();  // S's origin in C [m]
  // r_W_S = r_W_C + R_W_C·p_C_S, so v_W_S = v_W_C + R_W_C·(ω_C × p_C_S).
  const Eigen::Vector3d v_W_C = R_W_I * x.v_I_S - R_W_C * omega_C_radps.cross(p_C_S);
  const Eigen::Matrix3d R_C_I = R_W_C.transpose() * R_W_I;
  Matrix6d twist_covariance = Matrix6d::Zero();
  twist_covariance.topLeftCorner<3, 3>() = R_C_I * variance.segment<3>(kIdxV).asDiagonal() * R_C_I.transpose();
  // makeOdometry expresses the velocity in C: the same from W or O.
  return makeOdometry(t_ns, odom_frame_id, camera_frame_id, T_O_W * T_W_C, T_O_W.rotationMatrix() * v_W_C,
                      omega_C_radps, rotatePoseCovariance(odometryPoseCovariance(variance), T_O_W.rotationMatrix()),
                      twist_covariance);
}

std::span<const msg::PointField> mapPointFields() { return kMapPointFields; }

msg::PointCloud2 makePointCloud2(std::int64_t t_ns, const char* world_frame_id, std::span<const MapPoint> points) {
  if (points.size_bytes() > std::numeric_limits<std::uint32_t>::max()) {
    throw Error("map chunk of " + std::to_string(points.size()) + " points exceeds PointCloud2's 4 GiB data limit");
  }
  msg::PointCloud2 message{};
  message.header = makeHeader(t_ns, world_frame_id);
  message.height = 1;
  message.width = static_cast<std::uint32_t>(points.size());
  message.fields._maximum = message.fields._length = static_cast<std::uint32_t>(kMapPointFields.size());
  message.fields._buffer = const_cast<msg::PointField*>(kMapPointFields.data());
  message.fields._release = false;
  message.is_bigendian = false;
  message.point_step = sizeof(MapPoint);
  message.row_step = static_cast<std::uint32_t>(points.size_bytes());
  message.data._maximum = message.data._length = static_cast<std::uint32_t>(points.size_bytes());
  message.data._buffer = reinterpret_cast<std::uint8_t*>(const_cast<MapPoint*>(points.data()));
  message.data._release = false;
  message.is_dense = true;
  return message;
}

}  // namespace vifusion::dds
