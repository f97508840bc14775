#pragma once
// 6-parameter normal equations H δ = b (H = Jᵀ W J, b = Jᵀ W r) as reduced on the GPU: each
// workgroup writes kTerms fp32 sums (layout: shaders/include/reduce/normal_equations.glsl) and
// the host adds the partials in double, so precision is lost only within one workgroup.

#include <Eigen/Core>
#include <cstdint>
#include <span>

namespace vifusion {

struct NormalEquations6 {
  static constexpr int kTerms = 31;   ///< 21 (upper H) + 6 (b) + Σ w r² + inliers + candidates + Σ w e²
  static constexpr int kStride = 32;  ///< floats per workgroup partial (padded)

  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();  ///< Jᵀ W J
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();  ///< Jᵀ W r
  double weighted_squared_residual = 0.0;                               ///< Σ w r²
  double inliers = 0.0;                                                 ///< rows with w > 0
  double candidates = 0.0;  ///< rows offered with valid input, accepted or not (health ratios)
  /// Σ w e², e ≥ 0 a bound on each row's systematic error in r's units (0 for kernels that give none). A
  /// solution's systematic error δ then has δᵀHδ ≤ Σ w e² (Cauchy–Schwarz), whatever the errors' pattern.
  double weighted_squared_bound = 0.0;

  NormalEquations6& operator+=(const NormalEquations6& other);
  /// Adds one row J (1×6) with residual r, weight w (w ≤ 0: skipped, as on the GPU) and systematic-error
  /// bound e.
  void addRow(const Eigen::Matrix<double, 6, 1>& J, double r, double w, double e = 0.0);
  /// Counts an item with valid input that the gates may still reject.
  void addCandidate() { candidates += 1.0; }
  /// Adds `groups` partials of kStride floats each, summing in double.
  void addPartials(std::span<const float> partials, uint32_t groups);
};

}  // namespace vifusion
