#pragma once
// Uniform B-spline trajectory of the IMU body S in a world W, in the split representation:
//
//   p_W_S(t) = Σ_{j=0}^{k−1} b_j(u) · p_{s+j}                       (R³ B-spline)
//   R_W_S(t) = R_s · Π_{j=1}^{k−1} Exp(λ_j(u) · d_{s+j}),  d_i = Log(R_{i−1}ᵀ R_i)   (cumulative SO(3) B-spline)
//
// for t in segment s, u = (t − t0 − s·Δt)/Δt ∈ [0, 1], with b_j the uniform B-spline basis of order k and
// λ_j = Σ_{l≥j} b_l its cumulative form (Kim, Kim & Shin 1995; Sommer et al. 2020, "Efficient Derivative
// Computation for Cumulative B-Splines on Lie Groups"). Segment s uses control points s … s+k−1, so n control
// points give n − k + 1 segments and the spline is defined on [t0, t0 + (n − k + 1)·Δt].
//
// Order k = 6 (quintic, as Kalibr's pose spline): position and rotation are C⁴, so the accelerometer signal
// (p̈) is C² and the gyroscope signal (ω, a first derivative) is C³ across knots. A cubic (k = 4) would give
// an accelerometer signal that is only C⁰ with jerk steps at every knot — not what a physical IMU sees, and
// it costs an IMU integrator using higher-order sample interpolation its accuracy at each knot. Quintic
// rather than quartic (Basalt) keeps the jerk (the derivative of the accelerometer signal) continuous too,
// for one more control point per evaluation, which is nothing at simulation rates.
//
// Derivatives are analytic: p⁽ⁿ⁾ from the n-th derivative of the basis polynomials (blending matrix), the
// body angular velocity and acceleration from the recursion over the k − 1 factors of the product
// (ω_j = A_jᵀ ω_{j−1} + λ̇_j d_j, A_j = Exp(λ_j d_j)).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "vifusion/core/se3.hpp"

namespace vifusion::sim {

class Se3Spline {
 public:
  static constexpr int kOrder = 6;  ///< k: polynomial degree k − 1 = 5 (quintic)

  using BasisVector = Eigen::Matrix<double, kOrder, 1>;
  /// A quadratic form over a segment's k − 1 increments Δ_j = c_{s+j} − c_{s+j−1} (j = 1 … k − 1).
  using IncrementMatrix = Eigen::Matrix<double, kOrder - 1, kOrder - 1>;

  /// Everything an IMU simulator needs at one instant.
  struct Kinematics {
    SE3d T_W_S;                                                ///< pose of S in W
    Eigen::Vector3d v_W_mps = Eigen::Vector3d::Zero();         ///< velocity of S in W [m/s]
    Eigen::Vector3d a_W_mps2 = Eigen::Vector3d::Zero();        ///< acceleration of S in W [m/s²]
    Eigen::Vector3d omega_S_rad_s = Eigen::Vector3d::Zero();   ///< angular velocity of S w.r.t. W, in S [rad/s]
    Eigen::Vector3d alpha_S_rad_s2 = Eigen::Vector3d::Zero();  ///< its time derivative, in S [rad/s²]
  };

  /// Where a time falls: the first control point of its segment and the basis weights b_j(u), so that
  /// p(t) = Σ_j weights[j] · p_{first_control + j}. Used by least-squares fitting.
  struct SegmentWeights {
    int first_control = 0;
    BasisVector weights = BasisVector::Zero();
  };

  /// Right-perturbation Jacobians of R_W_S(t): perturbing control rotation first_control + m as
  /// R ← R·Exp(δ_m) changes the spline rotation to R_W_S(t)·Exp(Σ_m d_R_d_control[m]·δ_m) to first order.
  struct RotationJacobians {
    int first_control = 0;
    std::array<Eigen::Matrix3d, kOrder> d_R_d_control{};
  };

  /// @param t0_ns         time of the first knot, where the spline begins [ns]
  /// @param dt_ns         knot spacing [ns], > 0
  /// @param p_W_m         control positions [m]
  /// @param q_W_S         control rotations (normalised here); consecutive ones must differ by less than π
  /// @throws vifusion::Error if dt_ns ≤ 0, the two lists differ in length or hold fewer than kOrder points.
  Se3Spline(std::int64_t t0_ns, std::int64_t dt_ns, std::vector<Eigen::Vector3d> p_W_m,
            std::vector<Eigen::Quaterniond> q_W_S);

  std::int64_t startTimeNs() const { return t0_ns_; }
  std::int64_t endTimeNs() const { return t0_ns_ + numSegments() * dt_ns_; }
  std::int64_t knotSpacingNs() const { return dt_ns_; }
  int numSegments() const { return static_cast<int>(p_W_m_.size()) - kOrder + 1; }
  const std::vector<Eigen::Vector3d>& controlPositions() const { return p_W_m_; }
  const std::vector<Eigen::Quaterniond>& controlRotations() const { return q_W_S_; }

  /// Roughness of one segment: ∫₀¹ |dⁿ/duⁿ Σ_j λ_j(u)·Δ_j|² du = Σ_{j,l} Q(j, l)·Δ_jᵀΔ_l for n = derivative_order
  /// ≥ 1 (the constant control point of the cumulative form drops out). Divide by Δt^(2n−1) [s] for the
  /// time integral ∫|dⁿp/dtⁿ|² dt over the segment. Exact for positions; for rotations, with Δ_j = d_j, it
  /// is the same energy of the rotation-vector curve R_s·Exp(Σ_j λ_j d_j), which the cumulative spline
  /// follows to first order in the increments.
  static IncrementMatrix roughnessMatrix(int derivative_order);

  /// Control point m's basis function is centred at t0 + (m − (k − 2)/2)·Δt: the time a control point
  /// "belongs to", used to initialise fits.
  std::int64_t controlCentreTimeNs(int m) const;

  /// All of the following throw vifusion::Error if t_ns lies outside [startTimeNs(), endTimeNs()]. A time
  /// on an inner knot is evaluated in the segment that starts there; endTimeNs() in the last segment.
  SegmentWeights basisWeights(std::int64_t t_ns) const;
  SE3d pose(std::int64_t t_ns) const;
  Eigen::Vector3d position(std::int64_t t_ns) const;
  /// R_W_S(t); with J ≠ nullptr also its Jacobians w.r.t. the control rotations.
  Eigen::Quaterniond orientation(std::int64_t t_ns, RotationJacobians* J = nullptr) const;
  Kinematics kinematics(std::int64_t t_ns) const;

 private:
  struct SegmentTime {
    int segment = 0;
    double u = 0.0;  ///< normalised time in the segment, [0, 1]
  };
  SegmentTime locate(std::int64_t t_ns) const;

  std::int64_t t0_ns_;
  std::int64_t dt_ns_;
  std::vector<Eigen::Vector3d> p_W_m_;
  std::vector<Eigen::Quaterniond> q_W_S_;
  /// d_rad_[i] = Log(R_iᵀ R_{i+1}) [rad], cached because every evaluation needs k − 1 of them.
  std::vector<Eigen::Vector3d> d_rad_;
};

}  // namespace vifusion::sim
