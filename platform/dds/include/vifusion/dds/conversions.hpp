#pragma once
// Messages from vifusion's types: int64_t ns times, SE3d transforms T_a_b, the estimator state.
//
// Every make* returns a message that BORROWS the frame-id strings and point buffers passed in
// (messages.hpp): keep them alive until Writer::write returns. Nothing here allocates.
//
// Stamps are copied as given: convert CLOCK_MONOTONIC to the clock ROS 2 consumers expect (system
// time) before calling (platform.md §2.3).

#include <bit>
#include <cstdint>
#include <span>

#include "vifusion/core/se3.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/dds/messages.hpp"

namespace vifusion::dds {

/// builtin_interfaces/Time of t_ns: sec = ⌊t_ns / 1 s⌋, nanosec = the rest in [0, 10⁹) (also for
/// negative t_ns). Throws vifusion::Error when sec does not fit in int32 (after 2038-01-19 on the
/// Unix epoch).
msg::Time toTime(std::int64_t t_ns);
/// Inverse of toTime [ns].
std::int64_t toNs(const msg::Time& time);

msg::Header makeHeader(std::int64_t t_ns, const char* frame_id);
msg::Pose toPose(const SE3d& T_a_b);
msg::Transform toTransform(const SE3d& T_a_b);

/// geometry_msgs/PoseStamped: the pose of C in W (T_W_C), header.frame_id names W.
msg::PoseStamped makePoseStamped(std::int64_t t_ns, const char* world_frame_id, const SE3d& T_W_C);

/// geometry_msgs/TransformStamped: T_parent_child, as tf2 expects (it maps child points to parent).
msg::TransformStamped makeTransformStamped(std::int64_t t_ns, const char* parent_frame_id, const char* child_frame_id,
                                           const SE3d& T_parent_child);

/// tf2_msgs/TFMessage over `transforms` (borrowed).
msg::TFMessage makeTfMessage(std::span<msg::TransformStamped> transforms);

/// nav_msgs/Odometry of camera C in world W, following the message's contract: the pose in
/// header.frame_id (W), the twist in child_frame_id (C).
///   v_W_mps            velocity of C's origin, expressed in W [m/s]; rotated into C here
///   omega_C_radps      angular velocity of C, expressed in C [rad/s]
///   pose_covariance    6×6 over [δr_W, δα_W]: position in W [m²] and rotation about W's fixed axes
///                      [rad²] — the state's (δr, δα) block as is (state.hpp perturbs q_W_C on the left)
///   twist_covariance   6×6 over C's (linear [m²/s²], angular [rad²/s²]); zero means unknown
msg::Odometry makeOdometry(std::int64_t t_ns, const char* world_frame_id, const char* camera_frame_id,
                           const SE3d& T_W_C, const Eigen::Vector3d& v_W_mps, const Eigen::Vector3d& omega_C_radps,
                           const Matrix6d& pose_covariance, const Matrix6d& twist_covariance);

/// vifusion_msgs/ImuState of `x` with the 18×18 `covariance` of its δx (state.hpp), everything
/// expressed in W (header.frame_id) except the biases, which live in the IMU frame S:
///   velocity = R_W_I · v_I_S, gravity_direction = R_W_I · (0, 0, −1);
/// the covariance diagonals are those of the same linear maps applied to the δv and δg blocks
/// (δg rotates q_I_W on the left in I, so ∂gravity_direction/∂δg = R_W_I · [(0, 0, −1)]×).
/// A block of δx whose covariance is all zero is held, not estimated (gyro mode: δv, δb_a, δg): its
/// three message variances are −1 (vifusion_msgs.idl), never a 0 that would read as certainty.
msg::ImuState makeImuState(std::int64_t t_ns, const char* world_frame_id, const NavState& x,
                           const Matrix18d& covariance);

/// The same from the estimator's 18 marginal variances of δx (slam::FrameResult::state_variance; 0 =
/// held), i.e. with the covariance taken diagonal: the estimator reports no correlations, so the W-axis
/// variances of velocity and gravity direction are Σ_j J_ij² σ²_j over the I-axis ones.
msg::ImuState makeImuStateFromVariances(std::int64_t t_ns, const char* world_frame_id, const NavState& x,
                                        const Vector18d& variance);

/// nav_msgs/Odometry's pose covariance from the estimator's marginal variances of δx. ROS orders it
/// [x, y, z, rx, ry, rz], 6×6 row-major, position in header.frame_id (W) and rotation about W's fixed
/// axes; the state's (δr, δα) are exactly that (δr in W, δα a left perturbation of q_W_C: a rotation
/// vector in W), so the diagonal is variance[kIdxR .. kIdxAlpha + 2] as is. Off the diagonal: 0, because
/// the estimator reports marginal variances only — the correlations exist but are not published.
Matrix6d odometryPoseCovariance(const Vector18d& variance);

/// A pose covariance in ROS order (position, then rotation vector, both in the header frame) re-expressed in a
/// frame turned by R_new_old from the old one: blockdiag(R, R)·Σ·blockdiag(R, R)ᵀ.
Matrix6d rotatePoseCovariance(const Matrix6d& covariance, const Eigen::Matrix3d& R_new_old);

/// nav_msgs/Odometry of camera C from the estimator's state, for modes that estimate velocity (rgbdi), in the
/// frame O (header.frame_id: the odometry frame of REP-105) given by T_O_W (identity: the map frame W itself):
///  - pose T_O_C = T_O_W·(q_W_C, r_W_C), covariance odometryPoseCovariance(variance) turned by R_O_W;
///  - twist.linear: the velocity of C's origin, v_W_C = R_W_I·v_I_S − R_W_C·(ω_C × p_C_S), with the
///    lever arm p_C_S (S's origin in C, from T_S_C) turned by the angular velocity `omega_C_radps`
///    (expressed in C; the state has none, the caller supplies it), then expressed in C as the message
///    wants; twist.angular = omega_C_radps;
///  - twist covariance: the linear block is the δv variances (I axes) rotated into C,
///    R_C_I·diag(σ²_v)·R_I_C — a full 3×3 block, built on the same no-correlation assumption as above;
///    the lever-arm term's and the rotations' own uncertainty are left out (second order). The angular
///    block is 0 = unknown: the estimator does not estimate angular velocity.
msg::Odometry makeInertialOdometry(std::int64_t t_ns, const char* odom_frame_id, const char* camera_frame_id,
                                   const SE3d& T_O_W, const NavState& x, const Vector18d& variance,
                                   const Eigen::Vector3d& omega_C_radps, const SE3d& T_S_C);

/// One point of a map chunk: nine little-endian float32 fields, 36 bytes (mapPointFields()).
struct MapPoint {
  float x = 0, y = 0, z = 0;                       ///< surfel position in the header frame (W) [m]
  std::uint32_t rgb = 0;                           ///< PCL's packed colour 0x00RRGGBB, sent as a FLOAT32 field's bits
  float normal_x = 0, normal_y = 0, normal_z = 0;  ///< unit surface normal in W
  float radius = 0;                                ///< surfel radius [m]
  float confidence = 0;                            ///< fusion confidence (ElasticFusion's c) [1]

  /// PCL/RViz colour packing of 8-bit red, green and blue.
  static constexpr std::uint32_t packRgb(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    return static_cast<std::uint32_t>(r) << 16 | static_cast<std::uint32_t>(g) << 8 | b;
  }
};
static_assert(sizeof(MapPoint) == 36, "MapPoint is sent as the PointCloud2 byte layout of mapPointFields()");
// The message says is_bigendian = false and the points go out as they lie in memory.
static_assert(std::endian::native == std::endian::little, "map points are published in host byte order");

/// The PointField list of MapPoint: x, y, z, rgb, normal_x, normal_y, normal_z, radius, confidence,
/// all FLOAT32 with count 1 at offsets 0, 4, …, 32 (static storage).
std::span<const msg::PointField> mapPointFields();

/// sensor_msgs/PointCloud2 of a map chunk: an unorganised cloud (height 1, width = points), dense (no
/// invalid points), little-endian, point_step 36. `points` is borrowed as the data buffer.
msg::PointCloud2 makePointCloud2(std::int64_t t_ns, const char* world_frame_id, std::span<const MapPoint> points);

}  // namespace vifusion::dds
