#pragma once
// The deformation graph's energy terms (ElasticFusion; Laidlow et al. 2017 §V, eq. 12–17), each as a
// residual with its analytic Jacobian w.r.t. the 12 parameters of every node it involves (layout in
// deformation_function.hpp: A column-major at kNodeIdxA, t at kNodeIdxT). The solver minimises
//
//   E = ω_rot E_rot + ω_reg E_reg + ω_con (E_con + E_pin + E_rel) + ω_imu E_imu,   E_x = Σ ‖r_x‖²,
//
// so a weight ω enters the normal equations as ω·JᵀJ and ω·Jᵀr. Positions are in W [m]; A is unitless.
//
//   E_rot  6 rows per node: the independent entries of AᵀA − I, i.e. c_a·c_b − δ_ab for the columns c of A,
//          the three off-diagonal rows scaled by √2 so that ‖r‖² = ‖AᵀA − I‖²_F exactly (the paper's E_rot;
//          each off-diagonal entry appears twice in the Frobenius norm).
//   E_reg  3 rows per directed edge l → n: A_l (g_n − g_l) + g_l + t_l − (g_n + t_n) [m].
//   E_con  3 rows per constraint: φ(source) − target [m].
//   E_pin  3 rows per pin: φ(p) − p [m] (ElasticFusion pins the inactive map's targets in place).
//   E_rel  3 rows per relative constraint: φ(a) − φ(b) [m] (both ends deformed).
//   E_imu  3 rows per node: A g_W − g_W [m/s²], g_W gravity in W: the node's linear part may not turn
//          the direction of gravity (the paper's term). With |g_W| = 9.81 m/s² a node tilted by θ [rad]
//          costs ω_imu·96·θ², as much as a constraint error of 9.8·θ [m] at ω_con = ω_imu.
//
// All functions are pure: no allocation, no state.

#include <Eigen/Core>
#include <array>
#include <span>

#include "vifusion/loop/deformation_function.hpp"
#include "vifusion/loop/node_binding.hpp"

namespace vifusion::loop {

inline constexpr int kRotResidualDim = 6;

using RotResidual = Eigen::Matrix<double, kRotResidualDim, 1>;
using RotJacobian = Eigen::Matrix<double, kRotResidualDim, kNodeParamDim>;
/// ∂(3-row residual)/∂(one node's 12 parameters).
using NodeJacobian = Eigen::Matrix<double, 3, kNodeParamDim>;
/// One NodeJacobian per bound node slot of a point's NodeBinding (slots repeating a node add up).
using PointJacobians = std::array<NodeJacobian, kBoundNodes>;

/// E_rot residual of one node and, optionally, its 6×12 Jacobian (the t columns are 0).
RotResidual rotResidual(const NodeParams& x, RotJacobian* J = nullptr);

/// E_reg residual of the directed edge from node l (position g_l_W, parameters x_l) to its neighbour n.
Eigen::Vector3d regResidual(const Eigen::Vector3d& g_l_W, const NodeParams& x_l, const Eigen::Vector3d& g_n_W,
                            const NodeParams& x_n, NodeJacobian* J_l = nullptr, NodeJacobian* J_n = nullptr);

/// E_imu residual of one node for gravity g_W [m/s², W] (the t columns of J are 0).
Eigen::Vector3d imuResidual(const NodeParams& x, const Eigen::Vector3d& g_W, NodeJacobian* J = nullptr);

/// E_con residual φ(source_W) − target_W [m]; J[k] = ∂r/∂(parameters of binding.node[k]).
Eigen::Vector3d conResidual(const Eigen::Vector3d& source_W, const NodeBinding<double>& binding,
                            std::span<const Eigen::Vector3d> node_positions_W, std::span<const double> node_params,
                            const Eigen::Vector3d& target_W, PointJacobians* J = nullptr);

/// E_pin residual φ(p_W) − p_W [m].
Eigen::Vector3d pinResidual(const Eigen::Vector3d& p_W, const NodeBinding<double>& binding,
                            std::span<const Eigen::Vector3d> node_positions_W, std::span<const double> node_params,
                            PointJacobians* J = nullptr);

/// E_rel residual φ(a_W) − φ(b_W) [m]; J_a for a's bound nodes, J_b for b's.
Eigen::Vector3d relResidual(const Eigen::Vector3d& a_W, const NodeBinding<double>& binding_a,
                            const Eigen::Vector3d& b_W, const NodeBinding<double>& binding_b,
                            std::span<const Eigen::Vector3d> node_positions_W, std::span<const double> node_params,
                            PointJacobians* J_a = nullptr, PointJacobians* J_b = nullptr);

}  // namespace vifusion::loop
