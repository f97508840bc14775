#pragma once
// When an iterative pose solve has converged: its last step is smaller than the estimate's own uncertainty.
//
// A Gauss-Newton step δ over a pose whose terms are weighted by their inverse measurement variances has the
// information H = JᵀWJ; the estimate's covariance is H⁻¹, so δᵀHδ is the step's squared Mahalanobis length
// in units of that uncertainty. A draw from N(0, H⁻¹) has δᵀHδ ~ χ²(6); a step below the 0.01 quantile is
// shorter than 99 % of such draws — indistinguishable from the estimate's noise, and a further iteration only
// moves the pose within it. H of the dense terms counts every pixel as independent, so it is over-confident
// and the test errs on the side of iterating longer. A test in metres and radians cannot do this: the same
// 10 µm is noise for a view of a far wall and signal for a desk at 0.4 m.

#include "vifusion/core/se3.hpp"

namespace vifusion {

/// The 0.01 quantile of χ² with 6 degrees of freedom (the inverse of the regularised lower incomplete gamma
/// function P(3, x/2) at 0.01).
inline constexpr double kChi2SixDofQuantile001 = 0.8721;

/// True when the step's squared Mahalanobis length δᵀHδ under the information H is below `max_chi2`.
inline bool stepWithinUncertainty(const Vector6d& step, const Matrix6d& information, double max_chi2) {
  return step.dot(information * step) < max_chi2;
}

}  // namespace vifusion
