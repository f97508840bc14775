#include "vifusion/slam/tracking_state.hpp"

#include <cmath>

#include "vifusion/core/error.hpp"

namespace vifusion::slam {

const char* trackingStateName(TrackingState state) {
  switch (state) {
    case TrackingState::kImuCarried:
      return "imu_carried";
    case TrackingState::kLost:
      return "lost";
    case TrackingState::kTracked:
      break;
  }
  return "tracked";
}

void ImuCarryOptions::validate() const {
  if (!(max_pose_to_depth_sigma > 0.0) || !std::isfinite(max_pose_to_depth_sigma)) {
    throw Error("IMU-carry option 'max_pose_to_depth_sigma' must be finite and > 0");
  }
}

PoseVariance PoseVariance::of(const Vector18d& state_variance) {
  return {state_variance.segment<3>(kIdxR).maxCoeff(), state_variance.segment<3>(kIdxAlpha).maxCoeff()};
}

double PoseVariance::sigmaAt(double z_m) const { return std::sqrt(position_m2 + z_m * z_m * rotation_rad2); }

}  // namespace vifusion::slam
