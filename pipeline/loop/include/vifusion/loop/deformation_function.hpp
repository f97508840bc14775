#pragma once
// The deformation function φ of the deformation graph (Sumner et al. 2007 as used by ElasticFusion and
// Laidlow et al. 2017 §V), the CPU reference of the GPU surfel-deformation shader.
//
// Node i has a position g_i in W [m] (fixed when the graph is built) and 12 parameters: an affine 3×3
// matrix A_i (identity = no deformation; near a rotation after optimisation, E_rot makes it so) and a
// translation t_i in W [m] (0 = no deformation). A point p_W bound to nodes i with weights w_i
// (node_binding.hpp) moves to
//
//   φ(p) = Σ_i w_i (A_i (p − g_i) + g_i + t_i),
//
// a normal to n' = normalize(Σ_i w_i A_i⁻ᵀ n) (normals transform with the inverse transpose), and a camera
// pose T_W_C to R' = orthonormalise(Σ_i w_i A_i) · R_W_C with its position moved by φ.
//
// Parameter layout of node i inside the flat parameter array: 12 consecutive values from 12·i, A
// column-major (GLSL's mat3 order) at kNodeIdxA, t at kNodeIdxT.

#include <Eigen/Core>
#include <span>

#include "vifusion/core/se3.hpp"
#include "vifusion/loop/node_binding.hpp"

namespace vifusion::loop {

inline constexpr int kNodeParamDim = 12;  ///< unknowns per node
inline constexpr int kNodeIdxA = 0;       ///< A_i, 9 entries column-major: A(r, c) at kNodeIdxA + 3·c + r
inline constexpr int kNodeIdxT = 9;       ///< t_i in W [m], 3 entries

template <class T>
using NodeParamsT = Eigen::Matrix<T, kNodeParamDim, 1>;
using NodeParams = NodeParamsT<double>;

/// The parameters of an undeformed node: A = I, t = 0.
template <class T>
NodeParamsT<T> identityNodeParams() {
  NodeParamsT<T> x = NodeParamsT<T>::Zero();
  x[kNodeIdxA + 0] = T(1);
  x[kNodeIdxA + 4] = T(1);
  x[kNodeIdxA + 8] = T(1);
  return x;
}

/// A_i of node `node` in the flat parameter array.
template <class T>
Eigen::Map<const Eigen::Matrix<T, 3, 3>> nodeAffine(std::span<const T> params, int node) {
  return Eigen::Map<const Eigen::Matrix<T, 3, 3>>(params.data() + kNodeParamDim * node + kNodeIdxA);
}

/// t_i of node `node` in the flat parameter array [m].
template <class T>
Eigen::Map<const Vector3<T>> nodeTranslation(std::span<const T> params, int node) {
  return Eigen::Map<const Vector3<T>>(params.data() + kNodeParamDim * node + kNodeIdxT);
}

/// φ(p_W) [m, W] for a point bound by `binding` to nodes with positions node_positions_W and parameters
/// node_params (12 per node).
template <class T>
Vector3<T> deformPoint(const Vector3<T>& p_W, const NodeBinding<T>& binding,
                       std::span<const Vector3<T>> node_positions_W, std::span<const T> node_params) {
  Vector3<T> out = Vector3<T>::Zero();
  for (int k = 0; k < kBoundNodes; ++k) {
    const int i = binding.node[static_cast<std::size_t>(k)];
    const Vector3<T>& g = node_positions_W[static_cast<std::size_t>(i)];
    out += binding.weight[static_cast<std::size_t>(k)] *
           (nodeAffine(node_params, i) * (p_W - g) + g + nodeTranslation(node_params, i));
  }
  return out;
}

/// normalize(Σ w_i A_i⁻ᵀ n_W). A (near-)singular A_i means a broken deformation (E_rot keeps A_i near a
/// rotation); a zero result returns n_W unchanged rather than a NaN.
template <class T>
Vector3<T> deformNormal(const Vector3<T>& n_W, const NodeBinding<T>& binding, std::span<const T> node_params) {
  Vector3<T> out = Vector3<T>::Zero();
  for (int k = 0; k < kBoundNodes; ++k) {
    const int i = binding.node[static_cast<std::size_t>(k)];
    const Eigen::Matrix<T, 3, 3> A = nodeAffine(node_params, i);
    out += binding.weight[static_cast<std::size_t>(k)] * (A.inverse().transpose() * n_W);
  }
  const T norm = out.norm();
  return norm > T(0) ? Vector3<T>(out / norm) : n_W;
}

/// Σ w_i A_i, the blended linear part used for camera rotations.
template <class T>
Eigen::Matrix<T, 3, 3> blendedAffine(const NodeBinding<T>& binding, std::span<const T> node_params) {
  Eigen::Matrix<T, 3, 3> M = Eigen::Matrix<T, 3, 3>::Zero();
  for (int k = 0; k < kBoundNodes; ++k) {
    M += binding.weight[static_cast<std::size_t>(k)] *
         nodeAffine(node_params, binding.node[static_cast<std::size_t>(k)]);
  }
  return M;
}

/// The rotation nearest to M in the Frobenius norm (U·Vᵀ of its SVD, det +1); identity for a non-finite M.
Eigen::Matrix3d orthonormalise(const Eigen::Matrix3d& M);

/// A camera pose T_W_C moved with the map: R' = orthonormalise(Σ w_i A_i)·R_W_C, r' = φ(r_W_C). `binding`
/// binds the camera position (with the frame's index as its time).
SE3d deformPose(const SE3d& T_W_C, const NodeBinding<double>& binding,
                std::span<const Eigen::Vector3d> node_positions_W, std::span<const double> node_params);

}  // namespace vifusion::loop
