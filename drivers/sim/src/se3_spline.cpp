#include "vifusion/sim/se3_spline.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "vifusion/core/error.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::sim {
namespace {

constexpr int kK = Se3Spline::kOrder;
using BasisMatrix = Eigen::Matrix<double, kK, kK>;
using BasisVector = Se3Spline::BasisVector;

double binomial(int n, int r) {
  double result = 1.0;
  for (int i = 1; i <= r; ++i) result = result * (n - r + i) / i;
  return result;
}

double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

/// Blending matrix of the uniform B-spline of order k (Qin 2000, "General matrix representations for
/// B-splines"): b_j(u) = Σ_n M(j, n)·uⁿ is the weight of the segment's j-th control point.
BasisMatrix makeBlendingMatrix() {
  BasisMatrix M;
  for (int j = 0; j < kK; ++j) {
    for (int n = 0; n < kK; ++n) {
      double sum = 0.0;
      for (int s = j; s < kK; ++s) {
        const double sign = ((s - j) % 2 == 0) ? 1.0 : -1.0;
        sum += sign * binomial(kK, s - j) * std::pow(static_cast<double>(kK - 1 - s), kK - 1 - n);
      }
      M(j, n) = binomial(kK - 1, n) * sum / factorial(kK - 1);
    }
  }
  return M;
}

/// Cumulative form: λ_j(u) = Σ_{l≥j} b_l(u), so λ_0 ≡ 1.
BasisMatrix makeCumulativeMatrix(const BasisMatrix& M) {
  BasisMatrix C = M;
  for (int j = kK - 2; j >= 0; --j) C.row(j) += C.row(j + 1);
  return C;
}

const BasisMatrix& blending() {
  static const BasisMatrix M = makeBlendingMatrix();
  return M;
}

const BasisMatrix& cumulativeBlending() {
  static const BasisMatrix C = makeCumulativeMatrix(blending());
  return C;
}

/// d^order/du^order of [1, u, u², …, u^{k−1}].
BasisVector powerDerivative(double u, int order) {
  BasisVector U = BasisVector::Zero();
  for (int n = order; n < kK; ++n) {
    // n!/(n − order)! · u^{n − order}
    U[n] = factorial(n) / factorial(n - order) * std::pow(u, n - order);
  }
  return U;
}

}  // namespace

Se3Spline::IncrementMatrix Se3Spline::roughnessMatrix(int derivative_order) {
  // The n-th u-derivative of λ_j is Σ_a C(j, a)·a!/(a − n)!·u^(a − n); products integrate to
  // ∫₀¹ u^(a + b − 2n) du = 1/(a + b − 2n + 1).
  const BasisMatrix& C = cumulativeBlending();
  const int n = derivative_order;
  IncrementMatrix Q = IncrementMatrix::Zero();
  for (int j = 1; j < kK; ++j) {
    for (int l = 1; l < kK; ++l) {
      for (int a = n; a < kK; ++a) {
        for (int b = n; b < kK; ++b) {
          Q(j - 1, l - 1) += C(j, a) * factorial(a) / factorial(a - n) * C(l, b) * factorial(b) / factorial(b - n) /
                             (a + b - 2 * n + 1);
        }
      }
    }
  }
  return Q;
}

Se3Spline::Se3Spline(std::int64_t t0_ns, std::int64_t dt_ns, std::vector<Eigen::Vector3d> p_W_m,
                     std::vector<Eigen::Quaterniond> q_W_S)
    : t0_ns_(t0_ns), dt_ns_(dt_ns), p_W_m_(std::move(p_W_m)), q_W_S_(std::move(q_W_S)) {
  if (dt_ns_ <= 0) throw Error("Se3Spline: knot spacing must be > 0 ns, got " + std::to_string(dt_ns_));
  if (p_W_m_.size() != q_W_S_.size()) {
    throw Error("Se3Spline: " + std::to_string(p_W_m_.size()) + " control positions but " +
                std::to_string(q_W_S_.size()) + " control rotations");
  }
  if (p_W_m_.size() < static_cast<std::size_t>(kOrder)) {
    throw Error("Se3Spline: needs at least " + std::to_string(kOrder) + " control points, got " +
                std::to_string(p_W_m_.size()));
  }
  for (auto& q : q_W_S_) q.normalize();
  d_rad_.reserve(q_W_S_.size() - 1);
  for (std::size_t i = 0; i + 1 < q_W_S_.size(); ++i) d_rad_.push_back(logSO3(q_W_S_[i].conjugate() * q_W_S_[i + 1]));
}

std::int64_t Se3Spline::controlCentreTimeNs(int m) const {
  // Support of control point m: segments m − k + 1 … m, i.e. [t0 + (m − k + 1)Δt, t0 + (m + 1)Δt].
  // Twice the centre offset is an integer, so the division is exact for even Δt and off by 0.5 ns at most.
  return t0_ns_ + ((2 * m - (kOrder - 2)) * dt_ns_) / 2;
}

Se3Spline::SegmentTime Se3Spline::locate(std::int64_t t_ns) const {
  if (t_ns < startTimeNs() || t_ns > endTimeNs()) {
    throw Error("Se3Spline: time " + std::to_string(t_ns) + " ns outside the spline's range [" +
                std::to_string(startTimeNs()) + ", " + std::to_string(endTimeNs()) + "] ns");
  }
  // Integer arithmetic up to the final division keeps u exact to double precision anywhere in the range.
  const std::int64_t offset_ns = t_ns - t0_ns_;
  const int segment = std::min(static_cast<int>(offset_ns / dt_ns_), numSegments() - 1);
  const std::int64_t in_segment_ns = offset_ns - static_cast<std::int64_t>(segment) * dt_ns_;
  return {segment, static_cast<double>(in_segment_ns) / static_cast<double>(dt_ns_)};
}

