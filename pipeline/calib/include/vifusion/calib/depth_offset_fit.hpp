#pragma once
// Weighted least squares for the offsets a depth image carries as a whole: the inverse-depth bias b [1/m] and
// the shift s [px] of where the image reads the surface (ι_obs(u) = ι(u + s)), from pair residuals
// r ≈ (k, ∂r/∂s_x, ∂r/∂s_y)·(b, s_x, s_y) (pair_residuals.hpp). Why both: a structured-light sensor fills each
// pixel from a projector dot up to a cell away, and any preference in that fill (or a depth-to-colour
// registration error) reads sloped surfaces off by ∇ι·s, which changes between two views much as the bias
// does; fitted alone, b takes up part of it.
//
// Covariance. A pair's residuals share errors across the whole image (a depth staircase, the dot pattern), so
// pixels are far from independent for these three numbers. The covariance is the cluster-robust (sandwich) one
// with each pair a cluster: H⁻¹ (P/(P − 1)·Σ_p g_p g_pᵀ) H⁻¹, g_p = Σ_{i∈p} w_i J_i (r_i − J_i·θ), which holds
// whatever the pixels of one pair share, as long as different pairs' errors are independent.

#include <Eigen/Core>
#include <Eigen/QR>
#include <vector>

namespace vifusion::calib {

struct DepthOffsets {
  using Vector = Eigen::Vector3d;  ///< (b [1/m], s_x [px], s_y [px])
  Vector value = Vector::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  ///< zero with fewer than two pairs
};

class DepthOffsetFit {
 public:
  /// Starts a new cluster; add() goes to the latest one.
  void beginPair() { pairs_.push_back({}); }

  /// One residual r with its row J = ∂r/∂(b, s_x, s_y) and weight w = 1/var(r). Needs beginPair() first.
  void add(const DepthOffsets::Vector& row, double residual, double weight) {
    Pair& pair = pairs_.back();
    pair.normal += weight * row * row.transpose();
    pair.rhs += weight * row * residual;
  }

  /// The least-squares offsets and their clustered covariance; a direction no pair constrains (a pseudo-inverse's
  /// null space, e.g. the shift when no pair saw a sloped surface) comes out 0 with covariance 0.
  DepthOffsets solve() const {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    DepthOffsets::Vector rhs = DepthOffsets::Vector::Zero();
    for (const Pair& pair : pairs_) {
      normal += pair.normal;
      rhs += pair.rhs;
    }
    DepthOffsets out;
    if (pairs_.empty()) return out;
    const Eigen::Matrix3d inverse = normal.completeOrthogonalDecomposition().pseudoInverse();
    out.value = inverse * rhs;
    if (pairs_.size() < 2) return out;
    Eigen::Matrix3d meat = Eigen::Matrix3d::Zero();
    for (const Pair& pair : pairs_) {
      const DepthOffsets::Vector score = pair.rhs - pair.normal * out.value;
      meat += score * score.transpose();
    }
    const double count = static_cast<double>(pairs_.size());
    out.covariance = inverse * (count / (count - 1.0) * meat) * inverse;
    return out;
  }

 private:
  struct Pair {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    DepthOffsets::Vector rhs = DepthOffsets::Vector::Zero();
  };
  std::vector<Pair> pairs_;
};

}  // namespace vifusion::calib
