#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "expect_error.hpp"
#include "vifusion/eval/alignment.hpp"

namespace vifusion::eval {
namespace {

using test::expectError;

std::vector<Eigen::Vector3d> randomPoints(std::size_t count, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  std::vector<Eigen::Vector3d> points;
  for (std::size_t i = 0; i < count; ++i) points.emplace_back(uniform(rng), uniform(rng), uniform(rng));
  return points;
}

TEST(Alignment, RecoversKnownTransform) {
  std::mt19937 rng(7);
  const std::vector<Eigen::Vector3d> model = randomPoints(50, rng);
  const SE3d T_data_model(Eigen::Quaterniond(Eigen::AngleAxisd(2.5, Eigen::Vector3d(1, -2, 0.5).normalized())),
                          Eigen::Vector3d(0.3, -4.0, 12.0));
  std::vector<Eigen::Vector3d> data;
  for (const Eigen::Vector3d& p : model) data.push_back(T_data_model * p);
  const SE3d T = alignRigid(model, data);
  EXPECT_LT(T.quaternion().angularDistance(T_data_model.quaternion()), 1e-12);
  EXPECT_LT((T.translation() - T_data_model.translation()).norm(), 1e-12);
}

TEST(Alignment, PlanarMirrorDataStillGivesRotation) {
  // Data = model mirrored in z on a plane: the unconstrained optimum is a reflection; the S fix
  // must return a proper rotation instead.
  const std::vector<Eigen::Vector3d> model = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.1}};
  std::vector<Eigen::Vector3d> data;
  for (const Eigen::Vector3d& p : model) data.emplace_back(p.x(), p.y(), -p.z());
  const SE3d T = alignRigid(model, data);
  EXPECT_NEAR(T.rotationMatrix().determinant(), 1.0, 1e-12);
}

TEST(Alignment, RejectsTooFewOrMismatchedPoints) {
  const std::vector<Eigen::Vector3d> two = {{0, 0, 0}, {1, 0, 0}};
  const std::vector<Eigen::Vector3d> three = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  expectError([&] { alignRigid(two, two); }, "need at least 3 point pairs, got 2");
  expectError([&] { alignRigid(two, three); }, "differ in size");
}

TEST(Alignment, PosesDetermineTheRotationThatAStraightPathLeavesFree) {
  // Positions on a line leave the rotation about it free for alignRigid; the poses fix it.
  const SE3d T_data_model(Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1.0, -0.3).normalized())),
                          Eigen::Vector3d(1.5, -0.2, 3.0));
  std::vector<SE3d> model;
  std::vector<SE3d> data;
  for (int i = 0; i < 10; ++i) {
    model.emplace_back(Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * i, Eigen::Vector3d::UnitY())),
                       Eigen::Vector3d(0.002 * i, 0.0, 0.0));
    data.push_back(T_data_model * model.back());
  }
  const SE3d T = alignPoses(model, data);
  EXPECT_LT(T.quaternion().angularDistance(T_data_model.quaternion()), 1e-12);
  EXPECT_LT((T.translation() - T_data_model.translation()).norm(), 1e-12);
  expectError([&] { alignPoses({}, {}); }, "no pose pairs");
}

}  // namespace
}  // namespace vifusion::eval
