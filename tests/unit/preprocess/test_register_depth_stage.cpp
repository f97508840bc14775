// Depth registration as the first step of the preprocessing stage's options and of PreprocessCpu
// (GPU builds only: both live in vifusion::preprocess).

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/preprocess/depth_registration.hpp"
#include "vifusion/preprocess/preprocess_cpu.hpp"

namespace vifusion::preprocess {
namespace {

PinholeCamera depthCamera() { return PinholeCamera::create(80, 60, 70.0, 70.0, 39.5, 29.5); }

SE3d translation(double x_m, double y_m, double z_m) {
  return SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(x_m, y_m, z_m));
}

DepthRegistration sameIntrinsics(const SE3d& T_C_D) { return {depthCamera(), depthCamera(), T_C_D, 0.001}; }

// The whole CPU stage runs the registration first, and only when it is not the identity.
TEST(RegisterDepthStage, PreprocessCpuRegistersBeforeMetricDepth) {
  PreprocessOptions options;
  options.camera = PinholeCamera::create(96, 72, 90.0, 90.0, 47.3, 35.8);
  options.registration = DepthRegistration{depthCamera(), options.camera, translation(-0.025, 0.0, 0.0), 0.001};
  options.metric.depth_scale_m = 0.001f;
  ASSERT_TRUE(options.registersDepth());
  PreprocessCpu cpu(options);
  const Image<std::uint16_t> depth(80, 60, 1200);
  const Image<Rgb8> rgb(96, 72);
  cpu.setInput(depth.view(), rgb.view());
  cpu.runStep(PreprocessStep::RegisterDepth);
  cpu.runStep(PreprocessStep::MetricAndIntensity);
  Image<std::uint16_t> registered(96, 72);
  registerDepthToColourCpu(depth.view(), *options.registration, registered.view());
  std::size_t valid = 0;
  for (int y = 0; y < 72; ++y) {
    for (int x = 0; x < 96; ++x) {
      ASSERT_EQ(cpu.registeredDepth()(x, y), registered(x, y));
      ASSERT_EQ(cpu.rawDepth()(x, y), registered(x, y) == 0 ? 0.0f : 1.2f) << x << "," << y;
      valid += registered(x, y) != 0;
    }
  }
  EXPECT_GT(valid, 4000u);
  EXPECT_THROW(cpu.setInput(registered.view(), rgb.view()), Error);  // depth at the colour size
}

TEST(RegisterDepthStage, PreprocessOptionsCheckTheRegistrationAgainstTheRest) {
  PreprocessOptions options;
  options.camera = depthCamera();
  options.metric.depth_scale_m = 0.001f;
  options.registration = sameIntrinsics(SE3d());
  EXPECT_NO_THROW(options.validate());
  EXPECT_FALSE(options.registersDepth());  // identity: skipped
  options.registration->T_C_D = translation(0.025, 0.0, 0.0);
  EXPECT_TRUE(options.registersDepth());
  const auto expectError = [&](const std::string& name) {
    try {
      options.validate();
      ADD_FAILURE() << "accepted a bad '" << name << "'";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
    }
  };
  options.registration->colour.cx = 40.0;
  expectError("registration.colour");
  options.registration->colour = options.camera;
  options.registration->depth_scale_m = 0.0002;
  expectError("registration.depth_scale_m");
  options.registration->depth_scale_m = 0.001;
  options.registration->depth = PinholeCamera::create(81, 60, 70.0, 70.0, 40.0, 29.5);
  expectError("registration.depth");
  options.registration->depth.fy = 0.0;
  expectError("'depth'");
}

}  // namespace
}  // namespace vifusion::preprocess
