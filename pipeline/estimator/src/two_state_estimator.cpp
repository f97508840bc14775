#include "vifusion/estimator/two_state_estimator.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace vifusion::estimator {
namespace {

using Mask18 = Eigen::Matrix<double, kStateDim, 1>;

Mask18 maskOf(std::initializer_list<int> first_indices_of_triples) {
  Mask18 mask = Mask18::Zero();
  for (int first : first_indices_of_triples) mask.segment<3>(first).setOnes();
  return mask;
}

SE3d cameraPose(const NavState& x) { return SE3d(x.q_W_C, x.r_W_C); }

}  // namespace

TwoStateEstimator::TwoStateEstimator(const EstimatorOptions& options, const imu::ImuOptions& imu_options,
                                     const SE3d& T_S_C)
    : options_(options), preintegrator_(imu_options), imu_error_(imu_options, T_S_C) {
  options_.validate();
  if (options_.mode == InertialMode::kRgbdInertial) {
    x0_estimated_ = maskOf({kIdxR, kIdxAlpha, kIdxV, kIdxBg, kIdxBa, kIdxG});
    x0_estimated_[kIdxG + 2] = 0.0;  // the gauge: q_I_W's rotation about gravity
    x1_estimated_ = x0_estimated_;
    x1_inertial_only_ = x0_estimated_;
  } else {
    // Without the accelerometer nothing relates x0's position to x1's: x0's is held, x1's comes from
    // vision or, without it, from the constant-velocity guess.
    x0_estimated_ = maskOf({kIdxAlpha, kIdxBg});
    x1_estimated_ = maskOf({kIdxR, kIdxAlpha, kIdxBg});
    x1_inertial_only_ = x0_estimated_;
  }
  mask1_ = x1_estimated_;
}

void TwoStateEstimator::initialise(std::int64_t t_ns, const NavState& x) {
  const ImuNoiseParams& noise = preintegrator_.options().noise;
  Vector18d variance;
  variance.segment<6>(kIdxR).setConstant(options_.initial_pose_sigma * options_.initial_pose_sigma);
  variance.segment<3>(kIdxV).setConstant(options_.initial_velocity_sigma_mps * options_.initial_velocity_sigma_mps);
  variance.segment<3>(kIdxBg).setConstant(noise.gyro_bias_prior * noise.gyro_bias_prior);
  variance.segment<3>(kIdxBa).setConstant(noise.accel_bias_prior * noise.accel_bias_prior);
  variance.segment<3>(kIdxG).setConstant(options_.initial_gravity_sigma_rad * options_.initial_gravity_sigma_rad);
  prior_H_ = variance.cwiseInverse().cwiseProduct(x0_estimated_).asDiagonal();
  prior_b_.setZero();
  prior_x_ = x;
  x0_ = x;
  x1_ = x;
  t_ns_ = t_ns;
  last_translation_W_m_.setZero();
  initialised_ = true;
}

Matrix18d TwoStateEstimator::modeInformation(const Matrix18d& information) const {
  if (options_.mode == InertialMode::kRgbdInertial) return information;
  // Dropping residual rows of a correlated Gaussian keeps the marginal of the others: invert the
  // covariance's block of the rotation and gyro-bias rows.
  const Matrix18d covariance = information.ldlt().solve(Matrix18d::Identity());
  constexpr int kRows[6] = {kIdxAlpha, kIdxAlpha + 1, kIdxAlpha + 2, kIdxBg, kIdxBg + 1, kIdxBg + 2};
  Eigen::Matrix<double, 6, 6> kept;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) kept(i, j) = covariance(kRows[i], kRows[j]);
  }
  const Eigen::Matrix<double, 6, 6> kept_information = kept.inverse();
  Matrix18d result = Matrix18d::Zero();
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) result(kRows[i], kRows[j]) = kept_information(i, j);
  }
  return result;
}

