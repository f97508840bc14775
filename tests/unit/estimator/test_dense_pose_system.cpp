// The dense terms' change of coordinates (dense_pose_system.hpp) against numeric differentiation: the
// reference-camera twist that a state perturbation [δr, δα] of x1 causes, and the cost it preserves.

#include <gtest/gtest.h>

#include "vifusion/core/numeric_diff.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/estimator/dense_pose_system.hpp"
#include "vifusion/test/random_inputs.hpp"

namespace vifusion::estimator {
namespace {

using vifusion::test::RandomInputs;

SE3d randomPose(RandomInputs& rnd, double translation_m) {
  return SE3d(expSO3(rnd.vector<3>(2.0)), rnd.vector<3>(translation_m));
}

TEST(DensePoseSystem, TwistJacobianMatchesNumericDifferentiation) {
  RandomInputs rnd(41);
  for (int trial = 0; trial < 20; ++trial) {
    const SE3d T_W_ref = randomPose(rnd, 3.0);
    // The current camera near the reference, as in tracking, and also far from it and from W's origin.
    const SE3d T_W_C = trial % 2 == 0 ? T_W_ref * randomPose(rnd, 0.1) : randomPose(rnd, 5.0);
    NavState x;
    x.r_W_C = T_W_C.translation();
    x.q_W_C = T_W_C.quaternion();
    const SE3d T_ref_cur = T_W_ref.inverse() * T_W_C;
    // ξ(δ) = log(T_ref_cur(x ⊞ δ)·T_ref_cur⁻¹): the left twist in the reference camera.
    const auto twist = [&](const NavState& s) -> Vector6d {
      return (T_W_ref.inverse() * SE3d(s.q_W_C, s.r_W_C) * T_ref_cur.inverse()).log();
    };
    const Eigen::Matrix<double, 6, kStateDim> numeric = numericJacobian<kStateDim>(
        twist, x, [](const NavState& s, const Vector18d& d) { return boxPlus(s, d); });
    const Matrix6d analytic = referenceTwistPerStatePose(T_W_ref, T_W_C);
    EXPECT_LT((numeric.leftCols<6>() - analytic).cwiseAbs().maxCoeff(), 1e-7 * (1.0 + analytic.cwiseAbs().maxCoeff()))
        << "trial " << trial << "\nnumeric\n" << numeric.leftCols<6>() << "\nanalytic\n" << analytic;
    // The pose's Jacobian has no other columns: the dense terms see nothing but x1's pose.
    EXPECT_LT(numeric.rightCols<12>().cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(DensePoseSystem, ConvertedSystemPredictsTheSameCostChange) {
  // A quadratic cost in the reference twist, ½ξᵀHξ + bᵀξ, must change by the same amount to first and
  // second order whether the step is written as ξ or as the state perturbation it comes from.
  RandomInputs rnd(42);
  const SE3d T_W_ref = randomPose(rnd, 2.0);
  const SE3d T_W_C = T_W_ref * randomPose(rnd, 0.05);
  const Eigen::Matrix<double, 6, 6> L = Eigen::Matrix<double, 6, 6>::Random();
  const Matrix6d H_ref = L * L.transpose() + Matrix6d::Identity();
  const Vector6d b_ref = Vector6d::Random();
  const PoseSystem system = toStatePose(H_ref, b_ref, T_W_ref, T_W_C);
  const Vector6d delta_state = 1e-4 * Vector6d::Random();
  const Vector6d xi = referenceTwistPerStatePose(T_W_ref, T_W_C) * delta_state;
  const double cost_ref = 0.5 * xi.dot(H_ref * xi) + b_ref.dot(xi);
  const double cost_state = 0.5 * delta_state.dot(system.H * delta_state) + system.b.dot(delta_state);
  EXPECT_NEAR(cost_ref, cost_state, 1e-12 * (1.0 + std::abs(cost_ref)));
  EXPECT_LT((system.H - system.H.transpose()).cwiseAbs().maxCoeff(), 1e-9 * system.H.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace vifusion::estimator