Se3Spline::SegmentWeights Se3Spline::basisWeights(std::int64_t t_ns) const {
  const SegmentTime st = locate(t_ns);
  return {st.segment, blending() * powerDerivative(st.u, 0)};
}

Eigen::Vector3d Se3Spline::position(std::int64_t t_ns) const {
  const SegmentWeights w = basisWeights(t_ns);
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int j = 0; j < kOrder; ++j) p += w.weights[j] * p_W_m_[w.first_control + j];
  return p;
}

Eigen::Quaterniond Se3Spline::orientation(std::int64_t t_ns, RotationJacobians* J) const {
  const SegmentTime st = locate(t_ns);
  const BasisVector lambda = cumulativeBlending() * powerDerivative(st.u, 0);

  std::array<Eigen::Quaterniond, kOrder> A;  // A[j] = Exp(λ_j d_j), j ≥ 1
  Eigen::Quaterniond R = q_W_S_[st.segment];
  for (int j = 1; j < kOrder; ++j) {
    A[j] = expSO3(lambda[j] * d_rad_[st.segment + j - 1]);
    R = R * A[j];
  }
  if (J == nullptr) return R.normalized();

  // R = R_s·A_1⋯A_{k−1}. With P_j = A_{j+1}⋯A_{k−1}:
  //  - R_s ← R_s·Exp(δ) moves R by Exp(P_0ᵀ δ) on the right;
  //  - d_j ← d_j + Δ moves A_j by Exp(λ_j J_r(λ_j d_j) Δ) on the right, hence R by Exp(P_jᵀ λ_j J_r(λ_j d_j) Δ);
  //  - d_j = Log(R_{j−1}ᵀ R_j) changes by J_r⁻¹(d_j)·δ_j and by −J_l⁻¹(d_j)·δ_{j−1}.
  J->first_control = st.segment;
  for (auto& block : J->d_R_d_control) block.setZero();
  Eigen::Matrix3d P = Eigen::Matrix3d::Identity();  // P_j as a rotation matrix, built from the back
  for (int j = kOrder - 1; j >= 1; --j) {
    const Eigen::Vector3d& d = d_rad_[st.segment + j - 1];
    const Eigen::Matrix3d G = P.transpose() * lambda[j] * rightJacobianSO3(lambda[j] * d);
    J->d_R_d_control[j] += G * rightJacobianInvSO3(d);
    J->d_R_d_control[j - 1] -= G * leftJacobianInvSO3(d);
    P = A[j].toRotationMatrix() * P;
  }
  J->d_R_d_control[0] += P.transpose();
  return R.normalized();
}

SE3d Se3Spline::pose(std::int64_t t_ns) const { return SE3d(orientation(t_ns), position(t_ns)); }

Se3Spline::Kinematics Se3Spline::kinematics(std::int64_t t_ns) const {
  const SegmentTime st = locate(t_ns);
  const double dt_s = nsToSeconds(dt_ns_);
  const BasisVector U0 = powerDerivative(st.u, 0);
  const BasisVector U1 = powerDerivative(st.u, 1) / dt_s;  // d/dt = (1/Δt)·d/du
  const BasisVector U2 = powerDerivative(st.u, 2) / (dt_s * dt_s);

  Kinematics out;
  const BasisVector b0 = blending() * U0;
  const BasisVector b1 = blending() * U1;
  const BasisVector b2 = blending() * U2;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int j = 0; j < kOrder; ++j) {
    const Eigen::Vector3d& c = p_W_m_[st.segment + j];
    p += b0[j] * c;
    out.v_W_mps += b1[j] * c;
    out.a_W_mps2 += b2[j] * c;
  }

  const BasisVector lambda = cumulativeBlending() * U0;
  const BasisVector lambda_dot = cumulativeBlending() * U1;
  const BasisVector lambda_ddot = cumulativeBlending() * U2;
  Eigen::Quaterniond R = q_W_S_[st.segment];
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  Eigen::Vector3d alpha = Eigen::Vector3d::Zero();
  for (int j = 1; j < kOrder; ++j) {
    // After j factors the partial product R_s·A_1⋯A_j has body rate ω_j = A_jᵀω_{j−1} + λ̇_j d_j (A_j and its
    // derivative commute: both are functions of the fixed axis d_j), and differentiating once more
    // α_j = A_jᵀα_{j−1} − (λ̇_j d_j) × (A_jᵀω_{j−1}) + λ̈_j d_j.
    const Eigen::Vector3d& d = d_rad_[st.segment + j - 1];
    const Eigen::Quaterniond A = expSO3(lambda[j] * d);
    const Eigen::Vector3d rotated_omega = A.conjugate() * omega;
    alpha = A.conjugate() * alpha - (lambda_dot[j] * d).cross(rotated_omega) + lambda_ddot[j] * d;
    omega = rotated_omega + lambda_dot[j] * d;
    R = R * A;
  }
  out.T_W_S = SE3d(R, p);
  out.omega_S_rad_s = omega;
  out.alpha_S_rad_s2 = alpha;
  return out;
}

}  // namespace vifusion::sim
