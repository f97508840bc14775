#pragma once
// Between vifusion's own types (pipeline/core) and the ROS 2 messages: IMU samples, rigid transforms,
// pinhole intrinsics and images. All return views into the inputs where a message field is a view, so
// the inputs must outlive the message's serialisation.

#include <cstdint>
#include <string_view>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/ros2_msgs/geometry_tf.hpp"
#include "vifusion/ros2_msgs/sensor_msgs.hpp"
#include "vifusion/ros2_msgs/time_header.hpp"

namespace vifusion::ros2_msgs {

/// Diagonal variances of one IMU sample's noise; 0 leaves the covariance all zeros ("unknown").
struct ImuVariances {
  double gyro_rad2_s2 = 0.0;  ///< σ² of one angular-rate reading per axis [rad²/s²], >= 0
  double accel_m2_s4 = 0.0;   ///< σ² of one specific-force reading per axis [m²/s⁴], >= 0
};

/// An Imu message of `sample` in frame `frame_id` (the IMU sensor frame S): stamp sample.t_ns, no
/// orientation estimate (orientation_covariance[0] = −1), the variances on the rate covariances' diagonals.
Imu imuFromSample(const ImuSample& sample, std::string_view frame_id, const ImuVariances& variances = {});
/// The sample an Imu message holds (its orientation and covariances are not part of an ImuSample).
ImuSample sampleFromImu(const Imu& imu);

/// T_a_b as a geometry_msgs/Transform (translation [m], rotation x, y, z, w).
Transform transformFromSe3(const SE3d& T_a_b);
/// The SE3d of a Transform; the quaternion is normalised (SE3d's constructor), so a reader's rounding
/// does not leak into chained transforms.
SE3d se3FromTransform(const Transform& transform);

/// CameraInfo of an undistorted pinhole camera: plumb_bob with five zero coefficients (what ROS tools
/// expect of a rectified camera), K from fx, fy, cx, cy, R = identity, P = [K | 0], no binning, full ROI.
CameraInfo cameraInfoFromPinhole(const PinholeCamera& camera, const Header& header);

/// A 16UC1 ImageView of a tightly packed depth image (step = 2·width), pixels not copied.
ImageView depthImageView(const Header& header, const Image<std::uint16_t>& depth);
/// An rgb8 ImageView of a tightly packed colour image (step = 3·width), pixels not copied.
ImageView rgbImageView(const Header& header, const Image<Rgb8>& rgb);

}  // namespace vifusion::ros2_msgs
