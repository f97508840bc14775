#pragma once
// Local loop closure by map deformation (ElasticFusion's, with the paper's gravity term; DESIGN.md §4.5).
// After each tracked frame the map's INACTIVE stable surfels are rendered at the camera's pose beside the
// active ones (map/model_prediction.hpp). Where the camera has come back to surfaces it mapped more than a time
// window ago, the two renderings show the same surfaces offset by the drift since; ModelRegistration aligns them
// and judges the alignment (model_registration.hpp). An accepted one becomes a deformation:
//   1. nodes: every stride-th surfel of the map (map/map_sampling.hpp), a deformation graph over them
//      (loop/deformation_graph.hpp);
//   2. constraints on a grid of pixels: each active surfel there goes where the registration puts it
//      (E_con), each inactive surfel there stays (E_pin), and in the inertial modes the nodes keep gravity's
//      direction (E_imu, g_W from the estimator's q_I_W). After the first accepted closure, the map created
//      before the last one is held (its nodes fixed, its active surfels pinned): that closure corrected it,
//      and a later one moves only what was mapped since (ElasticFusion's rule);
//   3. the solve must leave the constraints consistent (mean error after ≤ max_constraint_error_m), else the
//      graph is reverted and the map is left exactly as it was (the closure is refused and reported);
//   A registration whose correction is within its own noise is not a deformation: moving the map by it would
//   move it by noise. If it also moves no point by more than the depth noise, the models agree; the inactive
//   surfels in view are reactivated and nothing moves (kAgreed). If it does, it is refused as ambiguous: two
//   layers that far apart would both be tracked against.
//   4. an accepted deformation moves every surfel and normal on the GPU (map/surfel_deformation.hpp), the
//      inactive surfels in view are reactivated (map/surfel_reactivation.hpp), and the caller moves the camera
//      pose, the estimator's state (estimator::TwoStateEstimator::moveWithMap) and the trajectory it keeps
//      (deformPose).
//
// Memory: every buffer comes from the capacity plan; the graph is sized by its options at construction; the node
// samples and the constraint grid are preallocated. The deformation graph's sparse factorisation allocates inside
// Eigen on a closure (loop/deformation_graph.hpp), never on a frame without one.

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "vifusion/core/se3.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/loop/deformation_graph.hpp"
#include "vifusion/map/fusion_params.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_sampling.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/map/surfel_deformation.hpp"
#include "vifusion/map/surfel_reactivation.hpp"
#include "vifusion/slam/model_registration.hpp"
#include "vifusion/tracking/icp_params.hpp"

namespace vifusion::slam {

struct LoopClosureOptions {
  /// Off: the paper's open-loop odometry (Table IV's ablation), and nothing of this is allocated.
  bool enabled = true;
  /// The paper's E_imu in the inertial modes (rgbd has no gravity estimate and never uses it).
  bool gravity_term = true;
  RegistrationOptions registration;
  /// ElasticFusion's graph, except 4 temporal neighbours per side: with 2, nodes made in one frame (a wall strip,
  /// all neighbours above each other) have a turn about that strip no term sees (tests/unit/loop).
  loop::DeformationGraphOptions graph = [] {
    loop::DeformationGraphOptions options;
    options.neighbours_per_side = 4;
    return options;
  }();
  /// Constraint grid spacing at level 0 [px]: ElasticFusion's 32 × 24 grid at 640×480 (768 points). ≥ 1.
  int constraint_grid_step_px = 20;
  /// Mean constraint error after the solve above which the deformation is refused [m]: the deformation must
  /// put the closure's surfaces within the sensor's depth noise at 1–2 m (σ_z 1.2–3.1 mm) of each other.
  double max_constraint_error_m = 0.003;
  /// The first closure is tried this many frames after the map's start at the earliest: before a time window has
  /// passed nothing is inactive. In frames, ≥ 0 (0: the map's time window).
  std::uint32_t first_frame = 0;

