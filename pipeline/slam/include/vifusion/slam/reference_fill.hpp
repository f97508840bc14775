#pragma once
// Fill-in of the tracker's reference view for the photometric term (shaders/reference_fill.comp, after
// ElasticFusion's): after the map's prediction is copied into DenseTracker::reference(l)
// (model_reference.hpp), it counts how much of the fused frame's view the prediction covers and fills the
// prediction's holes with the frame's own vertices and level-0 intensity, normals marked w = 0 so the ICP
// leaves them alone, so the next frame is aligned photometrically frame to frame where the map has no
// stable surfels yet. Recorded only into the sequence of frames that are fused: a lost frame's pose is a
// guess, and its measurements are not put where it might be.
//
// Lifecycle: construct (declares the counts buffer in the plan) → build(arena) → record() into a command
// sequence once → after each submission, coverage() reads what the prediction covered.

#include <cstdint>
#include <memory>
#include <vector>

#include "vifusion/core/image.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/preprocess/pixel_types.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/slam/dense_tracker.hpp"

namespace vifusion::slam {

/// Push constants of reference_fill.comp.
struct ReferenceFillParams {
  std::int32_t width = 0, height = 0;  ///< level size [px]
  std::uint32_t fill_intensity = 0;    ///< 1 at level 0
  std::uint32_t pass = 0;              ///< 0: count (level 0), 1: fill
};

/// One pyramid level: the frame's maps fill the reference view's (vertices, normals with w = 0; intensity at
/// level 0).
struct ReferenceFillLevel {
  PinholeCamera camera;
  preprocess::LevelBuffers current;
  preprocess::LevelBuffers reference;
};

/// What the prediction covered of the frame's view (level 0).
struct ReferenceCoverage {
  std::uint32_t valid_pixels = 0;    ///< pixels with a vertex in the frame
  std::uint32_t covered_pixels = 0;  ///< of those, the ones the prediction has a vertex at
  double share() const { return valid_pixels > 0 ? double(covered_pixels) / double(valid_pixels) : 0.0; }
};

class ReferenceFill {
 public:
  /// Declares the counts buffer.
  ReferenceFill(gpu::GpuContext& context, gpu::CapacityPlan& plan, std::vector<ReferenceFillLevel> levels);
  /// The tracker's preprocessed frame into its reference view, at every level.
  ReferenceFill(gpu::GpuContext& context, gpu::CapacityPlan& plan, const DenseTracker& tracker);
  ~ReferenceFill();

  /// Creates the kernel and one binding set per level.
  void build(const gpu::MemoryArena& arena);
  /// Records the count and the fill of every level; call after the prediction was copied into the
  /// reference view and before DenseTracker::recordReferenceIntensity, with a barrier before it (the
  /// caller's).
  void record(gpu::CommandRecorder& recorder) const;
  /// The last completed submission's counts.
  ReferenceCoverage coverage() const;

 private:
  gpu::GpuContext& context_;
  std::vector<ReferenceFillLevel> levels_;
  gpu::BufferId counts_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<gpu::ComputeKernel> kernel_;
  std::vector<gpu::BindingSet> sets_;
};

/// CPU reference of reference_fill.comp's pass 1 on one level (in place on the reference maps).
void referenceFillCpu(ImageView<const preprocess::VertexPixel> current_vertices,
                      ImageView<const preprocess::NormalPixel> current_normals,
                      ImageView<const float> current_intensity, ImageView<preprocess::VertexPixel> reference_vertices,
                      ImageView<preprocess::NormalPixel> reference_normals, ImageView<float> reference_intensity,
                      bool fill_intensity);
/// CPU reference of pass 0: the level-0 counts.
ReferenceCoverage referenceCoverageCpu(ImageView<const preprocess::VertexPixel> current_vertices,
                                       ImageView<const preprocess::VertexPixel> reference_vertices);

}  // namespace vifusion::slam
