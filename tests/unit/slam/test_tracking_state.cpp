// The tracking states' CPU rules (slam/tracking_state.hpp): names, the IMU-carry bound's option and the
// pose uncertainty the fusion weighs an IMU-carried frame by.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/slam/tracking_state.hpp"

namespace vifusion::slam {
namespace {

TEST(TrackingState, NamesAreTheReportsKeys) {
  EXPECT_EQ(std::string(trackingStateName(TrackingState::kTracked)), "tracked");
  EXPECT_EQ(std::string(trackingStateName(TrackingState::kImuCarried)), "imu_carried");
  EXPECT_EQ(std::string(trackingStateName(TrackingState::kLost)), "lost");
}

TEST(TrackingState, PoseVarianceTakesTheLargestPositionAndRotationVariances) {
  Vector18d variance = Vector18d::Constant(7.0);  // velocity, biases and gravity must not enter
  variance.segment<3>(kIdxR) << 1e-6, 4e-6, 2e-6;
  variance.segment<3>(kIdxAlpha) << 3e-7, 1e-7, 9e-7;
  const PoseVariance pose = PoseVariance::of(variance);
  EXPECT_EQ(pose.position_m2, 4e-6);
  EXPECT_EQ(pose.rotation_rad2, 9e-7);
  // σ_p(z) = √(σ_r² + z²σ_θ²): 2 mm at the camera, rotation adding 3 mm per metre … at 4 m √(4 + 144) mm.
  EXPECT_NEAR(pose.sigmaAt(0.0), 2e-3, 1e-12);
  EXPECT_NEAR(pose.sigmaAt(4.0), std::sqrt(4e-6 + 16.0 * 9e-7), 1e-12);
}

TEST(TrackingState, TheCarryBoundMustBePositiveAndFinite) {
  ImuCarryOptions options;
  EXPECT_NO_THROW(options.validate());
  for (const double bad : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    options.max_pose_to_depth_sigma = bad;
    EXPECT_THROW(options.validate(), Error) << bad;
  }
}

}  // namespace
}  // namespace vifusion::slam
