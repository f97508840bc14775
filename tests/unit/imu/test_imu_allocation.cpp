#include <gtest/gtest.h>

#include <vector>

#include "vifusion/test/counting_allocations.hpp"
#include "imu_test_utils.hpp"
#include "vifusion/imu/imu_error.hpp"
#include "vifusion/imu/preintegration.hpp"

namespace vifusion::imu {
namespace {

TEST(ImuAllocation, PerFramePathAllocatesNothing) {
  // Start-up: options, samples (the ring's memory in the real pipeline), integrator, error term.
  test::RandomInputs rnd(9);
  const std::vector<ImuSample> samples = test::smoothSamples(9, 0, 400);
  const ImuOptions options;
  const ImuPreintegrator integrator(options);
  const ImuError error(options, test::randomT_S_C(rnd));
  PreintegratedImu pre;
  const NavState x0 = test::randomState(rnd);
  const NavState x1 = test::randomState(rnd);
  Matrix18d J_x0, J_x1, information;
  std::vector<ImuSample> broken = samples;
  broken[100].t_ns = broken[99].t_ns;

  const std::uint64_t before = vifusion::test::heapAllocationCount();
  double checksum = 0.0;
  for (int frame = 0; frame < 50; ++frame) {
    const std::int64_t t0_ns = 10'000'000 + frame * 33'333'333;
    const auto issue = integrator.integrate(samples, t0_ns, t0_ns + 33'333'333, x0.b_g, x0.b_a, pre);
    checksum += issue.has_value() ? 1.0 : 0.0;
    if (pre.needsReintegration(x1.b_g)) {
      checksum += integrator.integrate(samples, t0_ns, t0_ns + 33'333'333, x1.b_g, x1.b_a, pre).has_value();
    }
    checksum += error.evaluate(pre, x0, x1, &J_x0, &J_x1, &information).norm();
    checksum += error.predict(pre, x0).r_W_C.norm();
    // The error path too, as long as nobody asks for the message.
    checksum += integrator.integrate(broken, t0_ns, t0_ns + 33'333'333, x0.b_g, x0.b_a, pre).has_value();
  }
  EXPECT_EQ(vifusion::test::heapAllocationCount(), before);
  EXPECT_GT(checksum, 0.0);
  // The counter does see allocations.
  const std::vector<int> probe(3);
  EXPECT_GT(vifusion::test::heapAllocationCount(), before);
}

}  // namespace
}  // namespace vifusion::imu
