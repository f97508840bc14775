#pragma once
// 6-parameter normal equations H δ = b (H = Jᵀ W J, b = Jᵀ W r) as reduced on the GPU: each
// workgroup writes kTerms fp32 sums (layout: shaders/include/reduce/normal_equations.glsl) and
// the host adds the partials in double, so precision is lost only within one workgroup.

#include <Eigen/Core>
#include <cstdint>
#include <span>

namespace vifusion {

struct NormalEquations6 {
  static constexpr int kTerms = 30;   ///< 21 (upper H) + 6 (b) + Σ w r² + inliers + candidates
  static constexpr int kStride = 32;  ///< floats per workgroup partial (padded)

  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();  ///< Jᵀ W J
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();  ///< Jᵀ W r
  double weighted_squared_residual = 0.0;                               ///< Σ w r²
  double inliers = 0.0;                                                 ///< rows with w > 0
  double candidates = 0.0;  ///< rows offered with valid input, accepted or not (health ratios)

  NormalEquations6& operator+=(const NormalEquations6& other);
  /// Adds one row J (1×6) with residual r and weight w (w ≤ 0: skipped, as on the GPU).
  void addRow(const Eigen::Matrix<double, 6, 1>& J, double r, double w);
  /// Counts an item with valid input that the gates may still reject.
  void addCandidate() { candidates += 1.0; }
  /// Adds `groups` partials of kStride floats each, summing in double.
  void addPartials(std::span<const float> partials, uint32_t groups);
};

}  // namespace vifusion
