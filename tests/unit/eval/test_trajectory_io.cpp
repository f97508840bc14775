#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "expect_error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/eval/trajectory_io.hpp"

namespace vifusion::eval {
namespace {

using test::expectError;

TEST(TrajectoryIo, ParsesSpacesCommasTabsCommentsAndBlankLines) {
  const std::string text =
      "# ground truth trajectory\n"
      "\n"
      "1305031098.6659 1.3563 0.6305 1.6380 0 0 0 1\n"
      "   \t\n"
      "1305031098.6758,1.0,2.0,3.0,0,0,1,0\r\n"
      "  # indented comment\n"
      "1305031099\t-1\t-2\t-3\t0\t1\t0\t0\n";
  const std::vector<StampedPose> poses = parseTum(text, "gt.txt");
  ASSERT_EQ(poses.size(), 3u);
  // Exact decimal conversion: no double rounding of a 1.3e9 s stamp.
  EXPECT_EQ(poses[0].t_ns, 1305031098665900000);
  EXPECT_EQ(poses[1].t_ns, 1305031098675800000);
  EXPECT_EQ(poses[2].t_ns, 1305031099000000000);
  EXPECT_TRUE(poses[0].T_world_body.translation().isApprox(Eigen::Vector3d(1.3563, 0.6305, 1.6380)));
  EXPECT_TRUE(poses[1].T_world_body.translation().isApprox(Eigen::Vector3d(1.0, 2.0, 3.0)));
  // Order is qx qy qz qw: (0, 0, 1, 0) is a half turn about z.
  EXPECT_NEAR(poses[1].T_world_body.quaternion().z(), 1.0, 1e-15);
  EXPECT_NEAR(poses[2].T_world_body.quaternion().y(), 1.0, 1e-15);
}

TEST(TrajectoryIo, ExponentStampsRoundToNearestNanosecond) {
  const std::vector<StampedPose> poses = parseTum("1.5e0 0 0 0 0 0 0 1\n", "x.txt");
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_EQ(poses[0].t_ns, 1'500'000'000);
}

TEST(TrajectoryIo, NearlyUnitQuaternionIsNormalised) {
  const std::vector<StampedPose> poses = parseTum("1 0 0 0 0 0 0 1.0005\n", "x.txt");
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_NEAR(poses[0].T_world_body.quaternion().norm(), 1.0, 1e-15);
}

TEST(TrajectoryIo, WrongFieldCountNamesFileLineAndCount) {
  expectError([] { parseTum("# c\n1 0 0 0 0 0 1\n", "gt.txt"); }, "gt.txt line 2: expected 8 numbers, found 7");
  expectError([] { parseTum("1 0 0 0 0 0 0 1 9\n", "gt.txt"); }, "gt.txt line 1: expected 8 numbers, found 9");
}

TEST(TrajectoryIo, NonFiniteOrGarbageFieldIsNamed) {
  expectError([] { parseTum("1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n3 0 0 0 0 0 0 nan\n", "e.txt"); },
              "e.txt line 3: field 'qw' is not a finite number");
  expectError([] { parseTum("1 0 inf 0 0 0 0 1\n", "e.txt"); }, "line 1: field 'ty' is not a finite number");
  expectError([] { parseTum("1 0 0 0 0 0x1 0 1\n", "e.txt"); }, "line 1: field 'qy' is not a finite number: '0x1'");
  expectError([] { parseTum("abc 0 0 0 0 0 0 1\n", "e.txt"); }, "line 1: field 't' is not a finite number");
}

TEST(TrajectoryIo, BackwardsAndRepeatedStampsAreRejected) {
  expectError([] { parseTum("1.000 0 0 0 0 0 0 1\n0.995 0 0 0 0 0 0 1\n", "imu.txt"); },
              "imu.txt line 2: timestamp goes backwards by 5 ms");
  expectError([] { parseTum("1.0 0 0 0 0 0 0 1\n1.000 0 0 0 0 0 0 1\n", "x.txt"); }, "x.txt line 2: timestamp repeats");
}

TEST(TrajectoryIo, StampsBeyondTheFileRangeAreRejected) {
  // Found by fuzz_dataset_lists: a stamp near -2^63 ns after a 2011 one overflowed the step between them.
  expectError([] { parseTum("1305031102.16 0 0 0 0 0 0 1\n-9141712971.3 0 0 0 0 0 0 1\n", "t.txt"); },
              "t.txt line 2: field 't' is beyond the 4000000000 s a stamp may hold: '-9141712971.3'");
  expectError([] { parseTum("9999999999.999999999 0 0 0 0 0 0 1\n", "t.txt"); },
              "t.txt line 1: field 't' is beyond the 4000000000 s");
  // The extremes of the range still order and round-trip.
  const std::vector<StampedPose> poses = parseTum("-4e9 0 0 0 0 0 0 1\n4000000000 0 0 0 0 0 0 1\n", "t.txt");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].t_ns, -kMaxFileStampNs);
  EXPECT_EQ(poses[1].t_ns, kMaxFileStampNs);
}

TEST(TrajectoryIo, QuaternionFarFromUnitIsRejected) {
  expectError([] { parseTum("1 0 0 0 0 0 0 1.002\n", "q.txt"); }, "q.txt line 1: quaternion norm 1.002");
  expectError([] { parseTum("1 0 0 0 0 0 0 0\n", "q.txt"); }, "q.txt line 1: quaternion norm 0");
}

TEST(TrajectoryIo, MissingFileIsNamed) {
  expectError([] { readTum("/nonexistent/dir/gt.txt"); }, "cannot open trajectory file '/nonexistent/dir/gt.txt'");
}

TEST(TrajectoryIo, WriteThenReadRoundTrips) {
  std::vector<StampedPose> poses;
  poses.push_back({1305031098665900001, SE3d(Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5), Eigen::Vector3d(1.25, -2, 3))});
  poses.push_back({1305031099000000000, SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX())),
                                             Eigen::Vector3d(-0.123456789, 0, 1e-3))});
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "vifusion_test_eval_roundtrip.txt";
  writeTum(path, poses);
  const std::vector<StampedPose> read = readTum(path);
  std::filesystem::remove(path);
  ASSERT_EQ(read.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_EQ(read[i].t_ns, poses[i].t_ns);
    EXPECT_LT((read[i].T_world_body.translation() - poses[i].T_world_body.translation()).norm(), 1e-9);
    EXPECT_LT(read[i].T_world_body.quaternion().angularDistance(poses[i].T_world_body.quaternion()), 1e-8);
  }
}

}  // namespace
}  // namespace vifusion::eval
