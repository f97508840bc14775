#include "vifusion/slam/dense_tracker.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "vifusion/core/binomial_test.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/shaders/spirv.hpp"
#include "vifusion/tracking/icp_degeneracy.hpp"

namespace vifusion::slam {
void TrackerOptions::validate() const {
  if (levels < 1 || levels > 3) throw Error("tracker option 'levels' must be 1..3");
  for (int l = 0; l < levels; ++l) {
    if (iterations[l] < 0 || iterations[l] > 100) throw Error("tracker option 'iterations' must be 0..100 per level");
  }
  if (!(converged_step_chi2 > 0.0)) throw Error("tracker option 'converged_step_chi2' must be > 0");
  if (!(rotation_converged_step_rad >= 0.0)) throw Error("tracker option 'rotation_converged_step_rad' must be ≥ 0");
  if (!(min_inlier_fraction >= 0.0 && min_inlier_fraction < 1.0)) {
    throw Error("tracker option 'min_inlier_fraction' must be in [0, 1)");
  }
  if (!(health_test_significance > 0.0 && health_test_significance < 0.5)) {
    throw Error("tracker option 'health_test_significance' must be in (0, 0.5)");
  }
  if (!(min_icp_constraint_share >= 0.0 && min_icp_constraint_share < 1.0 / 3.0)) {
    throw Error("tracker option 'min_icp_constraint_share' must be in [0, 1/3)");
  }
  if (!(motion_prior_sigma_m > 0.0) || !(motion_prior_sigma_rad > 0.0)) {
    throw Error("tracker options 'motion_prior_sigma_m' and 'motion_prior_sigma_rad' must be > 0");
  }
  if (!(max_motion_innovation_m > 0.0)) throw Error("tracker option 'max_motion_innovation_m' must be > 0");
  if (!(max_speed_mps > 0.0)) throw Error("tracker option 'max_speed_mps' must be > 0");
  if (!(max_continued_motion_s > 0.0)) throw Error("tracker option 'max_continued_motion_s' must be > 0");
  if (!(min_recovered_inlier_share > 0.0 && min_recovered_inlier_share <= 1.0)) {
    throw Error("tracker option 'min_recovered_inlier_share' must be in (0, 1]");
  }
  if (!(max_place_correction_m > 0.0) || !(max_place_correction_rad > 0.0)) {
    throw Error("tracker options 'max_place_correction_m' and 'max_place_correction_rad' must be > 0");
  }
  if (rotation_iterations < 1 || rotation_iterations > 100) {
    throw Error("tracker option 'rotation_iterations' must be 1..100");
  }
  icp.validate();
  photometric.validate();
}

DenseTracker::DenseTracker(gpu::GpuContext& context, gpu::CapacityPlan& plan, const RigCalibration& calibration,
                           const TrackerOptions& options)
    : context_(context), options_(options) {
  options_.validate();
  preprocess::PreprocessOptions preprocess_options = options_.preprocess;
  preprocess_options.camera = calibration.camera;
  preprocess_options.levels = options_.levels;
  preprocess_options.metric.depth_scale_m = static_cast<float>(calibration.depth_scale_m);
  preprocess_options.metric.inverse_depth_bias_per_m = static_cast<float>(calibration.inverse_depth_bias_per_m);
  if (calibration.depth_camera) {  // depth from its own camera: registered to colour on the GPU first
    preprocess_options.registration =
        preprocess::DepthRegistration{calibration.depth_camera->camera, calibration.camera,
                                      calibration.depth_camera->T_C_D, calibration.depth_scale_m};
  }
  stage_ = std::make_unique<preprocess::PreprocessStage>(context, plan, preprocess_options);
  for (int l = 0; l < options_.levels; ++l) {
    const preprocess::LevelBuffers& current = stage_->level(l);
    const auto mirror = [&](gpu::BufferId id, const char* what) {
      return plan.addBuffer("tracker.reference.l" + std::to_string(l) + "." + what, plan.buffers()[id.index].bytes,
                            gpu::MemoryUse::DeviceLocal);
    };
    reference_.push_back({mirror(current.depth_m, "depth"), mirror(current.intensity, "intensity"),
                          mirror(current.vertices, "vertices"), mirror(current.normals, "normals"),
                          mirror(current.gradients, "gradients")});
  }
  icp_ = std::make_unique<tracking::IcpTerm>(context, plan, options_.levels, options_.icp);
  photometric_ = std::make_unique<tracking::PhotometricTerm>(context, plan, options_.levels, options_.photometric);
  rotation_ = std::make_unique<RotationPrealignment>(
      context, plan, *stage_, options_.photometric, options_.rotation_iterations, options_.rotation_converged_step_rad);
}

DenseTracker::~DenseTracker() = default;

void DenseTracker::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  stage_->build(arena);
  std::vector<tracking::IcpLevelInputs> icp_inputs;
  std::vector<tracking::PhotometricLevelInputs> photometric_inputs;
  for (int l = 0; l < options_.levels; ++l) {
    const preprocess::LevelBuffers& cur = stage_->level(l);
    const preprocess::LevelBuffers& ref = reference_[l];
    icp_inputs.push_back({cur.vertices, cur.normals, ref.vertices, ref.normals});
    photometric_inputs.push_back({cur.vertices, cur.intensity, ref.intensity, ref.gradients, ref.vertices});
  }
  icp_->build(arena, icp_inputs);
  photometric_->build(arena, photometric_inputs);

