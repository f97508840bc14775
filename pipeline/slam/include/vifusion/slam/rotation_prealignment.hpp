#pragma once
// ElasticFusion's rotation-only pre-alignment (algorithms.md §1.6), coarse to fine: the rotation between
// the previous and the current frame, found by the homography of a pure rotation on their intensities
// (tracking/rotation_term.hpp), refines the guess of the six-parameter solve. It needs neither depth nor
// the map, so it follows a fast pan into a view the map does not cover. Its pyramid starts at the
// tracker's coarsest level and halves it kExtraLevels more times: a fast pan's 5° per frame, 10 px at
// 160 × 120, is 2.5 px at 40 × 30, inside the basin of intensity alignment (at 160 × 120 alone, ten
// Gauss-Newton steps got from 5° only to 2.8°: tests/gpu/test_dense_terms.cpp).
//
// Per frame: recordKeepPrevious() (before the frame's preprocessing overwrites the coarsest level) copies
// the previous frame's pyramid aside; recordPyramid() (after it) builds the current frame's; align() runs
// Gauss-Newton from coarse to fine.

#include <array>
#include <memory>
#include <vector>

#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/tracking/photometric_params.hpp"
#include "vifusion/tracking/rotation_term.hpp"

namespace vifusion::slam {

class RotationPrealignment {
 public:
  /// Levels beyond the tracker's coarsest, each half the size of the one before.
  static constexpr int kExtraLevels = 2;
  static constexpr int kLevels = kExtraLevels + 1;

  /// Declares the pyramids of the previous and the current frame, starting from `stage`'s coarsest level.
  /// `iterations` per level (coarse to fine) stop early when a step is below `converged_step_rad`.
  RotationPrealignment(gpu::GpuContext& context, gpu::CapacityPlan& plan, const preprocess::PreprocessStage& stage,
                       const tracking::PhotometricOptions& options, int iterations, double converged_step_rad);
  ~RotationPrealignment();

  /// Creates the kernels and records the alignment's sequences once.
  void build(const gpu::MemoryArena& arena);
  /// Copies the current frame's pyramid into the previous frame's; record before the preprocessing.
  void recordKeepPrevious(gpu::CommandRecorder& recorder) const;
  /// Builds the current frame's pyramid from the stage's coarsest level; record after the preprocessing.
  void recordPyramid(gpu::CommandRecorder& recorder) const;
  /// Marks that the pyramids now hold a previous and a current frame (call after each preprocessing).
  void framePreprocessed() { ++frames_; }

  /// R_prev_cur from `q_prev_cur_guess`: at each level Gauss-Newton on the 3×3 rotation block; a step that
  /// raises the mean weighted squared residual is taken back and ends the level. The guess itself before
  /// the second frame or where too few pixels constrain the rotation.
  Eigen::Quaterniond align(const Eigen::Quaterniond& q_prev_cur_guess) const;

 private:
  struct Level {
    PinholeCamera camera;
    gpu::BufferId current_intensity, current_gradients;  ///< level 0: the stage's own buffers
    gpu::BufferId previous_intensity, previous_gradients;
  };

  gpu::GpuContext& context_;
  const preprocess::PreprocessStage& stage_;
  int iterations_ = 0;
  double converged_step_rad_ = 0.0;
  std::array<Level, kLevels> levels_;
  std::unique_ptr<tracking::RotationTerm> term_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<gpu::ComputeKernel> pyramid_kernel_, gradient_kernel_;
  std::vector<gpu::BindingSet> pyramid_sets_, gradient_sets_;  ///< levels 1..kLevels−1
  std::vector<std::unique_ptr<gpu::CommandSequence>> sequences_;
  std::uint64_t frames_ = 0;
};

}  // namespace vifusion::slam
