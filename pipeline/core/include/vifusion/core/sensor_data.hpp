#pragma once
// What every sensor source produces (live driver, dataset reader, simulator): timestamped RGB-D
// frames and IMU samples, plus the simulator's ground truth. Times are int64 ns on the host's
// CLOCK_MONOTONIC after clock mapping (datasets: their own time base, monotonic).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

#include "vifusion/core/image.hpp"

namespace vifusion {

/// One IMU reading in the IMU sensor frame S, as measured (biases and noise included).
struct ImuSample {
  int64_t t_ns = 0;
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();  ///< angular rate of S w.r.t. inertial space, in S [rad/s]
  Eigen::Vector3d accel_mps2 = Eigen::Vector3d::Zero();  ///< specific force in S [m/s²] (≈ +9.81 up at rest)
};

/// How a live camera timed a frame: what recordings keep and the timestamp-sync check compares. All zero
/// where the source has no device clock (datasets, the simulator).
struct FrameTiming {
  std::uint32_t device_frame_number = 0;    ///< the camera's own frame counter (ZR300: DS4 metadata row)
  std::int64_t kernel_mid_exposure_ns = 0;  ///< the kernel's buffer time moved to mid-exposure, CLOCK_MONOTONIC
  std::int64_t device_event_ns = 0;         ///< the IMU microcontroller's event for the frame, mapped to host; 0: none
  std::int64_t device_event_clock_ns = 0;   ///< that event on the device clock (unwrapped ticks as ns); 0: none
  bool stamped_by_device_event = false;     ///< t_ns is device_event_ns (otherwise kernel_mid_exposure_ns)
};

/// One depth + colour frame. Depth is kept in the sensor's units so that nothing is
/// converted on the host; the GPU applies depth_scale_m.
struct RgbdFrame {
  int64_t t_ns = 0;   ///< mid-exposure time of the frame
  int64_t index = 0;  ///< position in the sequence (0, 1, 2, …)
  /// Raw depth, 0 = invalid: in the colour camera's pixels, or the depth camera's where the rig calibration has
  /// one (RigCalibration::depth_camera; preprocessing registers it to colour).
  Image<uint16_t> depth;
  double depth_scale_m = 0;  ///< metres per depth unit (0.001 mm sensors, 1/5000 TUM and ICL-NUIM)
  Image<Rgb8> rgb;           ///< colour, bytes R, G, B
  FrameTiming timing;        ///< live sources and their recordings: the device's view of the frame's time
};

/// The simulator's true state at an IMU sample: pose of S in the dataset world W, velocity, biases.
struct GroundTruthState {
  int64_t t_ns = 0;
  Eigen::Vector3d p_W_S = Eigen::Vector3d::Zero();            ///< position of S in W [m]
  Eigen::Quaterniond q_W_S = Eigen::Quaterniond::Identity();  ///< orientation of S in W (Hamilton)
  Eigen::Vector3d v_W_S = Eigen::Vector3d::Zero();            ///< velocity of S in W [m/s]
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();              ///< gyroscope bias [rad/s]
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();              ///< accelerometer bias [m/s²]
};

}  // namespace vifusion
