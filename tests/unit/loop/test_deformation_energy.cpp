// The deformation graph's energy terms against numeric differentiation at random, non-identity node
// parameters, and the deformation function φ on deformations with a known answer.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "vifusion/core/numeric_diff.hpp"
#include "vifusion/loop/deformation_energy.hpp"
#include "vifusion/loop/deformation_function.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion::loop {
namespace {

constexpr int kNodes = 7;
constexpr double kRelativeTolerance = 1e-6;

/// Nodes around the origin with affine maps far from the identity: a rotation of up to ~60° times a
/// stretch/shear of up to 20 %, translations up to 10 cm.
struct RandomGraph {
  std::vector<Eigen::Vector3d> positions;
  Eigen::VectorXd params;

  explicit RandomGraph(unsigned seed) : params(kNodeParamDim * kNodes) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const auto vec = [&](double s) { return Eigen::Vector3d(s * u(rng), s * u(rng), s * u(rng)); };
    for (int i = 0; i < kNodes; ++i) {
      positions.push_back(vec(1.5));
      const Eigen::Matrix3d R = Eigen::AngleAxisd(u(rng), vec(1.0).normalized()).toRotationMatrix();
      Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) S(r, c) += 0.2 * u(rng);
      }
      const Eigen::Matrix3d A = R * S;
      params.segment<9>(kNodeParamDim * i + kNodeIdxA) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(A.data());
      params.segment<3>(kNodeParamDim * i + kNodeIdxT) = vec(0.1);
    }
  }

  std::span<const Eigen::Vector3d> nodePositions() const { return positions; }
  NodeParams node(int i) const { return params.segment<kNodeParamDim>(kNodeParamDim * i); }
};

/// Binding to nodes {1, 4, 4, 6}: the repeated node checks that slots sharing a node add up.
NodeBinding<double> testBinding(std::array<std::int32_t, kBoundNodes> nodes) {
  NodeBinding<double> b;
  b.node = nodes;
  b.weight = {0.4, 0.3, 0.2, 0.1};
  return b;
}

/// The full 3 × 12·kNodes Jacobian from per-slot blocks.
Eigen::MatrixXd scatter(const NodeBinding<double>& b, const PointJacobians& J) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(3, kNodeParamDim * kNodes);
  for (int k = 0; k < kBoundNodes; ++k) {
    out.middleCols<kNodeParamDim>(kNodeParamDim * b.node[static_cast<std::size_t>(k)]) +=
        J[static_cast<std::size_t>(k)];
  }
  return out;
}

template <class A, class B>
void expectJacobianNear(const A& analytic, const B& numeric) {
  const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
  EXPECT_MATRIX_NEAR(analytic, numeric, kRelativeTolerance * scale);
}

TEST(DeformationEnergy, RotResidualIsTheFrobeniusNormAndItsJacobianMatches) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const RandomGraph g(seed);
    for (int i = 0; i < kNodes; ++i) {
      const NodeParams x = g.node(i);
      RotJacobian J;
      const RotResidual r = rotResidual(x, &J);
      const Eigen::Map<const Eigen::Matrix3d> A(x.data() + kNodeIdxA);
      EXPECT_NEAR(r.squaredNorm(), (A.transpose() * A - Eigen::Matrix3d::Identity()).squaredNorm(), 1e-12);
      const auto J_num = numericJacobian([](const NodeParams& p) { return rotResidual(p); }, x);
      expectJacobianNear(J, J_num);
    }
  }
}

TEST(DeformationEnergy, RegResidualJacobiansMatch) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const RandomGraph g(seed);
    for (int l = 0; l + 1 < kNodes; ++l) {
      const int n = l + 1;
      const Eigen::Vector3d& g_l = g.positions[static_cast<std::size_t>(l)];
      const Eigen::Vector3d& g_n = g.positions[static_cast<std::size_t>(n)];
      NodeJacobian J_l;
      NodeJacobian J_n;
      regResidual(g_l, g.node(l), g_n, g.node(n), &J_l, &J_n);
      const auto J_l_num =
          numericJacobian([&](const NodeParams& p) { return regResidual(g_l, p, g_n, g.node(n)); }, g.node(l));
      const auto J_n_num =
          numericJacobian([&](const NodeParams& p) { return regResidual(g_l, g.node(l), g_n, p); }, g.node(n));
      expectJacobianNear(J_l, J_l_num);
      expectJacobianNear(J_n, J_n_num);
    }
  }
}

TEST(DeformationEnergy, ImuResidualJacobianMatches) {
  const Eigen::Vector3d g_W(0.3, -9.7, 1.2);
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const RandomGraph g(seed);
    for (int i = 0; i < kNodes; ++i) {
      NodeJacobian J;
      imuResidual(g.node(i), g_W, &J);
      const auto J_num = numericJacobian([&](const NodeParams& p) { return imuResidual(p, g_W); }, g.node(i));
      expectJacobianNear(J, J_num);
    }
  }
}