  // The frame before keeps its coarse images for the rotation pre-alignment, then the stage overwrites them.
  rotation_->build(arena);
  preprocess_sequence_ = gpu::CommandSequence::create(context_, "tracker.preprocess");
  preprocess_sequence_->record([&](gpu::CommandRecorder& recorder) {
    rotation_->recordKeepPrevious(recorder);
    recorder.computeBarrier();
    stage_->record(recorder);
    recorder.computeBarrier();
    rotation_->recordPyramid(recorder);
  });
  gpu::KernelSpec gradient_spec;
  gradient_spec.name = "intensity_gradient";
  gradient_spec.spirv = shaders::intensity_gradient;
  gradient_spec.storage_buffers = 2;
  gradient_spec.push_constant_bytes = sizeof(preprocess::IntensityGradientParams);
  gradient_spec.max_binding_sets = static_cast<uint32_t>(options_.levels);
  gradient_kernel_ = gpu::ComputeKernel::create(context_, std::move(gradient_spec));
  for (int l = 0; l < options_.levels; ++l) {
    gradient_sets_.push_back(
        gradient_kernel_->bind({&arena.buffer(reference_[l].intensity), &arena.buffer(reference_[l].gradients)}));
  }
  gpu::KernelSpec pyramid_spec;
  pyramid_spec.name = "pyramid_down_intensity";
  pyramid_spec.spirv = shaders::pyramid_down_intensity;
  pyramid_spec.storage_buffers = 2;
  pyramid_spec.push_constant_bytes = sizeof(preprocess::PyramidDownIntensityParams);
  pyramid_spec.max_binding_sets = static_cast<uint32_t>(std::max(1, options_.levels - 1));
  pyramid_kernel_ = gpu::ComputeKernel::create(context_, std::move(pyramid_spec));
  for (int l = 1; l < options_.levels; ++l) {
    pyramid_sets_.push_back(
        pyramid_kernel_->bind({&arena.buffer(reference_[l - 1].intensity), &arena.buffer(reference_[l].intensity)}));
  }
  for (int l = 0; l < options_.levels; ++l) {
    level_sequences_.push_back(gpu::CommandSequence::create(context_, "tracker.level" + std::to_string(l)));
    level_sequences_.back()->record([&](gpu::CommandRecorder& recorder) {
      icp_->record(recorder, l);
      if (options_.use_photometric) photometric_->record(recorder, l);
    });
  }
}

void DenseTracker::preprocess(const RgbdFrame& frame) {
  stage_->upload(frame.depth.view(), frame.rgb.view());
  preprocess_sequence_->run();
  rotation_->framePreprocessed();
}

void DenseTracker::recordReferenceIntensity(gpu::CommandRecorder& recorder) const {
  for (int l = 1; l < options_.levels; ++l) {
    const PinholeCamera& fine = stage_->camera(l - 1);
    const PinholeCamera& coarse = stage_->camera(l);
    const preprocess::PyramidDownIntensityParams params{fine.width, fine.height};
    recorder.dispatch(
        *pyramid_kernel_, pyramid_sets_[l - 1],
        pyramid_kernel_->groupsFor(static_cast<uint32_t>(coarse.width), static_cast<uint32_t>(coarse.height)), params);
    recorder.computeBarrier();
  }
  for (int l = 0; l < options_.levels; ++l) {
    const PinholeCamera& camera = stage_->camera(l);
    const preprocess::IntensityGradientParams params{camera.width, camera.height};
    recorder.dispatch(
        *gradient_kernel_, gradient_sets_[l],
        gradient_kernel_->groupsFor(static_cast<uint32_t>(camera.width), static_cast<uint32_t>(camera.height)), params);
  }
  recorder.computeBarrier();
}

