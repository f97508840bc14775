// The first gravity direction from the accelerometer (gravity_initialisation.hpp).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "simulated_rig.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/estimator/gravity_initialisation.hpp"
#include "vifusion/imu/sample_window.hpp"

namespace vifusion::estimator {
namespace {

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / std::numbers::pi;
}

TEST(GravityInitialisation, FindsGravityInTheWorldFromARestingTiltedRig) {
  // The white_wall preset starts at rest (|a| < 0.02 m/s², 0.1°); the rig's IMU is tilted 3° against the
  // camera. Exact readings must give the direction to that 0.1°; with Table I noise and a random
  // accelerometer bias, the bias tilts the mean reading by atan(|b_a|/g) at most, and nothing else may.
  for (const bool realistic : {false, true}) {
    const test::SimulatedRig rig("white_wall", 5, realistic);
    const std::int64_t t0_ns = rig.frame_times_ns.front();
    const NavState truth = rig.trueState(t0_ns);
    const auto window = imu::bracketingSamples(rig.imu.samples, t0_ns - 200'000'000, t0_ns);
    const auto init = initialGravity(window, SE3d(truth.q_W_C, truth.r_W_C), rig.T_S_C);
    ASSERT_TRUE(init.has_value());
    EXPECT_GE(init->samples, 2);
    // Gravity in W according to the estimate and in truth (the presets' world is y-up).
    const Eigen::Vector3d g_W = init->q_I_W.conjugate() * Eigen::Vector3d(0.0, 0.0, -1.0);
    const double error_deg = angleDeg(g_W, Eigen::Vector3d(0.0, -1.0, 0.0));
    std::printf("  %s: gravity direction off by %.4f°\n", realistic ? "noise and biases" : "clean", error_deg);
    const double bias_deg = std::atan(rig.imu.states.front().b_a.norm() / 9.81) * 180.0 / std::numbers::pi;
    EXPECT_LT(error_deg, bias_deg + 0.15) << "bias alone tilts by up to " << bias_deg << "°";
  }
}

TEST(GravityInitialisation, RefusesWhatHasNoDirection) {
  EXPECT_FALSE(initialGravity({}, SE3d(), SE3d()).has_value());
  std::vector<ImuSample> free_fall(10);
  for (ImuSample& s : free_fall) s.accel_mps2 = Eigen::Vector3d(0.1, -0.2, 0.3);
  EXPECT_FALSE(initialGravity(free_fall, SE3d(), SE3d()).has_value());
}

}  // namespace
}  // namespace vifusion::estimator
