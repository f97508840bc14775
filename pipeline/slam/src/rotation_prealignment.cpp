#include "vifusion/slam/rotation_prealignment.hpp"

#include <Eigen/Cholesky>
#include <limits>
#include <string>
#include <utility>

#include "vifusion/core/so3.hpp"
#include "vifusion/preprocess/kernel_params.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::slam {
namespace {

/// Three rows determine a rotation; fewer is a blank or saturated image.
constexpr double kMinRotationRows = 3.0;

}  // namespace

RotationPrealignment::RotationPrealignment(gpu::GpuContext& context, gpu::CapacityPlan& plan,
                                           const preprocess::PreprocessStage& stage,
                                           const tracking::PhotometricOptions& options, int iterations,
                                           double converged_step_rad)
    : context_(context), stage_(stage), iterations_(iterations), converged_step_rad_(converged_step_rad) {
  const int coarsest = stage.levels() - 1;
  for (int r = 0; r < kLevels; ++r) {
    Level& level = levels_[static_cast<std::size_t>(r)];
    level.camera = stage.camera(0).atLevel(coarsest + r);
    const auto pixels =
        static_cast<std::uint64_t>(level.camera.width) * static_cast<std::uint64_t>(level.camera.height);
    const auto add = [&](const char* what, std::uint64_t bytes) {
      return plan.addBuffer("tracker.rotation.l" + std::to_string(r) + "." + what, bytes, gpu::MemoryUse::DeviceLocal);
    };
    if (r == 0) {
      level.current_intensity = stage.level(coarsest).intensity;
      level.current_gradients = stage.level(coarsest).gradients;
    } else {
      level.current_intensity = add("current.intensity", pixels * sizeof(float));
      level.current_gradients = add("current.gradients", pixels * sizeof(preprocess::GradientPixel));
    }
    level.previous_intensity = add("previous.intensity", pixels * sizeof(float));
    level.previous_gradients = add("previous.gradients", pixels * sizeof(preprocess::GradientPixel));
  }
  term_ = std::make_unique<tracking::RotationTerm>(context, plan, kLevels, options);
}

RotationPrealignment::~RotationPrealignment() = default;

void RotationPrealignment::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  std::vector<tracking::RotationInputs> inputs;
  for (const Level& level : levels_) {
    inputs.push_back({level.current_intensity, level.previous_intensity, level.previous_gradients});
  }
  term_->build(arena, inputs);

  gpu::KernelSpec pyramid_spec;
  pyramid_spec.name = "pyramid_down_intensity";
  pyramid_spec.spirv = shaders::pyramid_down_intensity;
  pyramid_spec.storage_buffers = 2;
  pyramid_spec.push_constant_bytes = sizeof(preprocess::PyramidDownIntensityParams);
  pyramid_spec.max_binding_sets = kExtraLevels;
  pyramid_kernel_ = gpu::ComputeKernel::create(context_, std::move(pyramid_spec));
  gpu::KernelSpec gradient_spec;
  gradient_spec.name = "intensity_gradient";
  gradient_spec.spirv = shaders::intensity_gradient;
  gradient_spec.storage_buffers = 2;
  gradient_spec.push_constant_bytes = sizeof(preprocess::IntensityGradientParams);
  gradient_spec.max_binding_sets = kExtraLevels;
  gradient_kernel_ = gpu::ComputeKernel::create(context_, std::move(gradient_spec));
  for (int r = 1; r < kLevels; ++r) {
    const Level& fine = levels_[static_cast<std::size_t>(r - 1)];
    const Level& level = levels_[static_cast<std::size_t>(r)];
    pyramid_sets_.push_back(
        pyramid_kernel_->bind({&arena.buffer(fine.current_intensity), &arena.buffer(level.current_intensity)}));
    gradient_sets_.push_back(
        gradient_kernel_->bind({&arena.buffer(level.current_intensity), &arena.buffer(level.current_gradients)}));
  }
  for (int r = 0; r < kLevels; ++r) {
    sequences_.push_back(gpu::CommandSequence::create(context_, "tracker.rotation.l" + std::to_string(r)));
    sequences_.back()->record([&](gpu::CommandRecorder& recorder) { term_->record(recorder, r); });
  }
}

void RotationPrealignment::recordKeepPrevious(gpu::CommandRecorder& recorder) const {
  for (const Level& level : levels_) {
    for (auto [from, to] : {std::pair{level.current_intensity, level.previous_intensity},
                            std::pair{level.current_gradients, level.previous_gradients}}) {
      recorder.copyBuffer(arena_->buffer(from), arena_->buffer(to), arena_->buffer(to).bytes);
    }
  }
}

void RotationPrealignment::recordPyramid(gpu::CommandRecorder& recorder) const {
  for (int r = 1; r < kLevels; ++r) {
    const PinholeCamera& fine = levels_[static_cast<std::size_t>(r - 1)].camera;
    const PinholeCamera& camera = levels_[static_cast<std::size_t>(r)].camera;
    const auto width = static_cast<std::uint32_t>(camera.width);
    const auto height = static_cast<std::uint32_t>(camera.height);
    recorder.dispatch(*pyramid_kernel_, pyramid_sets_[static_cast<std::size_t>(r - 1)],
                      pyramid_kernel_->groupsFor(width, height),
                      preprocess::PyramidDownIntensityParams{fine.width, fine.height});
    recorder.computeBarrier();
    recorder.dispatch(*gradient_kernel_, gradient_sets_[static_cast<std::size_t>(r - 1)],
                      gradient_kernel_->groupsFor(width, height),
                      preprocess::IntensityGradientParams{camera.width, camera.height});
  }
  recorder.computeBarrier();
}

Eigen::Quaterniond RotationPrealignment::align(const Eigen::Quaterniond& q_prev_cur_guess) const {
  if (frames_ < 2) return q_prev_cur_guess;
  Eigen::Quaterniond q = q_prev_cur_guess;
  for (int r = kLevels - 1; r >= 0; --r) {
    const PinholeCamera& camera = levels_[static_cast<std::size_t>(r)].camera;
    Eigen::Quaterniond q_kept = q;
    double kept_cost = std::numeric_limits<double>::infinity();
    for (int i = 0; i < iterations_; ++i) {
      term_->setRotation(r, q, camera);
      sequences_[static_cast<std::size_t>(r)]->run();
      const NormalEquations6 system = term_->result(r);
      if (!(system.inliers >= kMinRotationRows)) break;
      const double cost = system.weighted_squared_residual / system.inliers;
      if (!(cost < kept_cost)) break;  // the last step made it worse: keep the iterate before it
      kept_cost = cost;
      q_kept = q;
      const Eigen::LDLT<Eigen::Matrix3d> ldlt(system.H.bottomRightCorner<3, 3>());
      if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) break;
      const Eigen::Vector3d step = ldlt.solve(-system.b.tail<3>());
      if (!step.allFinite()) break;
      q = (expSO3(step) * q).normalized();
      if (step.norm() < converged_step_rad_) {
        q_kept = q;
        break;
      }
    }
    q = q_kept;
  }
  return q;
}

}  // namespace vifusion::slam
