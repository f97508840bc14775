#pragma once
// Model-to-model registration of local loop closure (ElasticFusion's "active vs inactive", DESIGN.md §4.5):
// the map's ACTIVE surfels (seen within the time window) and its INACTIVE ones (the older map the camera has
// come back to) are each rendered at the current camera pose; where the camera drifted, the two renderings of
// the same surfaces are offset. This aligns the active rendering (as "current") to the inactive one (as
// "reference") by point-to-plane ICP coarse to fine (tracking/icp_term.hpp, the tracker's kernel and noise
// model) from the identity, and decides whether the alignment is trustworthy enough to deform the map with.
//
// Photometric alignment is left out: both renderings carry the surfels' colours, but an inactive surface
// fused before the drift and an active one fused after it have different sampling and exposure histories,
// and geometry alone is what the acceptance tests below can judge (ICP's noise model is the sensor's).
//
// Acceptance (RegistrationOptions; a refusal names the test that failed):
//   overlap      inliers ≥ min_overlap_share · level-0 pixels: enough of the view is the same surfaces;
//   residual     mean χ² per inlier (Σ w r² / inliers, w the ICP's Huber-weighted inverse variance)
//                ≤ max_mean_chi2: the aligned models agree to the sensor's own noise;
//   (free)       the directions the surfaces leave free (tracking/icp_degeneracy.hpp's share test: a wall
//                alone leaves two translations and a turn) are left out: the steps do not move along them, and
//                the tests below and the correction's χ² are taken over the directions the surfaces constrain
//                (the pseudo-inverse of the projected information);
//   covariance   the alignment's largest position and rotation σ (σ_r, σ_θ: from the ICP information scaled
//                for the pixels' correlation, as DenseTermsOptions does) move a point at the far end of the
//                depth range by σ_p = √(σ_r² + z_far²·σ_θ²) ≤ max_pose_to_depth_sigma · σ_z(z_far): the
//                correction is known to the sensor's own noise there, so deforming the map by it adds no more
//                error than fusing one more frame (the bound of slam/tracking_state.hpp's IMU-carried frames);
//   correction   the correction within max_correction_m / max_correction_rad: local closure corrects drift
//                since the surfaces went inactive, and ICP from the identity has no wider basin anyway;
//   conditioning a correction that is evidence of drift (below) is refused as unconstrained when a direction
//                is free: the map would be moved by a correction nobody measured along that direction. One
//                that is not is accepted all the same: along a free direction the two renderings agree
//                whatever their offset, so reactivating the old surfaces (nothing moved) changes no geometry,
//                while refusing left the revisit to be mapped again beside them as a second active layer.
// Whether a correction ξ = log(T_inactive_active) is evidence of drift at all: χ² = ξᵀ Σ⁺ ξ against
// min_correction_chi2 for the number of constrained directions, with Σ = (1/s + Σ w e²)·H⁺: the covariance above
// (s the information scale) plus the systematic error the rig's calibration leaves. Each ICP row's share of it
// is e = σ_b·|z_obs,active² − z_obs,inactive²| (tracking::IcpOptions::inverse_depth_bias_sigma_per_m: a 1/z bias
// error moves a point observed from z_obs by b·z_obs²), and the solution's is bounded by δᵀHδ ≤ Σ w e²
// (Cauchy–Schwarz), whatever the pattern. Surfaces fused from different distances carry different remnants of
// the bias, and along an overlap's weak directions a few millimetres of it turn into centimetres and a degree. Below
// the threshold the two models agree to the alignment's noise and the calibration's, and moving the map by ξ would move
// it by them (LoopClosure then reactivates the old surfaces without deforming anything). The covariance test stays with
// the random part: it asks whether the alignment measured the correction, not whether the sensor is unbiased.
//   offset       a correction that is no evidence of drift is accepted (to reactivate) only if it moves a point at
//                the far end of the depth range by √(|ξ_t|² + z_far²·|ξ_θ|²) ≤ max_pose_to_depth_sigma · σ_z(z_far):
//                then the two layers coincide to the sensor's noise and fusing the revisit into the old surfaces
//                is what fusing one more frame would do. A larger one ("ambiguous") is neither drift the alignment
//                can tell from the calibration's remnant nor agreement: reactivating would lay two surfaces that
//                far apart into the active map, where tracking pulls between them, so neither is done.
//
// Lifecycle: construct (declares the ICP's buffers in the plan) → build(arena, level inputs) once → align()
// when a closure is tried. No allocation in align().

#include <array>
#include <memory>
#include <span>
#include <vector>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/tracking/icp_term.hpp"

