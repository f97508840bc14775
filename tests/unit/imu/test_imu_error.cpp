#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "imu_test_utils.hpp"
#include "vifusion/core/numeric_diff.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/imu/imu_error.hpp"
#include "vifusion/imu/preintegration.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion::imu {
namespace {

using test::integrateOrFail;
using test::RandomInputs;
using test::smoothSamples;
using Vector15d = Eigen::Matrix<double, kDeltaDim, 1>;

constexpr std::int64_t kStartNs = 5'000'000'000;

const auto kPlus = [](const NavState& x, const Vector18d& d) { return boxPlus(x, d); };

/// A random but realistic problem: biases of x0 away from the linearisation point (so the first-order
/// correction is active), one 30 Hz frame off the sample grid.
struct Problem {
  SE3d T_S_C;
  PreintegratedImu pre;
  NavState x0;
};

Problem randomProblem(unsigned seed) {
  RandomInputs rnd(seed);
  Problem p;
  p.T_S_C = test::randomT_S_C(rnd);
  const std::vector<ImuSample> samples = smoothSamples(seed, kStartNs, 20);
  const ImuPreintegrator integrator{ImuOptions{}};
  p.x0 = test::randomState(rnd);
  p.pre = integrateOrFail(integrator, samples, kStartNs + 2'345'678, kStartNs + 35'679'011,
                          p.x0.b_g + rnd.vector<3>(0.01), p.x0.b_a + rnd.vector<3>(0.1));
  return p;
}

/// A perturbation with rotations up to max_angle_rad.
Vector18d randomDelta(RandomInputs& rnd, double scale, double max_angle_rad) {
  Vector18d d = rnd.vector<18>(scale);
  d.segment<3>(kIdxAlpha) = rnd.rotationVector(max_angle_rad);
  d.segment<3>(kIdxG) = rnd.rotationVector(max_angle_rad);
  return d;
}

TEST(ImuError, JacobiansMatchNumericDifferentiation) {
  double worst_x0 = 0.0, worst_x1 = 0.0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const Problem p = randomProblem(seed);
    const ImuError error(ImuOptions{}, p.T_S_C);
    RandomInputs rnd(100 + seed);
    // x1 near the prediction (as during tracking), and far from it (large rotation errors, where the
    // inverse Jacobians of ⊟ are far from the identity).
    const NavState predicted = error.predict(p.pre, p.x0);
    for (const NavState& x1 :
         {boxPlus(predicted, randomDelta(rnd, 0.05, 0.05)), boxPlus(predicted, randomDelta(rnd, 2.0, 2.5))}) {
      Matrix18d J_x0, J_x1;
      error.evaluate(p.pre, p.x0, x1, &J_x0, &J_x1);
      const Matrix18d J_x0_num =
          numericJacobian<kStateDim>([&](const NavState& x) { return error.evaluate(p.pre, x, x1); }, p.x0, kPlus);
      const Matrix18d J_x1_num =
          numericJacobian<kStateDim>([&](const NavState& x) { return error.evaluate(p.pre, p.x0, x); }, x1, kPlus);
      EXPECT_MATRIX_NEAR(J_x0, J_x0_num, 1e-7) << "seed " << seed;
      EXPECT_MATRIX_NEAR(J_x1, J_x1_num, 1e-7) << "seed " << seed;
      worst_x0 = std::max(worst_x0, (J_x0 - J_x0_num).cwiseAbs().maxCoeff());
      worst_x1 = std::max(worst_x1, (J_x1 - J_x1_num).cwiseAbs().maxCoeff());
    }
  }
  std::printf("  largest |analytic − numeric|: J_x0 %.2e, J_x1 %.2e\n", worst_x0, worst_x1);
}

TEST(ImuError, VanishesAtThePrediction) {
  const Problem p = randomProblem(3);
  const ImuError error(ImuOptions{}, p.T_S_C);
  const NavState x1 = error.predict(p.pre, p.x0);
  Matrix18d J_x1;
  EXPECT_MATRIX_NEAR(error.evaluate(p.pre, p.x0, x1, nullptr, &J_x1), Vector18d::Zero(), 1e-12);
  EXPECT_MATRIX_NEAR(J_x1, -Matrix18d::Identity(), 1e-12);
  // Biases and the gravity direction are carried over unchanged.
  EXPECT_EQ(x1.b_g, p.x0.b_g);
  EXPECT_EQ(x1.b_a, p.x0.b_a);
  // A few ulp, not 0: with fused multiply-add (aarch64) the angle of equal quaternions is ~1e-16.
  EXPECT_ROTATION_NEAR(x1.q_I_W, p.x0.q_I_W, 1e-14);
}

TEST(ImuError, InformationInvertsTheMappedPreintegrationCovariance) {
  // Cov(e) = N·Σ_η·Nᵀ with N = ∂e/∂η from numeric differentiation: perturbing the preintegrated deltas
  // (Δp, ΔR on the right, Δv) and the bias walk (b1 = b0 + walk, so e_b = −walk), plus the gravity
  // direction's walk on δg.
  for (unsigned seed = 1; seed <= 5; ++seed) {
    Problem p = randomProblem(seed);
    p.x0.b_g = p.pre.b_g_lin_rad_s;  // η perturbs the uncorrected ΔR; here the correction is the identity
    p.x0.b_a = p.pre.b_a_lin_mps2;
    const ImuOptions options;
    const ImuError error(options, p.T_S_C);
    RandomInputs rnd(200 + seed);
    const NavState x1 = boxPlus(error.predict(p.pre, p.x0), randomDelta(rnd, 0.05, 0.3));
    Matrix18d information;
    error.evaluate(p.pre, p.x0, x1, nullptr, nullptr, &information);

    const auto perturbed = [&](const Vector15d& eta) {
      PreintegratedImu q = p.pre;
      q.delta.dp_S0_m += eta.segment<3>(kDeltaIdxP);
      q.delta.q_S0_S1 = q.delta.q_S0_S1 * expSO3(eta.segment<3>(kDeltaIdxPhi));
      q.delta.dv_S0_mps += eta.segment<3>(kDeltaIdxV);
      NavState x1_walked = x1;
      x1_walked.b_g += eta.segment<3>(kDeltaIdxBg);
      x1_walked.b_a += eta.segment<3>(kDeltaIdxBa);
      return error.evaluate(q, p.x0, x1_walked);
    };
    const Eigen::Matrix<double, kStateDim, kDeltaDim> N = numericJacobian(perturbed, Vector15d::Zero());
    Matrix18d covariance = N * p.pre.covariance * N.transpose();
    const Eigen::Matrix3d J_l_inv_g = leftJacobianInvSO3(error.evaluate(p.pre, p.x0, x1).segment<3>(kIdxG));
    covariance.block<3, 3>(kIdxG, kIdxG) += options.gravity_direction_random_walk *
                                            options.gravity_direction_random_walk * p.pre.dt_s * J_l_inv_g *
                                            J_l_inv_g.transpose();

    EXPECT_MATRIX_NEAR(information, information.transpose(), 0.0);
    EXPECT_EQ(information.llt().info(), Eigen::Success);
    EXPECT_MATRIX_NEAR(information * covariance, Matrix18d::Identity(), 1e-6) << "seed " << seed;
  }
}

}  // namespace
}  // namespace vifusion::imu
