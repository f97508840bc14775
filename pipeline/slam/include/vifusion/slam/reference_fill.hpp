#pragma once
// Fill-in of the tracker's reference view for the photometric term (shaders/reference_fill.comp, after
// ElasticFusion's): after the map's prediction is copied into DenseTracker::reference(l)
// (model_reference.hpp), it counts how much of the fused frame's view the prediction covers and fills the
// prediction's holes with the frame's own vertices and level-0 intensity, so that the next frame can be
// aligned photometrically frame to frame where the map has no stable surfels yet. Filled pixels are marked:
// vertex w = 0 (the map's are 1), which the photometric term ignores unless told to use the fill
// (PhotometricParams::use_reference_fill), and normal w = 0, which the ICP always reads as "no model".
// Recorded only into the sequence of frames that are fused: a lost frame's pose is a guess, and its
// measurements are not put where it might be.
//
// The filled pixels are a measurement relative to the previous frame's pose, but the dense terms treat the
// reference as the map, fixed: they hold the pose to the previous estimate where the map would correct it.
// So the fill is used only where the map cannot carry the frame on its own: while the map's prediction covers
// less than ReferenceFillOptions::max_coverage of the view, and, above that, for a frame that failed against
// the map's pixels alone (a fast pan whose view the map's stable surfels have not caught up with), which is
// tracked again with the fill. Slam fills in rgbd mode only: in the inertial modes the previous state's information
// is already in the marginalisation prior, so the filled pixels would count it twice, and the IMU carries the
// pose through the holes instead (tracking_state.hpp).
//
// Lifecycle: construct (declares the counts buffer in the plan) → build(arena) → recordCoverage() and (where
// the mode fills) recordFill() into a command sequence once → after each submission, coverage() reads what
// the prediction covered.

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

/// Vertex w of a filled reference pixel (the map's predicted vertices carry 1).
inline constexpr float kFilledVertexW = 0.0f;

struct ReferenceFillOptions {
  /// The photometric term uses the fill from the start while the prediction covers less than this share of
  /// the frame's valid level-0 pixels: below one half the frame-to-frame pixels would be the majority anyway;
  /// above it the map's absolute constraint is what the frame rests on, relative pixels beside it only add
  /// the previous pose's error, and the fill is only the fallback of a frame the map fails on
  /// (tests/bench/README.md, "Reference fill-in"). In [0, 1]; 0: only as the fallback, 1: always.
  double max_coverage = 0.5;

  /// Throws vifusion::Error naming the field out of range.
  void validate() const;
};

/// Push constants of reference_fill.comp.
struct ReferenceFillParams {
  std::int32_t width = 0, height = 0;  ///< level size [px]
  std::uint32_t fill_intensity = 0;    ///< 1 at level 0
  std::uint32_t pass = 0;              ///< 0: count (level 0), 1: fill
};

/// One pyramid level: the frame's maps fill the reference view's (vertices and normals with w = 0; intensity
/// at level 0).
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
  /// Whether the next frame is tracked with the fill from the start: share() < max_coverage.
  bool fills(double max_coverage) const { return share() < max_coverage; }
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
  /// Records the coverage count (pass 0); call after the prediction was copied into the reference view,
  /// with a barrier before it (the caller's).
  void recordCoverage(gpu::CommandRecorder& recorder) const;
  /// Records the fill of every level (pass 1): after recordCoverage and a barrier, before
  /// DenseTracker::recordReferenceIntensity.
  void recordFill(gpu::CommandRecorder& recorder) const;
  /// The last completed submission's counts.
  ReferenceCoverage coverage() const;

 private:
  static constexpr std::uint32_t kCountPass = 0;
  static constexpr std::uint32_t kFillPass = 1;

  void dispatch(gpu::CommandRecorder& recorder, std::size_t level, std::uint32_t pass) const;

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
