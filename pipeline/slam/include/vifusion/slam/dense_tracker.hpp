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
#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/core/step_convergence.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/slam/rotation_prealignment.hpp"
#include "vifusion/tracking/icp_term.hpp"
#include "vifusion/tracking/photometric_term.hpp"

namespace vifusion::slam {

struct TrackerOptions {
  int levels = 3;
  /// Gauss-Newton iterations per level, finest first (ElasticFusion: 10, 5, 4).
  std::array<int, 3> iterations = {10, 5, 4};
  /// Stop a level early when the step's squared Mahalanobis length under the dense terms' information is
  /// below this (core/step_convergence.hpp: the step is within the estimate's own noise). > 0.
  double converged_step_chi2 = kChi2SixDofQuantile001;
  bool use_photometric = true;
  /// ElasticFusion's rotation-only pre-alignment (rotation_prealignment.hpp): before the six-parameter
  /// solve, the guess's rotation is refined against the previous frame's coarse intensity images by the
  /// homography of a pure rotation. It needs neither depth nor the map, so it follows fast pans into views
  /// the map does not cover yet, where the constant-velocity guess is degrees off after a lost frame.
  bool rotation_prealignment = true;
  /// Gauss-Newton iterations of the pre-alignment per level (ElasticFusion: 10 at its one level); a level
  /// stops earlier when its rotation step is below rotation_converged_step_rad [rad].
  int rotation_iterations = 10;
  double rotation_converged_step_rad = 1e-5;
  /// Filter, pyramid and normal settings; camera, levels and depth scale are set by the tracker.
  preprocess::PreprocessOptions preprocess;
  tracking::IcpOptions icp;
  tracking::PhotometricOptions photometric;
  /// Tracking is lost when fewer than this fraction of the level-0 pixels that land on the model
  /// prediction pass the ICP gates. Pixels that see what the map does not hold yet do not count:
  /// a fast camera turns into unmapped space faster than new surfels become stable, and counting
  /// them declared aligned frames lost, which then were not fused, so the map never grew into the
  /// new view (sim:fast at 640×480, RGB-D-inertial: 403 of 601 frames lost, ATE 453 mm; the
  /// aligned share of the covered pixels never fell below 0.5 there: 0 lost, 14.3 mm).
  double min_inlier_fraction = 0.2;
  /// The health test is a one-sided binomial test (core/binomial_test.hpp), not a hard ratio: a frame is lost
  /// when its ICP inliers show the share below min_inlier_fraction at this significance. On a view the map
  /// hardly covers (a fast turn, where the photometric term aligns the frame to the previous one's fill) a
  /// handful of candidates shows nothing either way; as a ratio, one failing candidate made the frame lost
  /// while none left it tracked. For a covered view the bound is the ratio less z_α standard errors (0.2 less
  /// 0.002 at 300 000 candidates). 1 %, the level of the estimator's χ² gates and the closure tests. In (0, 0.5).
  double health_test_significance = 0.01;
  /// After a lost frame the health test above is not enough: from a guess seconds old (the last tracked pose
  /// after a covered camera) a frame can find a few surfaces of the old view within the innovation bound and
  /// pass it while most of the frame sees elsewhere (tests/bench/README.md, "Relocalisation"). A frame that
  /// ends a loss must also have this share of its valid level-0 pixels as ICP inliers: the loop closure's
  /// overlap test (model_registration.hpp), ElasticFusion's 35 000 of 640×480. In (0, 1].
  double min_recovered_inlier_share = 0.1;
  /// ICP degeneracy at the coarse levels. The point-to-plane term constrains translation only along
  /// the normals of the surfaces in view: two planes (wall and ceiling) leave their common direction
  /// free, yet noisy normals give it a formal information that looks decisive, while the residuals of
  /// quantised depth are biased along it (sim:living_room_1 at 320×240, frame 187: level 2 moved
  /// 23 mm in one step where the full-resolution terms are flat, out of the photometric term's basin,
  /// and the pose ran away). At levels ≥ 1 a translation direction e is therefore left to the
  /// photometric term and the motion prior when the surfaces give it less than this share of the ICP
  /// weight, Σw(n·e)²/Σw (the smallest eigenvalue of the ICP's translation block over its trace: 1/3
  /// in a box corner, 0 for one plane; on that view noisy normals alone give 0.004–0.009, with a third
  /// wall in the model 0.07–0.18; for one plane the rotation about its normal goes too: the rule of
  /// tracking/icp_degeneracy.hpp, which rgbdi applies at every level). Level 0 keeps all of it here:
  /// RGB-D alone has no IMU to carry those directions, and on clean data a small share is real
  /// information (a noise-free pan of the living room sees 0.001–0.017 and needs it for 3 mm).
  double min_icp_constraint_share = 0.02;
  /// Constant-velocity motion prior, per axis of the pose change from the guess [m], [rad]: holds the
  /// directions no dense term determines; far weaker than the data in every other direction.
  double motion_prior_sigma_m = 0.01;
  double motion_prior_sigma_rad = 0.01;
  /// Tracking is lost when the estimate corrects the constant-velocity guess by more than this [m]
  /// in one frame: 5 cm per frame at 30 Hz is an acceleration of 45 m/s², far beyond a hand-held or
  /// robot camera (the living_room paths need ≤ 1.7 mm), while a pose sliding along a direction the
  /// data do not pin down gains 26–110 mm per frame (sim:living_room_1 frames 186–191 before the
  /// fixes of issue 4). Such a frame keeps the guess and is not fused, and the velocity is reset, so
  /// the run-away stops instead of corrupting the map (ElasticFusion: a 0.3 m jump is rejected).
  double max_motion_innovation_m = 0.05;
  /// RGB-D tracking is lost when the pose moved faster than this since the reference frame [m/s]: the
  /// platform's top speed with margin — a hand-held camera at a brisk walk or an indoor robot stays below
  /// 2 m/s. The bound above limits only each frame's change of the constant-velocity guess, so a pose
  /// sliding along a direction nothing observes (RGB-D facing a blank wall: one plane for the ICP, no
  /// texture for the photometric term) can gain up to that much velocity every frame while every frame
  /// passes; this stops the slide, and the frame lost to it drops the velocity. Applied by Slam, which knows
  /// the frames' stamps. > 0.
  double max_speed_mps = 3.0;
  /// After a lost frame the lost frames' pose and the recovery's "kept moving" guess continue the last tracked
  /// motion for at most this long [s], then hold: issue 15's recovery window (rgbd recovers within 1 s), and
  /// about as long as a hand-held or robot camera keeps one velocity; continuing it further only carries the
  /// guess away from the map and from the camera. Applied by Slam. > 0.
  double max_continued_motion_s = 1.0;
  /// A place guess (TrackingGuess::kPlace: a recognised keyframe's pose, relocaliser.hpp) may be corrected by
  /// at most this much [m], [rad]; the motion prior's σ are these too, so the prior holds only the directions
  /// no dense term sees, over the whole accepted range. ElasticFusion refuses a 0.3 m jump, and dense
  /// alignment has no wider basin; 0.2 rad as the loop closure's registration (model_registration.hpp).
  double max_place_correction_m = 0.3;
  double max_place_correction_rad = 0.2;
  /// Throws vifusion::Error naming the field out of range.
  void validate() const;
};

/// Which reference pixels the photometric term aligns to (reference_fill.hpp).
enum class ReferencePixels {
  kMap,         ///< the map's prediction only
  kMapAndFill,  ///< also the holes filled in from the previous fused frame (the fallback)
};

/// What track()'s guess is.
enum class TrackingGuess {
  /// The previous pose moved by the constant-velocity motion: the motion prior and max_motion_innovation_m.
  kMotion,
  /// A recognised place's keyframe pose (relocalisation): it is as far from the camera as keyframes are apart,
  /// not one frame's acceleration away, so max_place_correction_m/_rad bound it instead.
  kPlace,
};

/// The outcome of aligning one frame.
struct TrackingResult {
  SE3d T_ref_cur;               ///< estimated pose of the current camera in the reference camera
  bool lost = false;            ///< too few inliers or a degenerate system: T_ref_cur is the guess
  double icp_inliers = 0.0;     ///< level-0 ICP inliers of the last iteration
  double icp_candidates = 0.0;  ///< level-0 pixels landing on the model prediction (the inliers' denominator)
  /// level-0 ICP Σ w·r² / inliers of the last iteration: the mean squared point-to-plane residual in units of the
  /// depth noise σ_z, Huber-weighted (icp_params.hpp). About 1–2 where frame and model agree within their noise
  /// (both measure the surface: r has up to twice σ_z²); an alignment that slid along the surfaces keeps
  /// residuals of centimetres under the ICP's 10 cm gate, many σ_z.
  double icp_energy = 0.0;
  /// level-0 pixels with a valid vertex (the photometric term's candidates; the image size when it is off)
  double valid_pixels = 0.0;
  double rgb_inliers = 0.0;                           ///< level-0 photometric inliers of the last iteration
  int iterations = 0;                                 ///< Gauss-Newton iterations run over all levels
  ReferencePixels reference = ReferencePixels::kMap;  ///< what the photometric term aligned to
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();  ///< last level-0 system (information)
};

class DenseTracker {
 public:
  /// Declares the preprocessing, reference-view and term buffers in `plan`, for the calibration's camera
  /// and depth units and bias.
  DenseTracker(gpu::GpuContext& context, gpu::CapacityPlan& plan, const RigCalibration& calibration,
               const TrackerOptions& options);
  ~DenseTracker();

