#pragma once
// Options of the IMU library: the sensor's noise model and the rules for what a sample stream may look
// like, when saturated samples are down-weighted, when a preintegration is redone and how freely the
// gravity direction may move between frames. One struct, so the preintegrator and the error term cannot
// disagree about the noise.

#include <cstdint>

#include "vifusion/core/imu_noise.hpp"

namespace vifusion::imu {

struct ImuOptions {
  /// Continuous-time noise densities and bias random walks, saturation limits, gravity magnitude and the
  /// nominal rate (the paper's Table I; the synthetic column by default).
  ImuNoiseParams noise;
  /// Largest spacing of consecutive samples, in nominal periods 1/noise.rate_hz; a wider spacing is a gap
  /// and is reported, never integrated. 2.5 lets one dropped sample (spacing 2) and driver jitter through,
  /// not two dropped samples in a row. > 1.
  double max_gap_periods = 2.5;
  /// A step whose samples sit at a saturation limit gets its white-noise σ multiplied by this (variance by
  /// its square). A clipped reading says only that the true value is at least the limit, with an error
  /// that is unbounded and one-sided; keeping the sample (dropping it would open a gap) with 100× the σ
  /// (OKVIS's factor) gives it 10⁻⁴ of its normal weight, so the visual terms decide that stretch. ≥ 1.
  double saturation_noise_factor = 100.0;
  /// Re-integrate when ‖b_g − b_g_lin‖·Δt exceeds this [rad] (OKVIS's rule; preintegration.hpp says why).
  /// > 0.
  double reintegrate_above_rad = 1e-4;
  /// Random walk of the gravity direction q_I_W between frames [rad/√s], the only noise on the δg
  /// residual (imu_error.hpp says why it exists and why this size). > 0.
  double gravity_direction_random_walk = 1e-4;

  /// The largest allowed spacing of consecutive samples [ns].
  std::int64_t maxGapNs() const;

  /// @throws vifusion::Error naming the first bad field: noise.* through ImuNoiseParams::validate(), then
  ///         the four densities must be > 0 (the error term inverts the covariance they make), then the
  ///         fields above.
  void validate() const;
};

}  // namespace vifusion::imu
