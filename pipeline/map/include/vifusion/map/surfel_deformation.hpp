#pragma once
// A loop closure's deformation applied to the surfel map on the GPU (shaders/map_deform.comp): every live
// surfel of the current array is bound to its deformation-graph nodes by creation frame and position and
// moved by φ (vifusion/loop/deformation_function.hpp), its normal by the nodes' A⁻ᵀ, in place. Confidence,
// radius, colour and times are kept. Surfels bound only to nodes a closure held (older than the previous
// accepted closure: the identity) are skipped, so a later closure costs what it moves, not the map's size.
//
// The nodes travel in a host-visible buffer sized once for `max_nodes` (the graph's capacity, from the
// capacity plan): setNodes() writes them, apply() runs the sequence recorded once per surfel-array parity.
// Not per frame: once per accepted closure, from the thread that owns the GPU, with no submission in flight
// that writes the map.
//
// CPU reference: deformSurfelsCpu, which binds with vifusion::loop::bindToNodes<float> (the shader mirrors it
// step by step) and applies the same float records.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <span>

#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/loop/deformation_graph.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/surfel.hpp"

namespace vifusion::map {

/// std430 mirror of DeformationNode in map_deform.comp (7 vec4, 112 bytes): one graph node with its committed
/// parameters, in float.
struct DeformationNode {
  Eigen::Vector4f position_time = Eigen::Vector4f::Zero();  ///< xyz g [m] in W; w the creation frame's uint bits
  Eigen::Vector4f columns[3];                               ///< A's columns; w of column c holds t[c] [m]
  Eigen::Vector4f inverse_transpose_columns[3];             ///< A⁻ᵀ's columns (w 0): normals transform with it

  std::uint32_t time() const;
};
static_assert(sizeof(DeformationNode) == 112, "must match the std430 layout in shaders/map_deform.comp");

/// Node `node` of `graph` with its committed parameters (A must be invertible: E_rot keeps it near a rotation).
DeformationNode deformationNode(const loop::DeformationGraph& graph, int node);

struct SurfelDeformationOptions {
  /// Nodes the buffer holds: the deformation graph's capacity (loop::DeformationGraphOptions::max_nodes). ≥ 1.
  std::uint32_t max_nodes = 1024;
  /// The binding window (loop::DeformationGraphOptions::candidates), ≥ 1.
  std::uint32_t candidates = 20;
  std::uint32_t workgroups = 256;      ///< workgroups of the grid-stride pass
  std::uint32_t workgroup_size = 128;  ///< invocations per workgroup

  /// Throws vifusion::Error naming the field that is out of range.
  void validate() const;
};

class SurfelDeformation {
 public:
  /// Declares the node and parameter buffers (Upload). `map` must outlive this object.
  SurfelDeformation(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                    const SurfelDeformationOptions& options = {});
  ~SurfelDeformation();
  SurfelDeformation(const SurfelDeformation&) = delete;
  SurfelDeformation& operator=(const SurfelDeformation&) = delete;

  /// Creates the kernel, one binding set and one recorded sequence per surfel-array parity.
  void build(const gpu::MemoryArena& arena);

  /// Writes the nodes (sorted by creation frame, 1 ≤ count ≤ max_nodes) for the next apply(). Nodes
  /// [0, first_moving_node) must be the identity: surfels bound to them alone are skipped, not rewritten.
  /// No allocation. Throws vifusion::Error when there are none, more than max_nodes, or first_moving_node > count.
  void setNodes(std::span<const DeformationNode> nodes, std::uint32_t first_moving_node = 0);
  /// Writes node i of `graph` for i < graph.nodeCount() (committed parameters), as setNodes, with the graph's
  /// held nodes (firstFreeNode()) as the identity ones. No allocation.
  void setNodes(const loop::DeformationGraph& graph);
  /// Deforms the current surfel array in place and waits for it; the next frame visits the whole map
  /// (MapBuffers::visitWholeMapNextFrame), so the other array's inactive prefix is rewritten too.
  void apply();

  /// Records the deformation of array `parity` (for callers that put it into their own sequence), ending with
  /// a compute barrier.
  void record(gpu::CommandRecorder& recorder, int parity) const;

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  const MapBuffers& map_;
  SurfelDeformationOptions options_;
  gpu::BufferId nodes_;
  gpu::BufferId params_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
};

/// CPU reference of map_deform.comp: deforms `surfels` in place by `nodes` (sorted by creation frame, ≥ 1),
/// binding each within a window of `candidates` nodes; a surfel whose window lies in [0, first_moving_node) is
/// left as it is.
void deformSurfelsCpu(std::span<Surfel> surfels, std::span<const DeformationNode> nodes, std::uint32_t candidates,
                      std::uint32_t first_moving_node = 0);

}  // namespace vifusion::map
