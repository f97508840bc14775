#pragma once
// Scalar coefficients of the SO(3)/SE(3) closed forms, θ = |φ| [rad] ≥ 0. Private to vifusion::core.
//
// A coefficient multiplying a term of order θᵏ loses ~ε/θᵏ to cancellation in its closed form, i.e.
// ~ε absolute in the product; so the closed forms are used down to θ = kSeriesAngle and a Taylor
// series (truncation < 1e-16 relative at θ = 0.1 with the terms kept) below, which also covers θ = 0.

#include <cmath>

namespace vifusion::detail {

inline constexpr double kSeriesAngle = 0.1;

/// sin(θ/2)/θ: the vector part of exp(φ) per unit φ. No cancellation, only θ = 0 needs the series.
inline double halfSinOverAngle(double theta) {
  if (theta < 1e-4) return 0.5 - theta * theta / 48.0;
  return std::sin(0.5 * theta) / theta;
}

/// (1 − cos θ)/θ², written as 2 sin²(θ/2)/θ², which does not cancel.
inline double oneMinusCosOverAngleSq(double theta) {
  if (theta < 1e-4) return 0.5 - theta * theta / 24.0;
  const double s = std::sin(0.5 * theta) / theta;
  return 2.0 * s * s;
}

/// (θ − sin θ)/θ³.
inline double angleMinusSinOverAngleCubed(double theta) {
  const double t2 = theta * theta;
  if (theta < kSeriesAngle) return 1.0 / 6.0 - t2 * (1.0 / 120.0 - t2 * (1.0 / 5040.0 - t2 / 362880.0));
  return (theta - std::sin(theta)) / (t2 * theta);
}

/// 1/θ² − (1 + cos θ)/(2θ sin θ): the Φ² coefficient of the inverse SO(3) Jacobians. Evaluated as
/// 1/θ² − cos(θ/2)/(2θ sin(θ/2)), because 1 + cos θ loses all but a few digits near θ = π.
inline double inverseJacobianCoefficient(double theta) {
  const double t2 = theta * theta;
  if (theta < kSeriesAngle) return 1.0 / 12.0 + t2 * (1.0 / 720.0 + t2 * (1.0 / 30240.0 + t2 / 1209600.0));
  return 1.0 / t2 - std::cos(0.5 * theta) / (2.0 * theta * std::sin(0.5 * theta));
}

/// (θ² + 2 cos θ − 2)/(2θ⁴), second coefficient of the SE(3) Q block.
inline double se3QCoefficient2(double theta) {
  const double t2 = theta * theta;
  if (theta < kSeriesAngle) return 1.0 / 24.0 - t2 * (1.0 / 720.0 - t2 * (1.0 / 40320.0 - t2 / 3628800.0));
  return (t2 + 2.0 * std::cos(theta) - 2.0) / (2.0 * t2 * t2);
}

/// (2θ − 3 sin θ + θ cos θ)/(2θ⁵), third coefficient of the SE(3) Q block.
inline double se3QCoefficient3(double theta) {
  const double t2 = theta * theta;
  if (theta < kSeriesAngle) return 1.0 / 120.0 - t2 * (1.0 / 2520.0 - t2 * (1.0 / 120960.0 - t2 / 9979200.0));
  return (2.0 * theta - 3.0 * std::sin(theta) + theta * std::cos(theta)) / (2.0 * t2 * t2 * theta);
}

}  // namespace vifusion::detail
