#pragma once
// The kernels of slam::Slam built on their own, one command sequence per step, for
// bench_rgbd_slam's per-step entry (rgbd_slam_steps.hpp).

#include <array>
#include <memory>
#include <utility>
#include <vector>

#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_export.hpp"
#include "vifusion/map/map_maintenance.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/map/surfel_fusion.hpp"
#include "vifusion/slam/slam.hpp"
#include "vifusion/tracking/icp_term.hpp"
#include "vifusion/tracking/photometric_term.hpp"

namespace vifusion::bench {

/// The kernels of Slam built on their own, each step in its own command sequence (per
/// surfel-array parity where it matters), in Slam's order: upload, preprocess steps, tracking
/// (each dense term at each level in its own submission), fusion steps, cleanup, compaction, flip,
/// prediction, the copies of the prediction into the tracker's reference view and the reference's
/// intensity pyramid and gradients. Fusion uses the ground-truth poses (relative to the first
/// frame), so the map grows as in a well-tracked run; tracking runs DenseTracker's Gauss-Newton loop
/// from the constant-velocity guess of those poses, so its iterations per level are realistic.
struct StepPipeline {
  gpu::CapacityPlan plan;
  slam::TrackerOptions tracker_options;
  std::unique_ptr<slam::DenseTracker> tracker;
  std::unique_ptr<map::MapBuffers> map;
  std::unique_ptr<map::SurfelFusion> fusion;
  std::unique_ptr<map::MapMaintenance> maintenance;
  std::unique_ptr<map::ModelPrediction> prediction;
  std::unique_ptr<map::MapExport> exporter;  ///< reads the map for the native prediction
  gpu::BufferId splat_ids_readback;          ///< the GPU's splat winners, to check the native did the same
  std::unique_ptr<gpu::MemoryArena> arena;
  std::unique_ptr<gpu::CommandSequence> splat_ids_copy;
  std::vector<std::unique_ptr<gpu::CommandSequence>> preprocess_steps;
  std::array<std::vector<std::unique_ptr<gpu::CommandSequence>>, 2> fusion_steps;
  std::array<std::unique_ptr<gpu::CommandSequence>, 2> cleanup, compaction, predict;
  std::unique_ptr<gpu::CommandSequence> reference_copy, reference_gradients;

  /// The tracker's terms are private, so each term is built again in a plan of its own (buffer
  /// names are unique per plan) over device-local copies of the tracker's current and reference
  /// maps, refreshed before each frame's tracking (untimed): the same kernels on the same data.
  struct Terms {
    gpu::CapacityPlan plan;
    std::vector<tracking::IcpLevelInputs> icp_inputs;
    std::vector<tracking::PhotometricLevelInputs> photometric_inputs;
    std::vector<std::pair<gpu::BufferId, gpu::BufferId>> copies;  ///< tracker arena → this arena
    std::unique_ptr<tracking::IcpTerm> icp;
    std::unique_ptr<tracking::PhotometricTerm> photometric;
    std::unique_ptr<gpu::MemoryArena> arena;
    std::unique_ptr<gpu::CommandSequence> refresh, level0_readback;
    std::vector<std::unique_ptr<gpu::CommandSequence>> icp_levels, photometric_levels;
    /// Readback copies of the level-0 inputs, which the native loops read.
    gpu::BufferId cur_vertices, cur_normals, cur_intensity, ref_vertices, ref_normals, ref_intensity, ref_gradients;
  } terms;

  /// Builds every kernel and records every step (start-up work, untimed).
  StepPipeline(const RigCalibration& calibration, const slam::SlamOptions& options);

  template <typename T>
  const T* host(gpu::BufferId id) const {
    return terms.arena->buffer(id).hostSpan<const T>().data();
  }
};

}  // namespace vifusion::bench
