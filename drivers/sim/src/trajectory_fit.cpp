#include "vifusion/sim/trajectory_fit.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::sim {
namespace {

constexpr int kK = Se3Spline::kOrder;
/// The smoothing penalty is on the jerk, ∫|p⃛|² dt: with it the fit is the quintic smoothing spline
/// (Reinsch 1967; order 2·3 = 6 is exactly the natural spline of this penalty), whose end conditions are
/// natural (no ringing between samples near the ends), and whose null space (quadratic motion) is never
/// biased.
constexpr int kPenalisedDerivative = 3;

void validate(const std::vector<StampedPose>& poses, const TrajectoryFitOptions& options) {
  if (poses.size() < 2) throw Error("fitTrajectory: needs at least 2 poses, got " + std::to_string(poses.size()));
  for (std::size_t i = 1; i < poses.size(); ++i) {
    if (poses[i].t_ns <= poses[i - 1].t_ns) {
      throw Error("fitTrajectory: pose " + std::to_string(i) + " at " + std::to_string(poses[i].t_ns) +
                  " ns does not come after pose " + std::to_string(i - 1) + " at " + std::to_string(poses[i - 1].t_ns) +
                  " ns");
    }
  }
  if (options.subsample < 1) throw Error("fitTrajectory: subsample must be ≥ 1");
  if (options.knot_spacing_ns < 0) throw Error("fitTrajectory: knot_spacing_ns must be ≥ 0");
  if (!std::isfinite(options.smoothing) || options.smoothing < 0.0) {
    throw Error("fitTrajectory: smoothing must be finite and ≥ 0");
  }
  if (options.max_iterations < 0) throw Error("fitTrajectory: max_iterations must be ≥ 0");
}

/// Every subsample-th pose and the last one.
std::vector<StampedPose> selectSamples(const std::vector<StampedPose>& poses, int subsample) {
  std::vector<StampedPose> out;
  for (std::size_t i = 0; i < poses.size(); i += static_cast<std::size_t>(subsample)) out.push_back(poses[i]);
  if (out.back().t_ns != poses.back().t_ns) out.push_back(poses.back());
  return out;
}

struct Knots {
  std::int64_t dt_ns = 0;
  int segments = 0;
};

Knots chooseKnots(const std::vector<StampedPose>& poses, const TrajectoryFitOptions& options) {
  const std::int64_t span_ns = poses.back().t_ns - poses.front().t_ns;
  if (options.knot_spacing_ns > 0) {
    const std::int64_t segments = (span_ns + options.knot_spacing_ns - 1) / options.knot_spacing_ns;
    return {options.knot_spacing_ns, static_cast<int>(std::max<std::int64_t>(1, segments))};
  }
  // Nominal spacing: the mean input spacing times the subsample step; then round the segment count and
  // stretch the spacing (ceil) so the spline ends on the last pose, not up to a knot interval beyond it.
  const double nominal_ns = static_cast<double>(span_ns) / static_cast<double>(poses.size() - 1) * options.subsample;
  const int segments = std::max(1, static_cast<int>(std::lround(static_cast<double>(span_ns) / nominal_ns)));
  return {(span_ns + segments - 1) / segments, segments};
}

/// Rotation of the samples at time t: slerp between the bracketing samples, held constant outside them.
Eigen::Quaterniond interpolateSampleRotation(const std::vector<StampedPose>& samples_W_S, std::int64_t t_ns) {
  if (t_ns <= samples_W_S.front().t_ns) return samples_W_S.front().T_world_body.quaternion();
  if (t_ns >= samples_W_S.back().t_ns) return samples_W_S.back().T_world_body.quaternion();
  const auto next = std::upper_bound(samples_W_S.begin(), samples_W_S.end(), t_ns,
                                     [](std::int64_t t, const StampedPose& s) { return t < s.t_ns; });
  const auto prev = next - 1;
  const double f = static_cast<double>(t_ns - prev->t_ns) / static_cast<double>(next->t_ns - prev->t_ns);
  return prev->T_world_body.quaternion().slerp(f, next->T_world_body.quaternion());
}

/// Control positions by penalised linear least squares (one normal-equation solve shared by x, y, z).
std::vector<Eigen::Vector3d> fitPositions(const Se3Spline& layout, const std::vector<StampedPose>& samples_W_S,
                                          double smoothing) {
  const int n = static_cast<int>(layout.controlPositions().size());
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
  for (const StampedPose& sample : samples_W_S) {
    const Se3Spline::SegmentWeights w = layout.basisWeights(sample.t_ns);
    H.block<kK, kK>(w.first_control, w.first_control) += w.weights * w.weights.transpose();
    rhs.middleRows<kK>(w.first_control) += w.weights * sample.T_world_body.translation().transpose();
  }
  // Segment s: increments Δ_j = c_{s+j} − c_{s+j−1} = D·[c_s … c_{s+k−1}].
  Eigen::Matrix<double, kK - 1, kK> D = Eigen::Matrix<double, kK - 1, kK>::Zero();
  for (int j = 0; j + 1 < kK; ++j) {
    D(j, j) = -1.0;
    D(j, j + 1) = 1.0;
  }
  // The roughness matrix integrates u-derivatives over a unit segment, ∫|dⁿp/duⁿ|² du = Δt^(2n−1)·∫|dⁿp/dtⁿ|² dt,
  // so TrajectoryFitOptions::smoothing's penalty λ·Δt⁵·∫|p⃛|² dt is λ times it, whatever the knot spacing.
  const Eigen::Matrix<double, kK, kK> H_segment =
      smoothing * D.transpose() * Se3Spline::roughnessMatrix(kPenalisedDerivative) * D;
  for (int segment = 0; segment < layout.numSegments(); ++segment) H.block<kK, kK>(segment, segment) += H_segment;

  const Eigen::MatrixXd c = H.ldlt().solve(rhs);
  std::vector<Eigen::Vector3d> out(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) out[static_cast<std::size_t>(j)] = c.row(j).transpose();
  return out;
}

struct RotationFit {
  std::vector<Eigen::Quaterniond> q_W_S;
  int iterations = 0;
};

/// Control rotations by Gauss–Newton on the SO(3) residuals plus the smoothing penalty.
RotationFit fitRotations(const Se3Spline& initial, const std::vector<StampedPose>& samples_W_S,
                         const TrajectoryFitOptions& options) {
  const std::int64_t t0_ns = initial.startTimeNs();
  const std::int64_t dt_ns = initial.knotSpacingNs();
  const std::vector<Eigen::Vector3d>& p_W_m = initial.controlPositions();
  const int n = static_cast<int>(p_W_m.size());
  RotationFit fit{initial.controlRotations(), 0};
  // The roughness form acts on each of the three rotation-vector components alike: Q ⊗ I₃.
  const Se3Spline::IncrementMatrix Q = Se3Spline::roughnessMatrix(kPenalisedDerivative);
  Eigen::Matrix<double, 3 * (kK - 1), 3 * (kK - 1)> W;
  for (int j = 0; j + 1 < kK; ++j) {
    for (int l = 0; l + 1 < kK; ++l) {
      W.block<3, 3>(3 * j, 3 * l) = options.smoothing * Q(j, l) * Eigen::Matrix3d::Identity();
    }
  }

  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    const Se3Spline spline(t0_ns, dt_ns, p_W_m, fit.q_W_S);
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * n);  // Jᵀr

