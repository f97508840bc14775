#pragma once
// Fusion of one RGB-D frame into the surfel map on the GPU (DESIGN.md §4.4): index map of the
// active surfels, data association, confidence-weighted fusion and new surfels, deterministic
// whatever the execution order (see the shaders map_index/associate/fuse/insert.comp).
//
// Lifecycle: construct (declares its scratch buffers in the plan) → build(arena, inputs) once →
// record(recorder) once per surfel-array parity → every frame setFrame(T_W_C, frame, uncertainty), submit.
// Per-frame values live in a host-written parameter buffer, so nothing is re-recorded or
// allocated per frame.

#include <cstdint>
#include <memory>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/map/fusion_params.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"

namespace vifusion::map {

/// The current frame's buffers the fusion reads (level 0, the map's index-map size).
struct FusionInputs {
  gpu::BufferId vertices;   ///< VertexPixel, camera frame [m]
  gpu::BufferId normals;    ///< NormalPixel, camera frame
  gpu::BufferId rgb_words;  ///< packed RGB888 upload (preprocess/packing.hpp)

  /// Level-0 vertices (unfiltered depth) and normals (filtered depth) of `stage`, and its RGB upload.
  static FusionInputs fromPreprocess(const preprocess::PreprocessStage& stage);
};

/// The recorded steps in order; benchmarks record them one at a time.
enum class FusionStep { Index, Associate, Fuse, Insert };
inline constexpr FusionStep kAllFusionSteps[] = {FusionStep::Index, FusionStep::Associate, FusionStep::Fuse,
                                                 FusionStep::Insert};
const char* fusionStepName(FusionStep step);

class SurfelFusion {
 public:
  /// `map` must outlive this object; `camera` is the level-0 camera (the map's index-map size).
  SurfelFusion(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map, const PinholeCamera& camera,
               const FusionOptions& options = {});
  ~SurfelFusion();
  SurfelFusion(const SurfelFusion&) = delete;
  SurfelFusion& operator=(const SurfelFusion&) = delete;

  /// Creates the kernels and writes one binding set per surfel-array parity.
  void build(const gpu::MemoryArena& arena, const FusionInputs& inputs);

  /// Writes the parameters of the next submission: pose T_W_C (camera → world), its uncertainty (zero
  /// for a registered frame) and frame number. Call only while no submission that reads them is in flight.
  void setFrame(const SE3d& T_W_C, std::uint32_t frame, const FusionPoseUncertainty& uncertainty = {});
  const FusionParams& params() const { return params_; }

  /// Records the whole fusion for surfel array `parity`, ending with a barrier that makes the map
  /// visible to later kernels and transfers (not to the host: add hostReadBarrier to read it).
  void record(gpu::CommandRecorder& recorder, int parity) const;
  void record(gpu::CommandRecorder& recorder) const { record(recorder, map_.current()); }
  /// Records one step followed by a barrier (benchmarks).
  void recordStep(gpu::CommandRecorder& recorder, FusionStep step, int parity) const;

  gpu::BufferId pixelMatch() const { return pixel_match_; }    ///< uint per pixel, see kPixelNewSurfel
  gpu::BufferId surfelClaim() const { return surfel_claim_; }  ///< uint per surfel: claiming pixel or kUnclaimed

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  const MapBuffers& map_;
  PinholeCamera camera_;
  FusionOptions options_;
  FusionParams params_;
  gpu::BufferId params_buffer_;
  gpu::BufferId pixel_match_;
  gpu::BufferId surfel_claim_;
  gpu::BufferId run_counts_;       ///< new surfels per pixel run (map_associate), then offsets (map_insert)
  std::uint32_t run_pixels_ = 0;  ///< pixels per run of map_associate and map_insert
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
};

}  // namespace vifusion::map