TEST(DeformationEnergy, PointTermJacobiansMatch) {
  const Eigen::Vector3d p(0.4, -0.7, 1.1);
  const Eigen::Vector3d q(-0.2, 0.5, 0.3);
  const Eigen::Vector3d target(0.5, -0.6, 1.0);
  const NodeBinding<double> b_p = testBinding({1, 4, 4, 6});
  const NodeBinding<double> b_q = testBinding({0, 4, 2, 3});
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const RandomGraph g(seed);
    const auto spanOf = [](const Eigen::VectorXd& x) { return std::span<const double>(x.data(), x.size()); };

    PointJacobians J;
    conResidual(p, b_p, g.nodePositions(), spanOf(g.params), target, &J);
    expectJacobianNear(scatter(b_p, J), numericJacobian(
                                            [&](const Eigen::VectorXd& x) {
                                              return conResidual(p, b_p, g.nodePositions(), spanOf(x), target);
                                            },
                                            g.params));

    pinResidual(p, b_p, g.nodePositions(), spanOf(g.params), &J);
    expectJacobianNear(
        scatter(b_p, J),
        numericJacobian([&](const Eigen::VectorXd& x) { return pinResidual(p, b_p, g.nodePositions(), spanOf(x)); },
                        g.params));

    PointJacobians J_b;
    relResidual(p, b_p, q, b_q, g.nodePositions(), spanOf(g.params), &J, &J_b);
    expectJacobianNear(
        Eigen::MatrixXd(scatter(b_p, J) + scatter(b_q, J_b)),
        numericJacobian(
            [&](const Eigen::VectorXd& x) { return relResidual(p, b_p, q, b_q, g.nodePositions(), spanOf(x)); },
            g.params));
  }
}

TEST(DeformationFunction, IdentityLeavesEverythingAndARigidMotionIsReproducedExactly) {
  const RandomGraph g(3);
  const NodeBinding<double> b = testBinding({1, 4, 4, 6});
  const Eigen::Vector3d p(0.4, -0.7, 1.1);
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, 0.9, -0.3).normalized();
  const SE3d T_W_C(Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())),
                   Eigen::Vector3d(0.4, -0.7, 1.1));

  Eigen::VectorXd params(kNodeParamDim * kNodes);
  for (int i = 0; i < kNodes; ++i) params.segment<kNodeParamDim>(kNodeParamDim * i) = identityNodeParams<double>();
  std::span<const double> x(params.data(), params.size());
  EXPECT_MATRIX_NEAR(deformPoint<double>(p, b, g.nodePositions(), x), p, 1e-15);
  EXPECT_MATRIX_NEAR(deformNormal<double>(n, b, x), n, 1e-15);

  // Every node moved by the same rigid motion T = (R, τ): A_i = R, t_i = R g_i + τ − g_i.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.5, Eigen::Vector3d(-1, 1, 2).normalized()).toRotationMatrix();
  const Eigen::Vector3d tau(0.1, -0.2, 0.05);
  for (int i = 0; i < kNodes; ++i) {
    const Eigen::Vector3d& g_i = g.positions[static_cast<std::size_t>(i)];
    params.segment<9>(kNodeParamDim * i + kNodeIdxA) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(R.data());
    params.segment<3>(kNodeParamDim * i + kNodeIdxT) = R * g_i + tau - g_i;
  }
  EXPECT_MATRIX_NEAR(deformPoint<double>(p, b, g.nodePositions(), x), R * p + tau, 1e-12);
  EXPECT_MATRIX_NEAR(deformNormal<double>(n, b, x), R * n, 1e-12);
  const SE3d moved = deformPose(T_W_C, b, g.nodePositions(), x);
  EXPECT_ROTATION_NEAR(moved.quaternion(), Eigen::Quaterniond(R) * T_W_C.quaternion(), 1e-12);
  EXPECT_MATRIX_NEAR(moved.translation(), R * T_W_C.translation() + tau, 1e-12);
}

TEST(DeformationFunction, OrthonormaliseGivesTheNearestRotation) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Matrix3d M = 1.3 * R;  // a scaled rotation's nearest rotation is the rotation
  EXPECT_MATRIX_NEAR(orthonormalise(M), R, 1e-12);
  const Eigen::Matrix3d reflection = -Eigen::Matrix3d::Identity();
  EXPECT_NEAR(orthonormalise(reflection).determinant(), 1.0, 1e-12);
  Eigen::Matrix3d bad = Eigen::Matrix3d::Identity();
  bad(0, 1) = std::nan("");
  EXPECT_MATRIX_NEAR(orthonormalise(bad), Eigen::Matrix3d::Identity(), 0.0);
}

}  // namespace
}  // namespace vifusion::loop