void TwoStateEstimator::buildSystem(const PoseSystem* dense, const Mask18& mask1) {
  H_.setZero();
  b_.setZero();
  Matrix18d J0, J1, information;
  const Vector18d e = imu_error_.evaluate(pre_, x0_, x1_, &J0, &J1, &information);
  const Matrix18d W = modeInformation(information);
  const Matrix18d WJ0 = W * J0;
  const Matrix18d WJ1 = W * J1;
  H_.topLeftCorner<kStateDim, kStateDim>() = J0.transpose() * WJ0;
  H_.topRightCorner<kStateDim, kStateDim>() = J0.transpose() * WJ1;
  H_.bottomRightCorner<kStateDim, kStateDim>() = J1.transpose() * WJ1;
  b_.head<kStateDim>() = WJ0.transpose() * e;
  b_.tail<kStateDim>() = WJ1.transpose() * e;

  Matrix18d J_prior;
  const Vector18d delta = boxMinus(x0_, prior_x_, &J_prior, nullptr);
  H_.topLeftCorner<kStateDim, kStateDim>() += J_prior.transpose() * prior_H_ * J_prior;
  b_.head<kStateDim>() += J_prior.transpose() * (prior_b_ + prior_H_ * delta);

  if (dense != nullptr) {
    H_.block<6, 6>(kStateDim + kIdxR, kStateDim + kIdxR) += dense->H;
    b_.segment<6>(kStateDim + kIdxR) += dense->b;
  }
  H_.bottomLeftCorner<kStateDim, kStateDim>() = H_.topRightCorner<kStateDim, kStateDim>().transpose();

  // Held dims: no coupling, unit diagonal, zero gradient, so their step is exactly zero.
  for (int i = 0; i < kDim; ++i) {
    const bool estimated = i < kStateDim ? x0_estimated_[i] != 0.0 : mask1[i - kStateDim] != 0.0;
    if (estimated) continue;
    H_.row(i).setZero();
    H_.col(i).setZero();
    H_(i, i) = 1.0;
    b_[i] = 0.0;
  }
  mask1_ = mask1;
}

bool TwoStateEstimator::solveStep(Vector36d& step) {
  ldlt_.compute(H_);
  if (ldlt_.info() != Eigen::Success || !(ldlt_.vectorD().minCoeff() > 0.0)) return false;
  step = ldlt_.solve(-b_);
  return step.allFinite();
}

bool TwoStateEstimator::solveAndUpdate(Vector36d& step) {
  if (!solveStep(step)) return false;
  x0_ = boxPlus(x0_, step.head<kStateDim>());
  x1_ = boxPlus(x1_, step.tail<kStateDim>());
  return true;
}

void TwoStateEstimator::reintegrateIfNeeded(int& reintegrations) {
  if (!pre_.needsReintegration(x0_.b_g)) return;
  // The samples integrated cleanly once; the same span cannot fail now.
  (void)preintegrator_.integrate(samples_, t_ns_, t1_ns_, x0_.b_g, x0_.b_a, pre_);
  ++reintegrations;
}

void TwoStateEstimator::marginalise(const Vector36d& last_step) {
  // The gradient at the solution, predicted by the last linear system.
  const Vector36d b = b_ + H_ * last_step;
  const auto H00 = H_.topLeftCorner<kStateDim, kStateDim>();
  const auto H01 = H_.topRightCorner<kStateDim, kStateDim>();
  const Eigen::LDLT<Matrix18d> H00_ldlt(H00);
  const Matrix18d H00_inv_H01 = H00_ldlt.solve(H01);
  const Vector18d H00_inv_b0 = H00_ldlt.solve(b.head<kStateDim>());
  prior_H_ = H_.bottomRightCorner<kStateDim, kStateDim>() - H01.transpose() * H00_inv_H01;
  prior_b_ = b.tail<kStateDim>() - H01.transpose() * H00_inv_b0;
  // Held dims carry no information (their unit diagonal was only a placeholder).
  prior_H_ = mask1_.asDiagonal() * prior_H_ * mask1_.asDiagonal();
  prior_H_ = 0.5 * (prior_H_ + prior_H_.transpose()).eval();
  prior_b_ = prior_b_.cwiseProduct(mask1_);
  prior_x_ = x1_;
}

