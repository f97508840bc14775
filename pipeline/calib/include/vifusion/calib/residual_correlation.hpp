#pragma once
// Spatial autocorrelation of normalised residual images (NaN = no residual), over pixel lags
// h = (dx, dy) with |dx|, |dy| ≤ max_lag:  ρ(h) = mean x(u)·x(u+h) / mean x(u)², over pixel pairs that both
// hold a residual. From it, camera_noise_model.hpp's two figures:
//   pixels per independent sample  N = Σ_h ρ(h) over the window (the variance inflation of a mean), ≥ 1;
//   correlation length             the lag along the image axes where ρ first falls to 1/e, interpolated
//                                  linearly between whole lags; max_lag when it never does.
// ρ(−h) = ρ(h), so only the half-plane dy > 0 or (dy = 0, dx > 0) is accumulated.

#include <cstdint>
#include <vector>

#include "vifusion/core/image.hpp"

namespace vifusion::calib {

class ResidualCorrelation {
 public:
  /// max_lag in [1, 32] px (std::invalid_argument otherwise).
  explicit ResidualCorrelation(int max_lag_px);

  /// Adds the products of one image's residual pairs.
  void add(ImageView<const float> normalised_residual);

  /// ρ(dx, dy) for |dx|, |dy| ≤ max_lag; 0 where no pair was seen, 1 at (0, 0) once any residual was.
  double correlation(int dx, int dy) const;
  double pixelsPerSample() const;
  double correlationLength_px() const;
  int maxLag_px() const { return max_lag_px_; }
  /// Residuals seen (pairs at lag 0).
  std::int64_t samples() const { return count_[index(0, 0)]; }

 private:
  std::size_t index(int dx, int dy) const;

  int max_lag_px_;
  std::vector<double> product_sum_;  ///< Σ x(u)·x(u+h) per half-plane lag
  std::vector<std::int64_t> count_;  ///< pairs per half-plane lag
};

}  // namespace vifusion::calib
