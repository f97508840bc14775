#pragma once
// The tracking state of each frame: what a robot may do with its pose, and what the map did with the frame.
//
//  - kTracked: the dense RGB-D terms registered the frame to the map. rgbd: DenseTracker::track passed its
//    tests (≥ 6 inliers at every level, a regular system, an innovation below max_motion_innovation_m and
//    the health test: ≥ min_inlier_fraction of the pixels that land on the model are ICP inliers), and Slam's:
//    the camera moved no faster than max_speed_mps since the reference frame. rgbdi
//    and gyro: the two-state estimator used them (usable at every level, the same health test, and not
//    refused by the gate on vision_chi2, the χ² by which they pull the state from the IMU and the prior).
//    The pose is registered to the map, so the frame is fused at full weight.
//  - kImuCarried (inertial modes only): the dense terms were unusable, unhealthy or refused, but this
//    frame's IMU samples were used: the state is the IMU prediction held by the marginalisation prior, and
//    its covariance grows with the dead reckoning. The frame is fused at the estimator's pose with every
//    measurement weighted by the share of its variance the pose leaves it, σ_z²/(σ_z² + σ_r² + z²σ_θ²)
//    (poseWeight in shaders/include/map/fusion_params.glsl): the model grows into the new view, so the
//    dense terms can take over again on the next frames, while a less certain pose shapes the map less.
//    Only while ImuCarryOptions' bound holds; beyond it the frame is kLost.
//  - kLost: no pose the map may trust: rgbd tracking failed (the pose is a guess), an IMU-carried pose is
//    beyond the bound, or the IMU samples were refused and the RGB-D fallback failed too. Not fused.
// Each frame's state follows from its own evidence: a run of kImuCarried or kLost frames ends at the first
// frame whose dense terms pass.

#include <cstdint>

#include "vifusion/core/state.hpp"

namespace vifusion::slam {

enum class TrackingState : std::uint8_t { kTracked = 0, kImuCarried = 1, kLost = 2 };

/// "tracked", "imu_carried", "lost".
const char* trackingStateName(TrackingState state);

/// When an IMU-carried pose is still fused.
struct ImuCarryOptions {
  /// A pose is fused while its uncertainty at the far end of the depth range is at most this multiple of
  /// the sensor's axial noise there: σ_p(z_max) = √(σ_r² + z_max²·σ_θ²) ≤ ratio · σ_z(z_max), with σ_r², σ_θ²
  /// the estimator's largest marginal position and rotation variances. At 1 the farthest measurements keep
  /// half their weight (σ_z grows with z², σ_p only with z, so nearer ones keep less); beyond it the pose
  /// adds more variance than the sensor anywhere in range and the frame is lost. With the Kinect noise model
  /// and a 4 m depth range the bound is σ_p(4 m) ≤ 25.8 mm. > 0.
  double max_pose_to_depth_sigma = 1.0;

  /// Throws vifusion::Error naming the field out of range.
  void validate() const;
};

/// The estimator's pose uncertainty as the fusion weighs it: the largest marginal variances of the camera
/// position [m²] and rotation [rad²] among the δr and δα components of `state_variance`.
struct PoseVariance {
  double position_m2 = 0.0;
  double rotation_rad2 = 0.0;

  static PoseVariance of(const Vector18d& state_variance);
  /// σ_p(z) = √(σ_r² + z²·σ_θ²) [m].
  double sigmaAt(double z_m) const;
};

}  // namespace vifusion::slam