bool TwoStateEstimator::solveInertialOnly(const NavState& x0_start, const NavState& x1_start, Vector36d& step,
                                          int& iterations, int& reintegrations) {
  x0_ = x0_start;
  x1_ = x1_start;
  for (int i = 0; i < options_.inertial_only_iterations; ++i) {
    reintegrateIfNeeded(reintegrations);
    buildSystem(nullptr, x1_inertial_only_);
    if (!solveAndUpdate(step)) return false;
    ++iterations;
  }
  return true;
}

double TwoStateEstimator::inertialCost() const {
  Matrix18d information;
  const Vector18d e = imu_error_.evaluate(pre_, x0_, x1_, nullptr, nullptr, &information);
  const Vector18d delta = boxMinus(x0_, prior_x_, nullptr, nullptr);
  return e.dot(modeInformation(information) * e) + delta.dot(prior_H_ * delta) + 2.0 * prior_b_.dot(delta);
}

bool TwoStateEstimator::solveDense(DenseTerms& dense, Vector36d& step, FrameSolve& summary) {
  for (int level = dense.levels() - 1; level >= 0; --level) {
    double previous_inliers = -1.0;
    NavState x0_previous, x1_previous;
    for (int i = 0; i < options_.iterations[level]; ++i) {
      reintegrateIfNeeded(summary.reintegrations);
      PoseSystem system;
      if (!dense.evaluate(level, cameraPose(x1_), system)) return false;
      if (system.inliers < (1.0 - options_.max_inlier_loss) * previous_inliers) {
        // The last step lost inliers: back to the iterate before it, evaluated again so that the system
        // marginalised (and the terms' statistics) belong to the pose kept.
        x0_ = x0_previous;
        x1_ = x1_previous;
        if (!dense.evaluate(level, cameraPose(x1_), system)) return false;
        buildSystem(&system, x1_estimated_);
        // Marginalised as if the kept iterate were the optimum (gradient b + H·step = 0 there): the linear
        // model that proposed the lost step is not to be carried into the prior.
        if (!solveStep(step)) return false;
        ++summary.backtracks;
        break;
      }
      previous_inliers = system.inliers;
      x0_previous = x0_;
      x1_previous = x1_;
      buildSystem(&system, x1_estimated_);
      if (!solveAndUpdate(step)) return false;
      ++summary.iterations;
      if (stepWithinUncertainty(step.segment<6>(kStateDim + kIdxR), system.H, options_.converged_step_chi2)) break;
    }
  }
  return dense.healthy();
}

bool TwoStateEstimator::refusedByGate(const NavState& x0_start, const NavState& x1_start, Vector36d& step,
                                      FrameSolve& summary) {
  const NavState x0_vision = x0_, x1_vision = x1_;
  const Matrix36d H_vision = H_;
  const Vector36d b_vision = b_, step_vision = step;
  const Mask18 mask_vision = mask1_;
  const double cost_vision = inertialCost();
  int iterations = 0;
  if (solveInertialOnly(x0_start, x1_start, step, iterations, summary.reintegrations)) {
    summary.vision_chi2 = std::max(0.0, cost_vision - inertialCost());
    const bool gross_step = (x1_vision.r_W_C - x1_.r_W_C).norm() > options_.vision_gate_min_step_m ||
                            x1_vision.q_W_C.angularDistance(x1_.q_W_C) > options_.vision_gate_min_step_rad;
    // Gyro mode has no motion model to carry position: refusing vision there only loses frames.
    summary.vision_rejected =
        options_.mode == InertialMode::kRgbdInertial && summary.vision_chi2 > options_.vision_gate_chi2 && gross_step;
  }
  if (summary.vision_rejected) {  // keep the inertial-only solution just computed
    summary.iterations += iterations;
    return true;
  }
  x0_ = x0_vision;
  x1_ = x1_vision;
  H_ = H_vision;
  b_ = b_vision;
  step = step_vision;
  mask1_ = mask_vision;
  return false;
}