namespace vifusion::slam {

struct RegistrationOptions {
  /// Gauss-Newton iterations per level, finest first (ElasticFusion's tracking schedule).
  std::array<int, 3> iterations = {10, 5, 4};
  /// A level stops early when the step is below this (translation [m] and rotation [rad]).
  double converged_step = 1e-5;
  /// Inliers as a share of the level-0 pixels: ElasticFusion's 35 000 of 640×480 (0.114), made
  /// resolution-independent. In (0, 1].
  double min_overlap_share = 0.1;
  /// Mean χ² per inlier at the solution. With the sensor's noise model a correct alignment gives ≤ 1 (the
  /// renderings are fused, less noisy than one frame); in (0, ∞).
  double max_mean_chi2 = 1.0;
  /// ICP translation directions with less than this share of the weight count as unconstrained (the
  /// tracker's DenseTermsOptions::icp_min_constraint_share). In [0, 1/3).
  double min_constraint_share = 0.02;
  /// The information's scale for the pixels' correlation (DenseTermsOptions::information_scale). In (0, 1].
  double information_scale = 0.01;
  /// The covariance test's bound on σ_p(z_far), and the offset test's on an agreeing correction's displacement
  /// at z_far, as a multiple of σ_z(z_far) (see above). > 0.
  double max_pose_to_depth_sigma = 1.0;
  /// Largest correction accepted [m], [rad] (ElasticFusion refuses a 0.3 m jump in tracking).
  double max_correction_m = 0.3;
  double max_correction_rad = 0.2;
  /// A correction with χ² = ξᵀ Σ⁺ ξ below entry k−1 is no evidence of drift when the surfaces constrain k
  /// directions: the 0.99 quantiles of χ² with 1…6 degrees of freedom (a correct alignment of undrifted models
  /// stays below it 99 % of the time). Each > 0.
  std::array<double, 6> min_correction_chi2 = {6.635, 9.210, 11.345, 13.277, 15.086, 16.812};

  /// Throws vifusion::Error naming the field out of range.
  void validate() const;
};

/// Why a registration was refused (kAccepted when it was not).
enum class RegistrationVerdict {
  kAccepted,
  kNoOverlap,
  kDiverged,
  kResidual,
  kUnconstrained,
  kCovariance,
  kCorrection,
  kAmbiguous
};
const char* registrationVerdictName(RegistrationVerdict verdict);

struct RegistrationResult {
  /// The active rendering's camera in the inactive rendering's camera: T_ref_cur (identity when nothing moved)
  SE3d T_inactive_active;
  RegistrationVerdict verdict = RegistrationVerdict::kNoOverlap;
  double inliers = 0.0;     ///< level-0 ICP inliers at the solution (refused for overlap: at the level it stopped)
  double candidates = 0.0;  ///< level-0 active pixels offered (likewise)
  double mean_chi2 = 0.0;   ///< Σ w r² / inliers at the solution
  double position_sigma_m = 0.0;    ///< σ_r: largest position σ [m]
  double rotation_sigma_rad = 0.0;  ///< σ_θ: largest rotation σ [rad]
  double far_sigma_m = 0.0;         ///< σ_p(z_far) = √(σ_r² + z_far²·σ_θ²) [m], the covariance test's figure
  double correction_m = 0.0;        ///< |translation of log(T_inactive_active)| [m]
  double correction_rad = 0.0;      ///< |rotation of log(T_inactive_active)| [rad]
  double correction_far_m = 0.0;    ///< √(|ξ_t|² + z_far²·|ξ_θ|²) [m], the offset test's figure
  double correction_chi2 = 0.0;  ///< ξᵀ Σ⁺ ξ of the correction, Σ with the systematic part (min_correction_chi2)
  double bias_bound = 0.0;       ///< Σ w e²: the systematic part's scale (0 without a calibrated σ_b)
  int free_directions = 0;       ///< directions left out as unconstrained (0–4; icp_degeneracy.hpp)
  int iterations = 0;
  bool accepted() const { return verdict == RegistrationVerdict::kAccepted; }
  /// The correction is evidence of drift (χ² ≥ min_correction_chi2; set by align() once the tests before the
  /// conditioning passed).
  bool significant = false;
};

/// Both renderings at one pyramid level (camera frame of the current pose).
struct RegistrationLevel {
  PinholeCamera camera;
  gpu::BufferId active_vertices, active_normals;      ///< "current"
  gpu::BufferId inactive_vertices, inactive_normals;  ///< "reference"
};

class ModelRegistration {
 public:
  /// Declares the ICP's buffers for `levels` levels (1..3). `far_depth_m`: the far end of the depth range [m],
  /// where the covariance test is taken. Throws vifusion::Error on bad options.
  ModelRegistration(gpu::GpuContext& context, gpu::CapacityPlan& plan, int levels, const tracking::IcpOptions& icp,
                    double far_depth_m, const RegistrationOptions& options = {});
  ~ModelRegistration();

  /// Creates the kernels and records one sequence per level over `levels` (finest first).
  void build(const gpu::MemoryArena& arena, std::span<const RegistrationLevel> levels);

  /// Aligns the active rendering to the inactive one from the identity and judges the result.
  RegistrationResult align();

  const RegistrationOptions& options() const { return options_; }

 private:
  gpu::GpuContext& context_;
  RegistrationOptions options_;
  double far_depth_m_ = 0.0;
  double far_depth_sigma_m_ = 0.0;  ///< σ_z(z_far) [m]
  int levels_ = 0;
  std::vector<PinholeCamera> cameras_;
  std::unique_ptr<tracking::IcpTerm> icp_;
  std::vector<std::unique_ptr<gpu::CommandSequence>> sequences_;
};

}  // namespace vifusion::slam