NormalEquations6 DenseTracker::evaluate(int level, const SE3d& T_ref_cur, TrackingResult& statistics,
                                        ReferencePixels reference) {
  const PinholeCamera& camera = stage_->camera(level);
  icp_->setPose(level, T_ref_cur, camera);
  if (options_.use_photometric) {
    photometric_->setPose(level, T_ref_cur, camera, reference == ReferencePixels::kMapAndFill);
  }
  level_sequences_[level]->run();
  NormalEquations6 sum = icp_->result(level);
  statistics.icp_inliers = sum.inliers;
  statistics.icp_candidates = sum.candidates;
  statistics.icp_energy = sum.inliers > 0.0 ? sum.weighted_squared_residual / sum.inliers : 0.0;
  statistics.rgb_inliers = 0.0;
  statistics.valid_pixels = static_cast<double>(camera.width) * static_cast<double>(camera.height);
  if (options_.use_photometric) {
    const NormalEquations6 rgb = photometric_->result(level);
    statistics.rgb_inliers = rgb.inliers;
    statistics.valid_pixels = rgb.candidates;
    sum += rgb;
  }
  return sum;
}

NormalEquations6 DenseTracker::icpEquations(int level) const { return icp_->result(level); }

// Gauss-Newton coarse to fine over the dense terms plus a weak constant-velocity prior on the change
// from the guess (r = log(T_ref_cur·guess⁻¹), Jacobian ≈ I), which holds what no term determines; at
// the coarse levels the ICP's degenerate translation directions are left to the other two.
SE3d DenseTracker::prealignRotation(const SE3d& T_prev_cur_guess) const {
  if (!options_.rotation_prealignment) return T_prev_cur_guess;
  return SE3d(rotation_->align(T_prev_cur_guess.quaternion()), T_prev_cur_guess.translation());
}

TrackingResult DenseTracker::track(const SE3d& T_ref_cur_guess, ReferencePixels reference, TrackingGuess guess) {
  TrackingResult result;
  result.T_ref_cur = T_ref_cur_guess;
  result.reference = reference;
  SE3d T_ref_cur = T_ref_cur_guess;
  const bool place = guess == TrackingGuess::kPlace;
  const double prior_sigma_m = place ? options_.max_place_correction_m : options_.motion_prior_sigma_m;
  const double prior_sigma_rad = place ? options_.max_place_correction_rad : options_.motion_prior_sigma_rad;
  Vector6d prior_information;
  prior_information << Eigen::Vector3d::Constant(1.0 / (prior_sigma_m * prior_sigma_m)),
      Eigen::Vector3d::Constant(1.0 / (prior_sigma_rad * prior_sigma_rad));
  for (int l = options_.levels - 1; l >= 0; --l) {
    for (int i = 0; i < options_.iterations[l]; ++i) {
      NormalEquations6 system = evaluate(l, T_ref_cur, result, reference);
      if (system.inliers < 6.0) {
        result.lost = true;
        return result;
      }
      if (l > 0) tracking::removeUnconstrainedIcpDirections(icp_->result(l), options_.min_icp_constraint_share, system);
      Matrix6d H = system.H;
      Vector6d b = system.b;
      H.diagonal() += prior_information;
      b += prior_information.cwiseProduct((T_ref_cur * T_ref_cur_guess.inverse()).log());
      const Eigen::LDLT<Matrix6d> ldlt(H);
      if (ldlt.info() != Eigen::Success) {
        result.lost = true;
        return result;
      }
      const Vector6d delta = ldlt.solve(-b);
      if (!delta.allFinite()) {
        result.lost = true;
        return result;
      }
      T_ref_cur = SE3d::exp(delta) * T_ref_cur;
      ++result.iterations;
      if (l == 0) result.H = system.H;
      if (stepWithinUncertainty(delta, system.H, options_.converged_step_chi2)) break;
    }
  }
  // A correction of the constant-velocity guess that no camera could make (max_motion_innovation_m)
  // is the pose sliding, not the camera moving; a place guess's bound is the keyframes' spacing.
  const Vector6d innovation = (T_ref_cur * T_ref_cur_guess.inverse()).log();
  const bool plausible =
      place ? innovation.head<3>().norm() <= options_.max_place_correction_m &&
                  innovation.tail<3>().norm() <= options_.max_place_correction_rad
            : (T_ref_cur * T_ref_cur_guess.inverse()).translation().norm() <= options_.max_motion_innovation_m;
  if (!plausible || !healthy(result)) {
    result.lost = true;
    return result;
  }
  result.T_ref_cur = T_ref_cur;
  return result;
}

// Whether the final iteration's ICP inliers fail to show that fewer than min_inlier_fraction of the level-0
// pixels landing on the model are aligned (health_test_significance).
bool DenseTracker::healthy(const TrackingResult& statistics) const {
  const auto inliers = static_cast<std::uint64_t>(std::llround(statistics.icp_inliers));
  const auto candidates = static_cast<std::uint64_t>(std::llround(statistics.icp_candidates));
  return !shareBelow(inliers, candidates, options_.min_inlier_fraction, options_.health_test_significance);
}

bool DenseTracker::explainsFrame(const TrackingResult& statistics) const {
  return statistics.icp_inliers >= options_.min_recovered_inlier_share * statistics.valid_pixels;
}

}  // namespace vifusion::slam