    for (const StampedPose& sample : samples_W_S) {
      Se3Spline::RotationJacobians J;
      const Eigen::Quaterniond q = spline.orientation(sample.t_ns, &J);
      const Eigen::Vector3d r = logSO3(q.conjugate() * sample.T_world_body.quaternion());
      // Log(Exp(−ε)·Exp(r)) = r − J_l⁻¹(r)·ε for a right perturbation ε of the spline rotation.
      const Eigen::Matrix3d d_r_d_eps = -leftJacobianInvSO3(r);
      Eigen::Matrix<double, 3, 3 * kK> Jr;
      for (int m = 0; m < kK; ++m) Jr.block<3, 3>(0, 3 * m) = d_r_d_eps * J.d_R_d_control[static_cast<std::size_t>(m)];
      const int col = 3 * J.first_control;
      H.block<3 * kK, 3 * kK>(col, col) += Jr.transpose() * Jr;
      g.segment<3 * kK>(col) += Jr.transpose() * r;
    }

    // Penalty per segment: dᵀ·W·d over its increments d_j = Log(R_{s+j−1}ᵀ R_{s+j}), j = 1 … k − 1, with
    // ∂d_j/∂δ_{s+j} = J_r⁻¹(d_j) and ∂d_j/∂δ_{s+j−1} = −J_l⁻¹(d_j).
    for (int segment = 0; segment < spline.numSegments(); ++segment) {
      Eigen::Matrix<double, 3 * (kK - 1), 1> d;
      Eigen::Matrix<double, 3 * (kK - 1), 3 * kK> Jd = Eigen::Matrix<double, 3 * (kK - 1), 3 * kK>::Zero();
      for (int j = 1; j < kK; ++j) {
        const Eigen::Vector3d d_j = logSO3(fit.q_W_S[segment + j - 1].conjugate() * fit.q_W_S[segment + j]);
        d.segment<3>(3 * (j - 1)) = d_j;
        Jd.block<3, 3>(3 * (j - 1), 3 * j) = rightJacobianInvSO3(d_j);
        Jd.block<3, 3>(3 * (j - 1), 3 * (j - 1)) = -leftJacobianInvSO3(d_j);
      }
      const int col = 3 * segment;
      H.block<3 * kK, 3 * kK>(col, col) += Jd.transpose() * W * Jd;
      g.segment<3 * kK>(col) += Jd.transpose() * W * d;
    }

