#pragma once
// Closed-form rigid alignment of two corresponding point sets, without scale (Horn 1987 / Umeyama
// 1991), computed exactly as the TUM benchmark's evaluate_ate.py does so numbers compare 1:1.

#include <vector>

#include <Eigen/Core>

#include "vifusion/core/se3.hpp"

namespace vifusion::eval {

/// T_data_model minimising Σ‖T·model_i − data_i‖². With centred points m'_i, d'_i and
/// W = Σ m'_i d'_iᵀ: SVD Wᵀ = U D Vh, S = I with S₃₃ = −1 if det(U)·det(Vh) < 0 (reflection fix),
/// R = U S Vh, t = d̄ − R m̄.
/// @throws vifusion::Error if the sets differ in size or hold fewer than 3 points.
SE3d alignRigid(const std::vector<Eigen::Vector3d>& model, const std::vector<Eigen::Vector3d>& data);

}  // namespace vifusion::eval
