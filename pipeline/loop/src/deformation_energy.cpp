#include "vifusion/loop/deformation_energy.hpp"

#include <cmath>
#include <numbers>

namespace vifusion::loop {
namespace {

/// ∂(A·v)/∂(A's column-major entries) = [v₀I, v₁I, v₂I], written into the A columns of J (times `scale`).
void setAffineColumns(const Eigen::Vector3d& v, double scale, NodeJacobian& J) {
  for (int c = 0; c < 3; ++c) {
    J.block<3, 3>(0, kNodeIdxA + 3 * c) = (scale * v[c]) * Eigen::Matrix3d::Identity();
  }
}

/// ∂φ(p)/∂(parameters of each bound node): w_k [(p − g)₀I, (p − g)₁I, (p − g)₂I, I], times `sign`.
void pointJacobians(const Eigen::Vector3d& p_W, const NodeBinding<double>& binding,
                    std::span<const Eigen::Vector3d> node_positions_W, double sign, PointJacobians& J) {
  for (int k = 0; k < kBoundNodes; ++k) {
    const auto s = static_cast<std::size_t>(k);
    const double w = sign * binding.weight[s];
    NodeJacobian& Jk = J[s];
    setAffineColumns(p_W - node_positions_W[static_cast<std::size_t>(binding.node[s])], w, Jk);
    Jk.block<3, 3>(0, kNodeIdxT) = w * Eigen::Matrix3d::Identity();
  }
}

}  // namespace

RotResidual rotResidual(const NodeParams& x, RotJacobian* J) {
  const auto c0 = x.segment<3>(kNodeIdxA + 0);
  const auto c1 = x.segment<3>(kNodeIdxA + 3);
  const auto c2 = x.segment<3>(kNodeIdxA + 6);
  constexpr double kSqrt2 = std::numbers::sqrt2;
  RotResidual r;
  r << c0.dot(c0) - 1.0, c1.dot(c1) - 1.0, c2.dot(c2) - 1.0, kSqrt2 * c0.dot(c1), kSqrt2 * c0.dot(c2),
      kSqrt2 * c1.dot(c2);
  if (J != nullptr) {
    J->setZero();
    J->block<1, 3>(0, kNodeIdxA + 0) = 2.0 * c0.transpose();
    J->block<1, 3>(1, kNodeIdxA + 3) = 2.0 * c1.transpose();
    J->block<1, 3>(2, kNodeIdxA + 6) = 2.0 * c2.transpose();
    J->block<1, 3>(3, kNodeIdxA + 0) = kSqrt2 * c1.transpose();
    J->block<1, 3>(3, kNodeIdxA + 3) = kSqrt2 * c0.transpose();
    J->block<1, 3>(4, kNodeIdxA + 0) = kSqrt2 * c2.transpose();
    J->block<1, 3>(4, kNodeIdxA + 6) = kSqrt2 * c0.transpose();
    J->block<1, 3>(5, kNodeIdxA + 3) = kSqrt2 * c2.transpose();
    J->block<1, 3>(5, kNodeIdxA + 6) = kSqrt2 * c1.transpose();
  }
  return r;
}

Eigen::Vector3d regResidual(const Eigen::Vector3d& g_l_W, const NodeParams& x_l, const Eigen::Vector3d& g_n_W,
                            const NodeParams& x_n, NodeJacobian* J_l, NodeJacobian* J_n) {
  const Eigen::Map<const Eigen::Matrix3d> A_l(x_l.data() + kNodeIdxA);
  const Eigen::Vector3d d = g_n_W - g_l_W;
  const Eigen::Vector3d r = A_l * d + g_l_W + x_l.segment<3>(kNodeIdxT) - (g_n_W + x_n.segment<3>(kNodeIdxT));
  if (J_l != nullptr) {
    setAffineColumns(d, 1.0, *J_l);
    J_l->block<3, 3>(0, kNodeIdxT).setIdentity();
  }
  if (J_n != nullptr) {
    J_n->setZero();
    J_n->block<3, 3>(0, kNodeIdxT) = -Eigen::Matrix3d::Identity();
  }
  return r;
}

Eigen::Vector3d imuResidual(const NodeParams& x, const Eigen::Vector3d& g_W, NodeJacobian* J) {
  const Eigen::Map<const Eigen::Matrix3d> A(x.data() + kNodeIdxA);
  if (J != nullptr) {
    setAffineColumns(g_W, 1.0, *J);
    J->block<3, 3>(0, kNodeIdxT).setZero();
  }
  return A * g_W - g_W;
}

Eigen::Vector3d conResidual(const Eigen::Vector3d& source_W, const NodeBinding<double>& binding,
                            std::span<const Eigen::Vector3d> node_positions_W, std::span<const double> node_params,
                            const Eigen::Vector3d& target_W, PointJacobians* J) {
  if (J != nullptr) pointJacobians(source_W, binding, node_positions_W, 1.0, *J);
  return deformPoint<double>(source_W, binding, node_positions_W, node_params) - target_W;
}

Eigen::Vector3d pinResidual(const Eigen::Vector3d& p_W, const NodeBinding<double>& binding,
                            std::span<const Eigen::Vector3d> node_positions_W, std::span<const double> node_params,
                            PointJacobians* J) {
  return conResidual(p_W, binding, node_positions_W, node_params, p_W, J);
}

Eigen::Vector3d relResidual(const Eigen::Vector3d& a_W, const NodeBinding<double>& binding_a,
                            const Eigen::Vector3d& b_W, const NodeBinding<double>& binding_b,
                            std::span<const Eigen::Vector3d> node_positions_W, std::span<const double> node_params,
                            PointJacobians* J_a, PointJacobians* J_b) {
  if (J_a != nullptr) pointJacobians(a_W, binding_a, node_positions_W, 1.0, *J_a);
  if (J_b != nullptr) pointJacobians(b_W, binding_b, node_positions_W, -1.0, *J_b);
  return deformPoint<double>(a_W, binding_a, node_positions_W, node_params) -
         deformPoint<double>(b_W, binding_b, node_positions_W, node_params);
}

}  // namespace vifusion::loop