    const Eigen::VectorXd delta = H.ldlt().solve(-g);
    for (int m = 0; m < n; ++m) fit.q_W_S[m] = (fit.q_W_S[m] * expSO3(delta.segment<3>(3 * m))).normalized();
    fit.iterations = iteration + 1;
    if (delta.cwiseAbs().maxCoeff() < options.convergence_rad) break;
  }
  return fit;
}

}  // namespace

FitResiduals fitResiduals(const TrajectoryFit& fit, const std::vector<StampedPose>& poses_W_C) {
  FitResiduals out;
  double sum_sq_position_mm2 = 0.0;
  double sum_sq_rotation_deg2 = 0.0;
  for (const StampedPose& pose : poses_W_C) {
    const SE3d T_W_C = fit.cameraPose(pose.t_ns);
    const double position_mm = 1e3 * (T_W_C.translation() - pose.T_world_body.translation()).norm();
    const double rotation_deg =
        logSO3(T_W_C.quaternion().conjugate() * pose.T_world_body.quaternion()).norm() * 180.0 / std::numbers::pi;
    sum_sq_position_mm2 += position_mm * position_mm;
    sum_sq_rotation_deg2 += rotation_deg * rotation_deg;
    if (position_mm > out.max_position_mm) {
      out.max_position_mm = position_mm;
      out.max_position_t_ns = pose.t_ns;
    }
    if (rotation_deg > out.max_rotation_deg) {
      out.max_rotation_deg = rotation_deg;
      out.max_rotation_t_ns = pose.t_ns;
    }
    ++out.count;
  }
  if (out.count > 0) {
    out.rms_position_mm = std::sqrt(sum_sq_position_mm2 / out.count);
    out.rms_rotation_deg = std::sqrt(sum_sq_rotation_deg2 / out.count);
  }
  return out;
}

bool withinTolerance(const FitResiduals& residuals, const FitTolerance& tolerance) {
  return residuals.max_position_mm <= tolerance.max_position_mm &&
         residuals.max_rotation_deg <= tolerance.max_rotation_deg;
}

TrajectoryFit fitTrajectory(const std::vector<StampedPose>& poses_W_C, const SE3d& T_S_C,
                            const TrajectoryFitOptions& options) {
  validate(poses_W_C, options);
  const std::vector<StampedPose> samples_W_C = selectSamples(poses_W_C, options.subsample);
  std::vector<StampedPose> samples_W_S;
  samples_W_S.reserve(samples_W_C.size());
  const SE3d T_C_S = T_S_C.inverse();
  for (const StampedPose& s : samples_W_C) samples_W_S.push_back({s.t_ns, s.T_world_body * T_C_S});

  const Knots knots = chooseKnots(poses_W_C, options);
  const std::int64_t t0_ns = poses_W_C.front().t_ns;
  const int n = knots.segments + kK - 1;
  if (options.smoothing == 0.0 && static_cast<std::size_t>(n) > samples_W_S.size()) {
    throw Error("fitTrajectory: " + std::to_string(n) + " control points but only " +
                std::to_string(samples_W_S.size()) + " samples; the fit needs smoothing > 0");
  }

  // The layout (knots) is all the position fit needs; the rotations start from the samples.
  const Se3Spline layout(t0_ns, knots.dt_ns,
                         std::vector<Eigen::Vector3d>(static_cast<std::size_t>(n), Eigen::Vector3d::Zero()),
                         std::vector<Eigen::Quaterniond>(static_cast<std::size_t>(n), Eigen::Quaterniond::Identity()));
  std::vector<Eigen::Quaterniond> q_initial(static_cast<std::size_t>(n));
  for (int m = 0; m < n; ++m)
    q_initial[static_cast<std::size_t>(m)] = interpolateSampleRotation(samples_W_S, layout.controlCentreTimeNs(m));
  const std::vector<Eigen::Vector3d> p_W_m = fitPositions(layout, samples_W_S, options.smoothing);
  const RotationFit rotations = fitRotations(Se3Spline(t0_ns, knots.dt_ns, p_W_m, q_initial), samples_W_S, options);

  TrajectoryFit fit{Se3Spline(t0_ns, knots.dt_ns, p_W_m, rotations.q_W_S),
                    T_S_C,
                    poses_W_C.front().t_ns,
                    poses_W_C.back().t_ns,
                    {},
                    {},
                    rotations.iterations};
  fit.at_samples = fitResiduals(fit, samples_W_C);
  fit.at_all_poses = fitResiduals(fit, poses_W_C);
  return fit;
}

}  // namespace vifusion::sim