std::optional<imu::ImuSampleIssue> TwoStateEstimator::track(std::int64_t t1_ns, std::span<const ImuSample> samples,
                                                            DenseTerms* dense, FrameSolve& summary) {
  summary = FrameSolve{};
  if (auto issue = preintegrator_.integrate(samples, t_ns_, t1_ns, x0_.b_g, x0_.b_a, pre_)) return issue;
  samples_ = samples;
  t1_ns_ = t1_ns;

  x1_ = imu_error_.predict(pre_, x0_);
  if (options_.mode == InertialMode::kGyro) {
    // Only the rotation comes from the IMU; the accelerometer-dependent parts stay as they were.
    x1_.r_W_C = x0_.r_W_C + last_translation_W_m_;
    x1_.v_I_S = x0_.v_I_S;
  }
  const NavState x0_start = x0_;
  const NavState x1_start = x1_;

  Vector36d step = Vector36d::Zero();
  bool vision = dense != nullptr && solveDense(*dense, step, summary);
  if (vision) {
    // The gate compares the dense solution with what the IMU and the prior say without it.
    vision = !refusedByGate(x0_start, x1_start, step, summary);
  } else {
    int iterations = 0;
    const bool solved = solveInertialOnly(x0_start, x1_start, step, iterations, summary.reintegrations);
    summary.iterations += iterations;
    if (!solved) {
      // Numerically hopeless (should not happen with a full-rank prior): keep the IMU prediction and
      // start over from it rather than carry a broken prior.
      initialise(t1_ns, x1_start);
      summary.restarted = true;
      return std::nullopt;
    }
  }
  summary.vision_used = vision;
  marginalise(step);

  Matrix18d information;
  const Vector18d e = imu_error_.evaluate(pre_, x0_, x1_, nullptr, nullptr, &information);
  summary.imu_chi2 = e.dot(modeInformation(information) * e);

  last_translation_W_m_ = x1_.r_W_C - x0_.r_W_C;
  x0_ = x1_;
  t_ns_ = t1_ns;
  return std::nullopt;
}

Vector18d TwoStateEstimator::covarianceDiagonal() const {
  Matrix18d H = prior_H_;
  Vector18d held = Vector18d::Zero();
  for (int i = 0; i < kStateDim; ++i) {
    if (H(i, i) > 0.0) continue;
    H(i, i) = 1.0;
    held[i] = 1.0;
  }
  const Matrix18d covariance = H.ldlt().solve(Matrix18d::Identity());
  return covariance.diagonal().cwiseProduct(Vector18d::Ones() - held);
}

void TwoStateEstimator::moveWithMap(const SE3d& T_Wnew_Wold) {
  const Eigen::Matrix3d R = T_Wnew_Wold.rotationMatrix();
  const auto move = [&](NavState& x) {
    const Eigen::Matrix3d R_I = x.q_I_W.toRotationMatrix() * R * x.q_I_W.toRotationMatrix().transpose();
    x.r_W_C = T_Wnew_Wold * x.r_W_C;
    x.q_W_C = (T_Wnew_Wold.quaternion() * x.q_W_C).normalized();
    x.v_I_S = R_I * x.v_I_S;
    return R_I;
  };
  const Eigen::Matrix3d R_I = move(prior_x_);
  move(x0_);
  move(x1_);
  Matrix18d J = Matrix18d::Identity();
  J.block<3, 3>(kIdxR, kIdxR) = R;
  J.block<3, 3>(kIdxAlpha, kIdxAlpha) = R;
  J.block<3, 3>(kIdxV, kIdxV) = R_I;
  prior_H_ = J * prior_H_ * J.transpose();
  prior_H_ = 0.5 * (prior_H_ + prior_H_.transpose()).eval();
  prior_b_ = J * prior_b_;
}

}  // namespace vifusion::estimator