  /// Throws vifusion::Error naming the field out of range.
  void validate() const;
};

/// What a frame's closure attempt did.
enum class ClosureOutcome : std::uint8_t {
  kNone,      ///< not tried (disabled, too early, frame not tracked) or no inactive map in view
  kAccepted,  ///< the map was deformed
  kRefused,   ///< registered or solved, but a test failed: the map is as it was
  /// registered and accepted, but the correction is within its own noise (RegistrationOptions::
  /// min_correction_chi2) and moves no point by more than the depth noise (model_registration.hpp's offset
  /// test): nothing moved, the inactive surfels in view were reactivated (the revisit is mapped onto the old
  /// surfaces, not beside them)
  kAgreed,
};
const char* closureOutcomeName(ClosureOutcome outcome);

/// The test a refused closure failed: the registration's (RegistrationVerdict) or the deformation's.
enum class ClosureRefusal : std::uint8_t {
  kNone,           ///< not refused
  kOverlap,        ///< RegistrationVerdict::kNoOverlap after iterating
  kDiverged,       ///< RegistrationVerdict::kDiverged
  kResidual,       ///< RegistrationVerdict::kResidual
  kUnconstrained,  ///< RegistrationVerdict::kUnconstrained
  kCovariance,     ///< RegistrationVerdict::kCovariance
  kCorrection,     ///< RegistrationVerdict::kCorrection
  kSolve,          ///< the deformation graph's solve failed
  kConsistency,    ///< the solve left the constraints inconsistent (LoopClosureOptions::max_constraint_error_m)
  kAmbiguous,      ///< RegistrationVerdict::kAmbiguous (last: frames.csv's codes of the others stay)
};
inline constexpr int kClosureRefusals = 10;
/// "none", "overlap", "diverged", "residual", "unconstrained", "covariance", "correction", "solve", "consistency",
/// "ambiguous".
const char* closureRefusalName(ClosureRefusal refusal);

struct ClosureReport {
  ClosureOutcome outcome = ClosureOutcome::kNone;
  ClosureRefusal refusal = ClosureRefusal::kNone;  ///< kRefused: the test that failed
  RegistrationResult registration;
  int nodes = 0;
  int constraints = 0;                     ///< E_con + E_pin
  double constraint_error_before_m = 0.0;  ///< mean, before the solve
  double constraint_error_after_m = 0.0;   ///< mean, after it
  double ms = 0.0;                         ///< wall time of the attempt (rendering, registration, solve, apply)
  /// Its stages [ms]: rendering the inactive model and registering (every attempt, also one that finds nothing
  /// inactive in view); node sampling, graph build and solve (attempts that reached the deformation); moving
  /// the map on the GPU and reactivating (accepted closures). 0 for a stage not reached.
  double registration_ms = 0.0;
  double deformation_ms = 0.0;
  double apply_ms = 0.0;
  /// kAccepted: the camera's correction, T_W'_W at the camera's pose (deformPose of the camera).
  SE3d T_Wnew_Wold;
};

class LoopClosure {
 public:
  /// Declares the inactive prediction, registration, sampling, deformation and reactivation in `plan`, for the
  /// active `prediction` (whose level-0 camera and levels it shares) of `map`; `fusion`: the association gates a
  /// surfel must pass to be reactivated; `far_depth_m` is the far end of the depth range [m] (ModelRegistration's
  /// covariance test).
  LoopClosure(gpu::GpuContext& context, gpu::CapacityPlan& plan, const map::MapBuffers& map,
              const map::ModelPrediction& prediction, const map::PredictionOptions& prediction_options,
              const map::FusionOptions& fusion, const tracking::IcpOptions& icp, double far_depth_m,
              const LoopClosureOptions& options);
  ~LoopClosure();

  /// Creates the kernels and sequences and runs each once on the (empty) map, so that pipelines are compiled at
  /// start-up. Call after the map was reset.
  void build(const gpu::MemoryArena& arena);

  /// After a tracked, fused frame `frame` at T_W_C (the active prediction rendered there, the map flipped):
  /// renders the inactive model, registers, and on acceptance deforms the map. `g_W`: gravity in W [m/s²] for
  /// E_imu, or nullopt (rgbd). The caller then moves its poses (deformPose) and re-renders the active prediction.
  ClosureReport tryClose(const SE3d& T_W_C, std::uint32_t frame, const std::optional<Eigen::Vector3d>& g_W);

  /// Makes the inactive surfels in view at T_W_C that were created before `created_before` active in `frame`, as
  /// an agreed closure does, without a registration: for a camera just located in a loaded map (map_loading.hpp),
  /// whose surfels have aged past the time window, and then on every tracked frame for the loaded map's surfels
  /// it sees again. Renders the inactive model, so the caller renders the active prediction again after it.
  void reactivateInView(const SE3d& T_W_C, std::uint32_t frame, std::uint32_t created_before = map::kAnyCreationFrame);
  /// A pose of frame `frame` moved by the last accepted deformation (identity before any).
  SE3d deformPose(const SE3d& T_W_C, std::uint32_t frame) const;

  const LoopClosureOptions& options() const { return options_; }

 private:
  ClosureReport deform(const SE3d& T_W_C, std::uint32_t frame, const std::optional<Eigen::Vector3d>& g_W,
                       ClosureReport report);

  gpu::GpuContext& context_;
  const map::MapBuffers& map_;
  const map::ModelPrediction& active_;
  LoopClosureOptions options_;
  std::unique_ptr<map::ModelPrediction> inactive_;
  std::unique_ptr<ModelRegistration> registration_;
  std::unique_ptr<map::MapSampling> sampling_;
  std::unique_ptr<map::PredictionGather> active_gather_;
  std::unique_ptr<map::PredictionGather> inactive_gather_;
  std::unique_ptr<map::SurfelDeformation> deformation_;
  std::unique_ptr<map::SurfelReactivation> reactivation_;
  std::unique_ptr<loop::DeformationGraph> graph_;
  std::array<std::unique_ptr<gpu::CommandSequence>, 2> render_inactive_;  ///< per surfel-array parity
  std::vector<loop::NodeSample> node_samples_;                            ///< max_nodes, preallocated
  std::vector<map::GatherPixel> grid_;                                    ///< the constraint grid
  /// Frame of the last accepted closure (0: none): the map created before it is held by the next closures.
  std::uint32_t last_accepted_frame_ = 0;
};

}  // namespace vifusion::slam
