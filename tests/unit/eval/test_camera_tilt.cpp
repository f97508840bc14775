#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "expect_error.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/eval/camera_tilt.hpp"

namespace vifusion::eval {
namespace {

using test::expectError;

constexpr double kDegToRad = M_PI / 180.0;
const Eigen::Vector3d kGravityGt(0.0, -9.81, 0.0);  // y-up ground truth

/// 50 true camera poses turning about every axis, 33 ms apart.
std::vector<StampedPose> trueCameras() {
  std::vector<StampedPose> poses;
  for (int k = 0; k < 50; ++k) {
    const double t = 0.1 * k;
    poses.push_back(
        {int64_t{k} * 33'000'000, SE3d(expSO3(Eigen::Vector3d(0.3 * std::sin(t), 1.5 * t, 0.2 * std::cos(2 * t))),
                                       Eigen::Vector3d(std::cos(t), 0.1 * t, std::sin(t)))});
  }
  return poses;
}

std::vector<std::size_t> identityPairs(std::size_t n) {
  std::vector<std::size_t> index(n);
  for (std::size_t i = 0; i < n; ++i) index[i] = i;
  return index;
}

/// The same cameras in another world W = R_W_G·G, with gravity rotated alike: no tilt at all.
struct Estimate {
  std::vector<StampedPose> poses;
  std::vector<EstimatedState> states;
};
Estimate inAnotherWorld(const std::vector<StampedPose>& gt, const Eigen::Quaterniond& q_W_G) {
  Estimate estimate;
  for (const StampedPose& pose : gt) {
    estimate.poses.push_back({pose.t_ns, SE3d(q_W_G, Eigen::Vector3d(0.5, -2.0, 3.0)) * pose.T_world_body});
    EstimatedState state;
    state.t_ns = pose.t_ns;
    state.g_W = (q_W_G * kGravityGt).normalized();
    estimate.states.push_back(state);
  }
  return estimate;
}

TEST(CameraTilt, AnyWorldWithItsGravityHasNoTiltAndATiltedGravityHasItsAngle) {
  const std::vector<StampedPose> gt = trueCameras();
  const auto pairs = identityPairs(gt.size());
  // W differs from G by a yaw and a tilt: the estimate's gravity knows it, so nothing is tilted.
  const Eigen::Quaterniond q_W_G = expSO3(Eigen::Vector3d(0.4, -1.1, 0.25));
  Estimate estimate = inAnotherWorld(gt, q_W_G);
  for (const CameraTiltSample& s :
       cameraTilt(gt, estimate.poses, pairs, pairs, estimate.states, kGravityGt, 1'000'000).series) {
    EXPECT_NEAR(s.tilt_deg, 0.0, 1e-6);
  }
  // A yaw error of every camera about gravity is not a tilt.
  Estimate yawed = estimate;
  const Eigen::Vector3d down_W = estimate.states.front().g_W;
  for (StampedPose& pose : yawed.poses)
    pose.T_world_body = SE3d(expSO3(0.7 * down_W), Eigen::Vector3d::Zero()) * pose.T_world_body;
  for (const CameraTiltSample& s :
       cameraTilt(gt, yawed.poses, pairs, pairs, yawed.states, kGravityGt, 1'000'000).series) {
    EXPECT_NEAR(s.tilt_deg, 0.0, 1e-6);
  }
  // Gravity rotated by 0.3° about a horizontal axis of W: every camera is tilted by exactly that.
  const Eigen::Vector3d horizontal_W = down_W.cross(Eigen::Vector3d(0.3, 0.5, -0.2)).normalized();
  for (EstimatedState& state : estimate.states) state.g_W = expSO3(0.3 * kDegToRad * horizontal_W) * state.g_W;
  const CameraTilt tilted = cameraTilt(gt, estimate.poses, pairs, pairs, estimate.states, kGravityGt, 1'000'000);
  ASSERT_EQ(tilted.series.size(), gt.size());
  for (const CameraTiltSample& s : tilted.series) EXPECT_NEAR(s.tilt_deg, 0.3, 1e-9);
  EXPECT_NEAR(tilted.rms_deg, 0.3, 1e-9);
  EXPECT_NEAR(tilted.max_deg, 0.3, 1e-9);
  EXPECT_NEAR(tilted.final_deg, 0.3, 1e-9);
}

TEST(CameraTilt, PosesWithoutAStateNearTheirStampAreLeftOut) {
  const std::vector<StampedPose> gt = trueCameras();
  const auto pairs = identityPairs(gt.size());
  Estimate estimate = inAnotherWorld(gt, Eigen::Quaterniond::Identity());
  // Every second state 2 ms late: within a 3 ms window they count, within 1 ms they do not.
  for (std::size_t i = 1; i < estimate.states.size(); i += 2) estimate.states[i].t_ns += 2'000'000;
  EXPECT_EQ(cameraTilt(gt, estimate.poses, pairs, pairs, estimate.states, kGravityGt, 3'000'000).series.size(),
            gt.size());
  EXPECT_EQ(cameraTilt(gt, estimate.poses, pairs, pairs, estimate.states, kGravityGt, 1'000'000).series.size(),
            gt.size() / 2);
}

TEST(CameraTilt, NoStateOrNoGravityIsAnError) {
  const std::vector<StampedPose> gt = trueCameras();
  const auto pairs = identityPairs(gt.size());
  Estimate estimate = inAnotherWorld(gt, Eigen::Quaterniond::Identity());
  expectError([&] { cameraTilt(gt, estimate.poses, pairs, pairs, {}, kGravityGt, 1'000'000); },
              "no estimated pose has an estimator state");
  expectError(
      [&] { cameraTilt(gt, estimate.poses, pairs, pairs, estimate.states, Eigen::Vector3d::Zero(), 1'000'000); },
      "the ground truth's gravity is zero");
  estimate.states[3].g_W = Eigen::Vector3d(std::nan(""), 0.0, 0.0);
  expectError([&] { cameraTilt(gt, estimate.poses, pairs, pairs, estimate.states, kGravityGt, 1'000'000); },
              "an estimated gravity is zero or not finite");
}

}  // namespace
}  // namespace vifusion::eval
