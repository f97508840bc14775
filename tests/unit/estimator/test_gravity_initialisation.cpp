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

TEST(GravityInitialisation, RemovesAKnownStaticBiasBeforeTakingTheDirection) {
  // A level rig at rest reading gravity's reaction plus the ZR300's static bias (Table I, real world): the
  // bias tilts "up" by atan(|b_xy| / g) unless it is removed.
  const Eigen::Vector3d static_bias_S(0.060, 0.258, 0.126);
  std::vector<ImuSample> at_rest(20);
  for (ImuSample& s : at_rest) s.accel_mps2 = Eigen::Vector3d(0.0, 0.0, 9.81) + static_bias_S;
  const Eigen::Vector3d up_I = Eigen::Vector3d::UnitZ();
  const auto ignored = initialGravity(at_rest, SE3d(), SE3d());
  const auto removed = initialGravity(at_rest, SE3d(), SE3d(), static_bias_S);
  ASSERT_TRUE(ignored && removed);
  const double tilt_deg =
      std::atan(static_bias_S.head<2>().norm() / (9.81 + static_bias_S.z())) * 180.0 / std::numbers::pi;
  EXPECT_NEAR(angleDeg(ignored->q_I_W.conjugate() * up_I, up_I), tilt_deg, 1e-9);
  EXPECT_NEAR(angleDeg(removed->q_I_W.conjugate() * up_I, up_I), 0.0, 1e-9);
  EXPECT_TRUE(removed->mean_specific_force_S_mps2.isApprox(Eigen::Vector3d(0.0, 0.0, 9.81), 1e-12));
}

TEST(GravityInitialisation, RefusesWhatHasNoDirection) {
  EXPECT_FALSE(initialGravity({}, SE3d(), SE3d()).has_value());
  std::vector<ImuSample> free_fall(10);
  for (ImuSample& s : free_fall) s.accel_mps2 = Eigen::Vector3d(0.1, -0.2, 0.3);
  EXPECT_FALSE(initialGravity(free_fall, SE3d(), SE3d()).has_value());
}

}  // namespace
}  // namespace vifusion::estimator
