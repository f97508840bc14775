#include "vifusion/slam/reference_fill.hpp"

#include <cstring>
#include <utility>

#include "vifusion/core/error.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::slam {
namespace {

std::vector<ReferenceFillLevel> trackerLevels(const DenseTracker& tracker) {
  std::vector<ReferenceFillLevel> levels;
  for (int l = 0; l < tracker.options().levels; ++l) {
    levels.push_back({tracker.camera(l), tracker.preprocessing().level(l), tracker.reference(l)});
  }
  return levels;
}

}  // namespace

void ReferenceFillOptions::validate() const {
  if (!(max_coverage >= 0.0 && max_coverage <= 1.0))
    throw Error("reference fill option 'max_coverage' must be in [0, 1]");
}

ReferenceFill::ReferenceFill(gpu::GpuContext& context, gpu::CapacityPlan& plan, std::vector<ReferenceFillLevel> levels)
    : context_(context), levels_(std::move(levels)) {
  counts_ = plan.addBuffer("slam.reference_fill.counts", 2 * sizeof(std::uint32_t), gpu::MemoryUse::Readback);
}

ReferenceFill::ReferenceFill(gpu::GpuContext& context, gpu::CapacityPlan& plan, const DenseTracker& tracker)
    : ReferenceFill(context, plan, trackerLevels(tracker)) {}

ReferenceFill::~ReferenceFill() = default;

void ReferenceFill::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  gpu::KernelSpec spec;
  spec.name = "reference_fill";
  spec.spirv = shaders::reference_fill;
  spec.storage_buffers = 7;
  spec.push_constant_bytes = sizeof(ReferenceFillParams);
  spec.max_binding_sets = static_cast<std::uint32_t>(levels_.size());
  kernel_ = gpu::ComputeKernel::create(context_, std::move(spec));
  for (const ReferenceFillLevel& level : levels_) {
    const preprocess::LevelBuffers& current = level.current;
    const preprocess::LevelBuffers& reference = level.reference;
    sets_.push_back(
        kernel_->bind({&arena.buffer(current.vertices), &arena.buffer(current.normals),
                       &arena.buffer(current.intensity), &arena.buffer(reference.vertices),
                       &arena.buffer(reference.normals), &arena.buffer(reference.intensity), &arena.buffer(counts_)}));
  }
}

void ReferenceFill::dispatch(gpu::CommandRecorder& recorder, std::size_t level, std::uint32_t pass) const {
  const PinholeCamera& camera = levels_[level].camera;
  const ReferenceFillParams params{camera.width, camera.height, level == 0 ? 1u : 0u, pass};
  recorder.dispatch(
      *kernel_, sets_[level],
      kernel_->groupsFor(static_cast<std::uint32_t>(camera.width), static_cast<std::uint32_t>(camera.height)), params);
}

void ReferenceFill::recordCoverage(gpu::CommandRecorder& recorder) const {
  recorder.fillBuffer(arena_->buffer(counts_), 0u);
  recorder.computeBarrier();
  dispatch(recorder, 0, kCountPass);
}

void ReferenceFill::recordFill(gpu::CommandRecorder& recorder) const {
  for (std::size_t l = 0; l < levels_.size(); ++l) dispatch(recorder, l, kFillPass);
}

ReferenceCoverage ReferenceFill::coverage() const {
  std::uint32_t counts[2];
  std::memcpy(counts, arena_->buffer(counts_).mapped, sizeof(counts));
  return {counts[0], counts[1]};
}

ReferenceCoverage referenceCoverageCpu(ImageView<const preprocess::VertexPixel> current_vertices,
                                       ImageView<const preprocess::VertexPixel> reference_vertices) {
  ReferenceCoverage coverage;
  for (int v = 0; v < current_vertices.height; ++v) {
    for (int u = 0; u < current_vertices.width; ++u) {
      if (!(current_vertices(u, v).z() > 0.0f)) continue;
      ++coverage.valid_pixels;
      if (reference_vertices(u, v).z() > 0.0f) ++coverage.covered_pixels;
    }
  }
  return coverage;
}

void referenceFillCpu(ImageView<const preprocess::VertexPixel> current_vertices,
                      ImageView<const preprocess::NormalPixel> current_normals,
                      ImageView<const float> current_intensity, ImageView<preprocess::VertexPixel> reference_vertices,
                      ImageView<preprocess::NormalPixel> reference_normals, ImageView<float> reference_intensity,
                      bool fill_intensity) {
  for (int v = 0; v < reference_vertices.height; ++v) {
    for (int u = 0; u < reference_vertices.width; ++u) {
      if (reference_vertices(u, v).z() > 0.0f) continue;
      const preprocess::VertexPixel& p = current_vertices(u, v);
      if (!(p.z() > 0.0f)) continue;
      reference_vertices(u, v) << p.head<3>(), kFilledVertexW;
      reference_normals(u, v) << current_normals(u, v).head<3>(), 0.0f;
      if (fill_intensity) reference_intensity(u, v) = current_intensity(u, v);
    }
  }
}

}  // namespace vifusion::slam