  /// Creates kernels and records every command sequence once.
  void build(const gpu::MemoryArena& arena);

  /// Uploads and preprocesses a frame (no allocation).
  void preprocess(const RgbdFrame& frame);
  /// Aligns the preprocessed frame to the reference view starting from `T_ref_cur_guess`.
  TrackingResult track(const SE3d& T_ref_cur_guess, ReferencePixels reference = ReferencePixels::kMap,
                       TrackingGuess guess = TrackingGuess::kMotion);
  /// A guess of the motion from the previous frame to this one with its rotation refined by the
  /// rotation-only pre-alignment (unchanged when that is off or there is no previous frame).
  SE3d prealignRotation(const SE3d& T_prev_cur_guess) const;

  /// The dense terms' normal equations at `level` for the pose T_ref_cur, over a LEFT perturbation in
  /// the reference camera frame: T_ref_cur ← exp(δ)·T_ref_cur, δ = [ρ; φ] (se3.hpp), H = JᵀWJ, b = JᵀWr,
  /// so the Gauss-Newton step is δ = −H⁻¹b. Each term is already weighted by its inverse measurement
  /// variance. Fills the inlier counts of `statistics`. For estimators that add their own terms (the
  /// two-state RGB-D-inertial solver); track() runs the same evaluation.
  NormalEquations6 evaluate(int level, const SE3d& T_ref_cur, TrackingResult& statistics,
                            ReferencePixels reference = ReferencePixels::kMap);
  /// The ICP term's part of the last evaluate() at `level` (icp_degeneracy.hpp needs it on its own).
  NormalEquations6 icpEquations(int level) const;
  /// The tracking-health test on the statistics of a final level-0 evaluation (see min_inlier_fraction).
  bool healthy(const TrackingResult& statistics) const;
  /// The stricter test of a frame that ends a loss (see min_recovered_inlier_share).
  bool explainsFrame(const TrackingResult& statistics) const;

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
  std::unique_ptr<RotationPrealignment> rotation_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<gpu::CommandSequence> preprocess_sequence_;
  std::unique_ptr<gpu::ComputeKernel> gradient_kernel_;
  std::vector<gpu::BindingSet> gradient_sets_;
  std::unique_ptr<gpu::ComputeKernel> pyramid_kernel_;
  std::vector<gpu::BindingSet> pyramid_sets_;  ///< level l−1 → l, for l ≥ 1
  std::vector<std::unique_ptr<gpu::CommandSequence>> level_sequences_;
};

}  // namespace vifusion::slam
