#pragma once
// Dense RGB-D tracking on the GPU: preprocesses each frame, then aligns it to a reference view by
// Gauss-Newton over the ICP and photometric terms, coarse to fine. The two terms are each weighted
// by their inverse measurement variances inside the kernels (depth noise model, intensity noise), so
// their normal equations simply add: no hand-tuned λ between them. The reference view is the surfel
// map's prediction: its owner copies the predicted vertex and normal maps into reference(l) at every
// level and the intensity into reference(0), then records recordReferenceIntensity().

#include <array>
#include <memory>
#include <vector>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/tracking/icp_term.hpp"
#include "vifusion/tracking/photometric_term.hpp"

namespace vifusion::slam {

struct TrackerOptions {
  int levels = 3;
  /// Gauss-Newton iterations per level, finest first (ElasticFusion: 10, 5, 4).
  std::array<int, 3> iterations = {10, 5, 4};
  /// Stop a level early when the step is below this (translation [m] and rotation [rad]).
  double converged_step = 1e-5;
  bool use_photometric = true;
  /// Filter, pyramid and normal settings; camera, levels and depth scale are set by the tracker.
  preprocess::PreprocessOptions preprocess;
  tracking::IcpOptions icp;
  tracking::PhotometricOptions photometric;
  /// Tracking is lost when fewer than this fraction of the level-0 pixels with valid depth end up
  /// as ICP inliers (the rest fell outside the reference view or failed the gates).
  double min_inlier_fraction = 0.2;

  /// Throws vifusion::Error naming the field out of range.
  void validate() const;
};

/// The outcome of aligning one frame.
struct TrackingResult {
  SE3d T_ref_cur;            ///< estimated pose of the current camera in the reference camera
  bool lost = false;         ///< too few inliers or a degenerate system: T_ref_cur is the guess
  double icp_inliers = 0.0;     ///< level-0 ICP inliers of the last iteration
  double icp_candidates = 0.0;  ///< level-0 pixels with valid depth (the inliers' denominator)
  double rgb_inliers = 0.0;  ///< level-0 photometric inliers of the last iteration
  int iterations = 0;        ///< Gauss-Newton iterations run over all levels
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();  ///< last level-0 system (information)
};

class DenseTracker {
 public:
  /// Declares the preprocessing, reference-view and term buffers in `plan`. `depth_scale_m` is the
  /// metres per raw depth unit of the source.
  DenseTracker(gpu::GpuContext& context, gpu::CapacityPlan& plan, const PinholeCamera& camera, double depth_scale_m,
               const TrackerOptions& options);
  ~DenseTracker();

  /// Creates kernels and records every command sequence once.
  void build(const gpu::MemoryArena& arena);

  /// Uploads and preprocesses a frame (no allocation).
  void preprocess(const RgbdFrame& frame);
  /// Aligns the preprocessed frame to the reference view starting from `T_ref_cur_guess`.
  TrackingResult track(const SE3d& T_ref_cur_guess);

  /// The dense terms' normal equations at `level` for the pose T_ref_cur, over a LEFT perturbation in
  /// the reference camera frame: T_ref_cur ← exp(δ)·T_ref_cur, δ = [ρ; φ] (se3.hpp), H = JᵀWJ, b = JᵀWr,
  /// so the Gauss-Newton step is δ = −H⁻¹b. Each term is already weighted by its inverse measurement
  /// variance. Fills the inlier counts of `statistics`. For estimators that add their own terms (the
  /// two-state RGB-D-inertial solver); track() runs the same evaluation.
  NormalEquations6 evaluate(int level, const SE3d& T_ref_cur, TrackingResult& statistics);
  /// The ICP term's part of the last evaluate() at `level` (icp_degeneracy.hpp needs it on its own).
  NormalEquations6 icpEquations(int level) const;
  /// The tracking-health test on the statistics of a final level-0 evaluation (see min_inlier_fraction).
  bool healthy(const TrackingResult& statistics) const;

  const TrackerOptions& options() const { return options_; }

  /// Buffers of the reference view at `level` (vertices, normals, intensity in the reference camera
  /// frame; coarser intensities and all gradients are derived by recordReferenceIntensity).
  const preprocess::LevelBuffers& reference(int level) const { return reference_[level]; }
  /// Records the reference's intensity pyramid from its level 0, with the current frame's Gaussian
  /// (a point-sampled model at the coarse levels would see sharper edges than the blurred current
  /// frame, and the coarse photometric solution would start level 0 outside its basin — measured:
  /// 8 mm after one frame instead of 1 mm), then its gradients at every level.
  void recordReferenceIntensity(gpu::CommandRecorder& recorder) const;

  const preprocess::PreprocessStage& preprocessing() const { return *stage_; }
  const PinholeCamera& camera(int level) const { return stage_->camera(level); }

 private:
  gpu::GpuContext& context_;
  TrackerOptions options_;
  std::unique_ptr<preprocess::PreprocessStage> stage_;
  std::vector<preprocess::LevelBuffers> reference_;  ///< copies of the reference view's maps
  std::unique_ptr<tracking::IcpTerm> icp_;
  std::unique_ptr<tracking::PhotometricTerm> photometric_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<gpu::CommandSequence> preprocess_sequence_;
  std::unique_ptr<gpu::ComputeKernel> gradient_kernel_;
  std::vector<gpu::BindingSet> gradient_sets_;
  std::unique_ptr<gpu::ComputeKernel> pyramid_kernel_;
  std::vector<gpu::BindingSet> pyramid_sets_;  ///< level l−1 → l, for l ≥ 1
  std::vector<std::unique_ptr<gpu::CommandSequence>> level_sequences_;
};

}  // namespace vifusion::slam
