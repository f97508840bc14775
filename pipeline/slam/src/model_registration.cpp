#include "vifusion/slam/model_registration.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/tracking/icp_degeneracy.hpp"

namespace vifusion::slam {
namespace {

/// Below this many inliers a level's 6×6 system is not solved (as DenseTracker).
constexpr double kMinSystemInliers = 6.0;

std::string field(const char* name) { return std::string("registration option '") + name + "'"; }

}  // namespace

void RegistrationOptions::validate() const {
  for (const int n : iterations) {
    if (n < 0 || n > 100) throw Error(field("iterations") + " must be 0..100 per level");
  }
  if (!(converged_step >= 0.0)) throw Error(field("converged_step") + " must be ≥ 0");
  if (!(min_overlap_share > 0.0 && min_overlap_share <= 1.0))
    throw Error(field("min_overlap_share") + " must be in (0, 1]");
  if (!(max_mean_chi2 > 0.0)) throw Error(field("max_mean_chi2") + " must be > 0");
  if (!(min_constraint_share >= 0.0 && min_constraint_share < 1.0 / 3.0)) {
    throw Error(field("min_constraint_share") + " must be in [0, 1/3)");
  }
  if (!(information_scale > 0.0 && information_scale <= 1.0))
    throw Error(field("information_scale") + " must be in (0, 1]");
  if (!(max_pose_to_depth_sigma > 0.0)) throw Error(field("max_pose_to_depth_sigma") + " must be > 0");
  if (!(max_correction_m > 0.0)) throw Error(field("max_correction_m") + " must be > 0");
  if (!(max_correction_rad > 0.0)) throw Error(field("max_correction_rad") + " must be > 0");
  for (const double chi2 : min_correction_chi2) {
    if (!(chi2 > 0.0)) throw Error(field("min_correction_chi2") + " must be > 0 for every number of directions");
  }
}

const char* registrationVerdictName(RegistrationVerdict verdict) {
  switch (verdict) {
    case RegistrationVerdict::kAccepted:
      return "accepted";
    case RegistrationVerdict::kNoOverlap:
      return "overlap";
    case RegistrationVerdict::kDiverged:
      return "diverged";
    case RegistrationVerdict::kResidual:
      return "residual";
    case RegistrationVerdict::kUnconstrained:
      return "unconstrained";
    case RegistrationVerdict::kCovariance:
      return "covariance";
    case RegistrationVerdict::kCorrection:
      return "correction";
    case RegistrationVerdict::kAmbiguous:
      return "ambiguous";
  }
  return "unknown";
}

namespace {

/// H⁺, the pseudo-inverse of a symmetric positive semi-definite system over the directions it constrains. With
/// the unconstrained directions projected out, H is singular up to rounding, where an LDLT reports a numerical
/// issue; the pseudo-inverse is zero along eigenvalues below kRelativeEigenvalueFloor of the largest. NaN when
/// the eigensolver fails.
Matrix6d pseudoInverse(const Matrix6d& H) {
  constexpr double kRelativeEigenvalueFloor = 1e-9;
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(H);
  if (eigen.info() != Eigen::Success) return Matrix6d::Constant(std::numeric_limits<double>::quiet_NaN());
  const double floor = kRelativeEigenvalueFloor * eigen.eigenvalues().cwiseAbs().maxCoeff();
  Vector6d inverse = Vector6d::Zero();
  for (int k = 0; k < 6; ++k) {
    if (eigen.eigenvalues()(k) > floor) inverse(k) = 1.0 / eigen.eigenvalues()(k);
  }
  return eigen.eigenvectors() * inverse.asDiagonal() * eigen.eigenvectors().transpose();
}

/// The Gauss-Newton step −H⁺·b over the directions the system constrains.
Vector6d constrainedStep(const NormalEquations6& system) { return -pseudoInverse(system.H) * system.b; }

}  // namespace

ModelRegistration::ModelRegistration(gpu::GpuContext& context, gpu::CapacityPlan& plan, int levels,
                                     const tracking::IcpOptions& icp, double far_depth_m,
                                     const RegistrationOptions& options)
    : context_(context),
      options_(options),
      far_depth_m_(far_depth_m),
      far_depth_sigma_m_(icp.axialSigmaAt(far_depth_m)),
      levels_(levels) {
  options_.validate();
  if (!(far_depth_m > 0.0)) throw Error("model registration: the far depth must be > 0 m");
  if (levels < 1 || levels > 3) throw Error("model registration: levels must be 1..3");
  icp_ = std::make_unique<tracking::IcpTerm>(context, plan, levels, icp, LevelReductionOptions{},
                                             "registration.icp_reduce");
}

ModelRegistration::~ModelRegistration() = default;

void ModelRegistration::build(const gpu::MemoryArena& arena, std::span<const RegistrationLevel> levels) {
  if (static_cast<int>(levels.size()) != levels_) throw Error("model registration: wrong number of levels");
  std::vector<tracking::IcpLevelInputs> inputs;
  for (const RegistrationLevel& level : levels) {
    cameras_.push_back(level.camera);
    inputs.push_back({level.active_vertices, level.active_normals, level.inactive_vertices, level.inactive_normals});
  }
  icp_->build(arena, inputs);
  for (int l = 0; l < levels_; ++l) {
    sequences_.push_back(gpu::CommandSequence::create(context_, "registration.level" + std::to_string(l)));
    sequences_.back()->record([&](gpu::CommandRecorder& recorder) { icp_->record(recorder, l); });
  }
}

RegistrationResult ModelRegistration::align() {
  RegistrationResult result;
  SE3d T = SE3d();
  NormalEquations6 last;
  for (int l = levels_ - 1; l >= 0; --l) {
    for (int i = 0; i < options_.iterations[static_cast<std::size_t>(l)]; ++i) {
      icp_->setPose(l, T, cameras_[static_cast<std::size_t>(l)]);
      sequences_[static_cast<std::size_t>(l)]->run();
      NormalEquations6 system = icp_->result(l);
      // Most frames have no inactive map in view: the first coarse evaluation says so at a sixteenth of the
      // level-0 cost (min_overlap_share of the level's pixels, as at level 0).
      const PinholeCamera& camera = cameras_[static_cast<std::size_t>(l)];
      const bool first = l == levels_ - 1 && i == 0;
      if (system.inliers < kMinSystemInliers ||
          (first && system.inliers < options_.min_overlap_share * camera.width * camera.height)) {
        result.inliers = system.inliers;  // at this level: what the report shows of a view without overlap
        result.candidates = system.candidates;
        result.verdict = RegistrationVerdict::kNoOverlap;
        return result;
      }
      if (l == 0) last = system;
      // Directions the surfaces leave free are not moved: the conditioning test below refuses such a view.
      NormalEquations6 constrained = system;
      tracking::removeUnconstrainedIcpDirections(system, options_.min_constraint_share, constrained);
      const Vector6d delta = constrainedStep(constrained);
      if (!delta.allFinite()) {
        result.verdict = RegistrationVerdict::kDiverged;
        return result;
      }
      T = SE3d::exp(delta) * T;
      ++result.iterations;
      if (delta.head<3>().norm() < options_.converged_step && delta.tail<3>().norm() < options_.converged_step) break;
    }
  }
  // Coarser levels may have stepped along directions the finest level leaves free, where nothing measured the
  // step: the correction keeps only its part in the finest level's constrained subspace (H⁺H projects onto
  // the range of the projected information).
  {
    NormalEquations6 constrained = last;
    tracking::removeUnconstrainedIcpDirections(last, options_.min_constraint_share, constrained);
    T = SE3d::exp(pseudoInverse(constrained.H) * constrained.H * T.log());
  }
  // The statistics at the final pose.
  icp_->setPose(0, T, cameras_[0]);
  sequences_[0]->run();
  last = icp_->result(0);
  result.T_inactive_active = T;
  result.inliers = last.inliers;
  result.candidates = last.candidates;
  const double pixels = static_cast<double>(cameras_[0].width) * static_cast<double>(cameras_[0].height);
  if (last.inliers < options_.min_overlap_share * pixels) {
    result.verdict = RegistrationVerdict::kNoOverlap;
    return result;
  }
  result.mean_chi2 = last.weighted_squared_residual / last.inliers;
  // Judged over the directions the surfaces constrain, as the steps were taken (model_registration.hpp).
  NormalEquations6 projected = last;
  result.free_directions = tracking::removeUnconstrainedIcpDirections(last, options_.min_constraint_share, projected);
  const Matrix6d information = options_.information_scale * projected.H;
  const Matrix6d covariance = pseudoInverse(information);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> position(covariance.topLeftCorner<3, 3>());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> rotation(covariance.bottomRightCorner<3, 3>());
  result.position_sigma_m = std::sqrt(std::max(0.0, position.eigenvalues().maxCoeff()));
  result.rotation_sigma_rad = std::sqrt(std::max(0.0, rotation.eigenvalues().maxCoeff()));
  // Both the covariance and the offset test judge a pose change by how far it moves a point at z_far.
  const auto at_far_depth = [&](double position_m, double rotation_rad) {
    return std::hypot(position_m, far_depth_m_ * rotation_rad);
  };
  const double far_bound_m = options_.max_pose_to_depth_sigma * far_depth_sigma_m_;
  result.far_sigma_m = at_far_depth(result.position_sigma_m, result.rotation_sigma_rad);
  const Vector6d correction = T.log();
  result.correction_m = correction.head<3>().norm();
  result.correction_rad = correction.tail<3>().norm();
  result.correction_far_m = at_far_depth(result.correction_m, result.correction_rad);
  // Σ = (1/s + Σ w e²)·H⁺ (model_registration.hpp): the random and the systematic part share H⁺'s shape.
  result.bias_bound = last.weighted_squared_bound;
  const double covariance_scale = 1.0 / options_.information_scale + result.bias_bound;
  result.correction_chi2 = correction.dot(projected.H * correction) / covariance_scale;
  if (!(result.mean_chi2 <= options_.max_mean_chi2)) {
    result.verdict = RegistrationVerdict::kResidual;
  } else if (!(result.far_sigma_m <= far_bound_m)) {
    result.verdict = RegistrationVerdict::kCovariance;
  } else if (!(result.correction_m <= options_.max_correction_m) ||
             !(result.correction_rad <= options_.max_correction_rad)) {
    result.verdict = RegistrationVerdict::kCorrection;
  } else {
    const int constrained = 6 - result.free_directions;
    result.significant =
        result.correction_chi2 >= options_.min_correction_chi2[static_cast<std::size_t>(constrained - 1)];
    // Moving the map needs the correction in every direction; reactivating needs the layers to coincide to the
    // depth noise where they are seen.
    if (result.significant) {
      result.verdict =
          result.free_directions > 0 ? RegistrationVerdict::kUnconstrained : RegistrationVerdict::kAccepted;
    } else {
      result.verdict =
          result.correction_far_m <= far_bound_m ? RegistrationVerdict::kAccepted : RegistrationVerdict::kAmbiguous;
    }
  }
  return result;
}

}  // namespace vifusion::slam
