// The estimator's per-frame path allocates nothing (DESIGN §1): fixed-size Eigen throughout.

#include <gtest/gtest.h>

#include "simulated_rig.hpp"
#include "vifusion/imu/sample_window.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::estimator {
namespace {

TEST(TwoStateEstimator, TracksFramesWithoutAllocating) {
  const test::SimulatedRig rig("fast", 71);
  test::SimulatedVision vision(0.002, 0.002, 72);
  for (const InertialMode mode : {InertialMode::kRgbdInertial, InertialMode::kGyro}) {
    EstimatorOptions options;
    options.mode = mode;
    TwoStateEstimator estimator(options, imu::ImuOptions{}, rig.T_S_C);
    estimator.initialise(rig.frame_times_ns.front(), rig.initialState());
    const auto track = [&](std::size_t k, bool healthy) {
      const std::int64_t t_ns = rig.frame_times_ns[k];
      const NavState truth = rig.trueState(t_ns);  // outside the count: the test's truth allocates nothing either
      vision.observe(SE3d(truth.q_W_C, truth.r_W_C));
      vision.setHealthy(healthy);
      FrameSolve solve;
      EXPECT_FALSE(estimator.track(t_ns, imu::bracketingSamples(rig.imu.samples, estimator.t_ns(), t_ns), &vision, solve));
    };
    for (std::size_t k = 1; k < 10; ++k) track(k, true);
    const uint64_t before = vifusion::test::heapAllocationCount();
    for (std::size_t k = 10; k < 70; ++k) track(k, k % 7 != 0);  // every 7th frame without vision
    EXPECT_EQ(vifusion::test::heapAllocationCount() - before, 0u) << inertialModeName(mode);
    (void)estimator.covarianceDiagonal();
  }
}

}  // namespace
}  // namespace vifusion::estimator
