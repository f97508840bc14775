#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "vifusion/estimator/estimator_options.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::estimator {
namespace {

TEST(EstimatorOptions, DefaultsAreValidAndModesHaveNames) {
  EXPECT_NO_THROW(EstimatorOptions{}.validate());
  EXPECT_EQ(inertialModeFromName("rgbdi"), InertialMode::kRgbdInertial);
  EXPECT_EQ(inertialModeFromName("gyro"), InertialMode::kGyro);
  EXPECT_STREQ(inertialModeName(InertialMode::kGyro), "gyro");
  EXPECT_STREQ(inertialModeName(InertialMode::kRgbdInertial), "rgbdi");
  vifusion::test::expectError([] { inertialModeFromName("rgbd-i"); }, "'rgbd-i' is not one of: rgbdi, gyro");
}

TEST(EstimatorOptions, ValidationNamesTheField) {
  const auto expectRejected = [](auto change, const std::string& field) {
    EstimatorOptions options;
    change(options);
    vifusion::test::expectError([&] { options.validate(); }, "'" + field + "'");
  };
  expectRejected([](EstimatorOptions& o) { o.iterations[1] = -1; }, "iterations");
  expectRejected([](EstimatorOptions& o) { o.converged_step_chi2 = 0.0; }, "converged_step_chi2");
  expectRejected([](EstimatorOptions& o) { o.inertial_only_iterations = 0; }, "inertial_only_iterations");
  expectRejected([](EstimatorOptions& o) { o.vision_gate_chi2 = 0.0; }, "vision_gate_chi2");
  expectRejected([](EstimatorOptions& o) { o.max_inlier_loss = 0.0; }, "max_inlier_loss");
  expectRejected([](EstimatorOptions& o) { o.max_inlier_loss = 1.5; }, "max_inlier_loss");
  expectRejected([](EstimatorOptions& o) { o.vision_gate_min_step_m = 0.0; }, "vision_gate_min_step_m");
  expectRejected([](EstimatorOptions& o) { o.vision_gate_min_step_rad = -1.0; }, "vision_gate_min_step_rad");
  expectRejected([](EstimatorOptions& o) { o.vision_gate_chi2 = std::numeric_limits<double>::quiet_NaN(); },
                 "vision_gate_chi2");
  expectRejected([](EstimatorOptions& o) { o.initial_pose_sigma = 0.0; }, "initial_pose_sigma");
  expectRejected([](EstimatorOptions& o) { o.initial_velocity_sigma_mps = -2.0; }, "initial_velocity_sigma_mps");
  expectRejected([](EstimatorOptions& o) { o.initial_gravity_sigma_rad = std::numeric_limits<double>::infinity(); },
                 "initial_gravity_sigma_rad");
  expectRejected([](EstimatorOptions& o) { o.gravity_window_ns = 0; }, "gravity_window_ns");
}

}  // namespace
}  // namespace vifusion::estimator
