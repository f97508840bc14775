#pragma once
// Model prediction on the GPU (DESIGN.md §4.4): the active, stable surfels of the map splatted as
// disks into the camera at pose T_C_W, giving the camera-frame vertex, normal and intensity maps
// the tracking terms align the next frame against, at every pyramid level.
// With PredictionOptions::surfels = PredictedSurfels::kInactive the same rendering shows the
// inactive stable surfels instead (ElasticFusion's inactive model, which local loop closure
// registers the active one against): a second instance with its own buffers, named
// "prediction_inactive.*" in the capacity plan.
//
// Per frame, recorded once per surfel-array parity:
//   clear → map_predict_depth (atomicMin of depth bits) → map_predict_id (atomicMin of the index
//   among surfels at the minimum depth) → map_predict_attributes (the winner writes level 0) →
//   map_pyramid_subsample (levels ≥ 1 sample level 0 at 2^l·(x, y)).
// On devices with 64-bit buffer atomics (GpuFeatures::int64_atomics) the two splat passes are one,
// map_predict_splat64 (atomicMin of key << 32 | index), and map_predict_attributes64 unpacks it:
// the same winners from one traversal of the surfels instead of two.
// Which surfels are rendered and how a disk is splatted: shaders/include/map/prediction.glsl.
// The pose and frame live in a host-written parameter buffer (setView), so nothing is re-recorded.

#include <cstdint>
#include <memory>
#include <vector>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/prediction_cpu.hpp"

namespace vifusion::map {

/// Which surfels one submission renders (ModelPrediction::setView): PredictionParams' surfels and created_before.
struct SurfelSelection {
  PredictedSurfels surfels = PredictedSurfels::kActive;
  std::uint32_t created_before = kAnyCreationFrame;  ///< only surfels created before this frame
};

struct PredictionOptions {
  int levels = 3;  ///< pyramid levels of the model maps, as the preprocessing pyramids
  /// Which surfels this instance renders (prediction.glsl states the rules). Fixed at construction:
  /// it names the instance's buffers, so an active and an inactive prediction share one plan.
  PredictedSurfels surfels = PredictedSurfels::kActive;
  /// Before this frame every active surfel is rendered, stable or not (kActive only): a surfel gains at most 1
  /// confidence per frame, so none can be stable before frame confidence_threshold and tracking
  /// would have no model. 20 frames (≈ 0.7 s at 30 Hz) leaves time for the first surfels to
  /// reach the default threshold of 10 even when seen off-centre (weight ≈ 0.5 per frame).
  std::uint32_t young_map_frames = 20;
  float min_depth_m = 0.1f;                   ///< surfel centres nearer than this are not rendered [m]
  int max_half_footprint_px = 3;              ///< a disk covers at most 7 × 7 px
  std::uint32_t surfel_workgroups = 512;      ///< workgroups of the grid-stride splat passes
  std::uint32_t surfel_workgroup_size = 128;  ///< invocations per splat workgroup
  std::uint32_t image_workgroup_size = 16;    ///< square workgroups of the per-pixel passes

  /// Throws vifusion::Error naming the field that is out of range.
  void validate() const;
};

/// Model maps of one pyramid level (device-local, row-major, camera frame).
struct ModelLevelBuffers {
  gpu::BufferId vertices;   ///< vec4 (x, y, z, z_obs) [m] (z_obs: observed from), vec4(0) = no model
  gpu::BufferId normals;    ///< vec4 (n, 1), facing the camera, vec4(0) = no model
  gpu::BufferId intensity;  ///< float 0..255, 0 = no model
};

class ModelPrediction {
 public:
  /// Declares the parameter, splat and model-map buffers. `camera`: level-0 intrinsics, the size of
  /// the map's index map. Throws vifusion::Error on bad options or a size mismatch.
  ModelPrediction(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map, const PinholeCamera& camera,
                  const PredictionOptions& options = {});
  ~ModelPrediction();

  /// Creates the kernels and writes their bindings (one set per surfel-array parity).
  void build(const gpu::MemoryArena& arena);

  /// The parameters a prediction at T_C_W in frame `frame` uses (also the CPU reference's input).
  PredictionParams makeParams(const SE3d& T_C_W, std::uint32_t frame) const;
  /// Writes them for the next submission (host, no allocation).
  void setView(const SE3d& T_C_W, std::uint32_t frame) const;
  /// The same with another selection for this one submission: a camera entering a saved map is verified against
  /// every stable surfel (kStable) by the active instance, whose buffers the tracker reads; the inactive
  /// instance shows a loaded map's surfels only (created_before its first frame) for their reactivation. The
  /// inactive instance's selection stays kInactive, and the active one's is never kInactive (their buffers'
  /// meanings). @throws vifusion::Error for such a selection
  void setView(const SE3d& T_C_W, std::uint32_t frame, const SurfelSelection& selection) const;

  /// Records the prediction from surfel array `parity` (MapBuffers::current() when it runs),
  /// ending with a compute barrier that makes the model maps visible to later kernels and copies.
  void record(gpu::CommandRecorder& recorder, int parity) const;

  const PredictionOptions& options() const { return options_; }
  PredictedSurfels surfels() const { return options_.surfels; }
  int levels() const { return options_.levels; }
  const PinholeCamera& camera(int level) const { return cameras_.at(static_cast<std::size_t>(level)); }
  const ModelLevelBuffers& level(int level) const { return levels_.at(static_cast<std::size_t>(level)); }
  gpu::BufferId splatDepthBits() const { return depth_bits_; }  ///< splat key (prediction.glsl) per level-0 pixel
  gpu::BufferId splatIds() const { return ids_; }               ///< uint per level-0 pixel, kNoSurfel = none
  gpu::BufferId paramsBuffer() const { return params_; }        ///< PredictionParams of the next submission

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  PredictionOptions options_;
  MapOptions map_options_;
  gpu::BufferId surfels_[2];
  gpu::BufferId state_;
  std::vector<PinholeCamera> cameras_;
  gpu::BufferId params_;
  gpu::BufferId depth_bits_;
  gpu::BufferId ids_;
  bool int64_splat_ = false;  ///< one 64-bit splat pass instead of two 32-bit ones
  gpu::BufferId splat64_;     ///< uint64 per level-0 pixel: key << 32 | index (int64_splat_ only)
  std::vector<ModelLevelBuffers> levels_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
};

}  // namespace vifusion::map
