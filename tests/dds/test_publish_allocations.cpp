// Publishing allocates nothing of ours: building messages borrows, Writer::write hands them to
// Cyclone, which serialises with its own (C) allocator. Counted with the operator-new replacement of
// tests/gpu, which sees every C++ allocation in this executable.

#include <gtest/gtest.h>

#include "dds_test_support.hpp"
#include "vifusion/dds/conversions.hpp"
#include "vifusion/dds/writer.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::dds {
namespace {

TEST(DdsPublish, AllocatesNothingOfOurs) {
  const Participant participant(test::loopbackOptions());
  Writer pose_writer(participant, topics::kPose);
  Writer odometry_writer(participant, topics::kOdometry);
  Writer tf_writer(participant, topics::kTf);
  Writer imu_writer(participant, topics::kImuState);
  Writer map_writer(participant, topics::kMap);
  std::vector<MapPoint> points(1000);
  std::array<msg::TransformStamped, 1> transforms{};
  const NavState x;
  const Matrix18d covariance = Matrix18d::Identity();
  const Vector18d variance = Vector18d::Ones();

  const std::uint64_t before = vifusion::test::heapAllocationCount();
  for (std::int64_t t_ns = 0; t_ns < 50; ++t_ns) {
    const SE3d T_W_C(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.01 * t_ns, 0, 0));
    EXPECT_TRUE(pose_writer.write(makePoseStamped(t_ns, "world", T_W_C)));
    EXPECT_TRUE(odometry_writer.write(makeOdometry(t_ns, "world", "camera", T_W_C, Eigen::Vector3d::Zero(),
                                                   Eigen::Vector3d::Zero(), Matrix6d::Identity(), Matrix6d::Zero())));
    transforms[0] = makeTransformStamped(t_ns, "world", "camera", T_W_C);
    EXPECT_TRUE(tf_writer.write(makeTfMessage(transforms)));
    EXPECT_TRUE(imu_writer.write(makeImuState(t_ns, "world", x, covariance)));
    // The inertial modes' builders (vifusiond's publisher, per frame).
    EXPECT_TRUE(imu_writer.write(makeImuStateFromVariances(t_ns, "world", x, variance)));
    EXPECT_TRUE(odometry_writer.write(
        makeInertialOdometry(t_ns, "world", "camera", SE3d(), x, variance, Eigen::Vector3d(0, 0, 0.1), T_W_C)));
    EXPECT_TRUE(map_writer.write(makePointCloud2(t_ns, "world", points)));
  }
  EXPECT_EQ(vifusion::test::heapAllocationCount() - before, 0u);
}

}  // namespace
}  // namespace vifusion::dds
