#include "vifusion/map/surfel_deformation.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <string>
#include <vector>

#include "grid_stride.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/loop/node_binding.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::map {
namespace {

/// std430 mirror of map_deform.comp's DeformParams.
struct DeformParams {
  std::uint32_t node_count = 0;
  std::uint32_t candidates = 0;
  std::uint32_t first_moving_node = 0;
  std::uint32_t pad = 0;
};

std::string field(const char* name) { return std::string("surfel deformation option '") + name + "'"; }

}  // namespace

std::uint32_t DeformationNode::time() const { return std::bit_cast<std::uint32_t>(position_time.w()); }

DeformationNode deformationNode(const loop::DeformationGraph& graph, int node) {
  const std::span<const double> params = graph.parameters();
  const Eigen::Matrix3d A = loop::nodeAffine(params, node);
  const Eigen::Vector3d t = loop::nodeTranslation(params, node);
  const Eigen::Matrix3d A_inverse_transpose = A.inverse().transpose();
  DeformationNode out;
  out.position_time << graph.nodePositions()[static_cast<std::size_t>(node)].cast<float>(),
      std::bit_cast<float>(graph.nodeTimes()[static_cast<std::size_t>(node)]);
  for (int c = 0; c < 3; ++c) {
    out.columns[c] << A.col(c).cast<float>(), static_cast<float>(t[c]);
    out.inverse_transpose_columns[c] << A_inverse_transpose.col(c).cast<float>(), 0.0f;
  }
  return out;
}

void SurfelDeformationOptions::validate() const {
  if (max_nodes == 0) throw Error(field("max_nodes") + " must be ≥ 1");
  if (candidates == 0) throw Error(field("candidates") + " must be ≥ 1");
  if (workgroups == 0) throw Error(field("workgroups") + " must be ≥ 1");
  if (workgroup_size == 0 || workgroup_size > 1024) throw Error(field("workgroup_size") + " must be in 1..1024");
}

struct SurfelDeformation::Kernels {
  std::unique_ptr<gpu::ComputeKernel> deform;
  gpu::BindingSet sets[2];
  std::unique_ptr<gpu::CommandSequence> sequences[2];  ///< per surfel-array parity
  std::uint32_t groups = 0;
};

SurfelDeformation::SurfelDeformation(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                                     const SurfelDeformationOptions& options)
    : context_(context), map_(map), options_(options) {
  options_.validate();
  nodes_ = plan.addBuffer("map_deform.nodes", std::uint64_t{options_.max_nodes} * sizeof(DeformationNode),
                          gpu::MemoryUse::Upload);
  params_ = plan.addBuffer("map_deform.params", sizeof(DeformParams), gpu::MemoryUse::Upload);
}

SurfelDeformation::~SurfelDeformation() = default;

void SurfelDeformation::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  kernels_ = std::make_unique<Kernels>();
  Kernels& k = *kernels_;
  gpu::KernelSpec spec;
  spec.name = "map_deform";
  spec.spirv = shaders::map_deform;
  spec.storage_buffers = 4;
  spec.workgroup_size = {options_.workgroup_size, 1, 1};
  spec.max_binding_sets = 2;
  k.deform = gpu::ComputeKernel::create(context_, std::move(spec));
  k.groups = surfelWorkgroups(context_, options_.workgroups);
  const auto buffer = [&](gpu::BufferId id) { return &arena.buffer(id); };
  for (int parity = 0; parity < 2; ++parity) {
    k.sets[parity] =
        k.deform->bind({buffer(map_.state()), buffer(map_.surfels(parity)), buffer(nodes_), buffer(params_)});
    k.sequences[parity] = gpu::CommandSequence::create(context_, "map deform " + std::to_string(parity));
    k.sequences[parity]->record([&](gpu::CommandRecorder& recorder) {
      recorder.computeBarrier();  // after earlier submissions' map writes
      record(recorder, parity);
    });
  }
}

void SurfelDeformation::record(gpu::CommandRecorder& recorder, int parity) const {
  recorder.dispatch(*kernels_->deform, kernels_->sets[parity & 1], {kernels_->groups, 1, 1});
  recorder.computeBarrier();
}

void SurfelDeformation::setNodes(std::span<const DeformationNode> nodes, std::uint32_t first_moving_node) {
  if (nodes.empty() || nodes.size() > options_.max_nodes) {
    throw Error("surfel deformation: " + std::to_string(nodes.size()) + " nodes, must be 1.." +
                std::to_string(options_.max_nodes) + " (max_nodes)");
  }
  if (first_moving_node > nodes.size()) {
    throw Error("surfel deformation: first moving node " + std::to_string(first_moving_node) + " of " +
                std::to_string(nodes.size()) + " nodes");
  }
  std::memcpy(arena_->buffer(nodes_).mapped, nodes.data(), nodes.size_bytes());
  const DeformParams params{static_cast<std::uint32_t>(nodes.size()), options_.candidates, first_moving_node};
  std::memcpy(arena_->buffer(params_).mapped, &params, sizeof(params));
}

void SurfelDeformation::setNodes(const loop::DeformationGraph& graph) {
  const int count = graph.nodeCount();
  if (count <= 0 || static_cast<std::uint32_t>(count) > options_.max_nodes) {
    throw Error("surfel deformation: the graph has " + std::to_string(count) + " nodes, must be 1.." +
                std::to_string(options_.max_nodes) + " (max_nodes)");
  }
  const std::span<DeformationNode> out = arena_->buffer(nodes_).hostSpan<DeformationNode>();
  for (int i = 0; i < count; ++i) out[static_cast<std::size_t>(i)] = deformationNode(graph, i);
  const DeformParams params{static_cast<std::uint32_t>(count), options_.candidates,
                            static_cast<std::uint32_t>(graph.firstFreeNode())};
  std::memcpy(arena_->buffer(params_).mapped, &params, sizeof(params));
}

void SurfelDeformation::apply() {
  kernels_->sequences[map_.current()]->run();
  // Only the current array moved: its inactive prefix no longer matches the other array's.
  map_.visitWholeMapNextFrame(*arena_);
}

void deformSurfelsCpu(std::span<Surfel> surfels, std::span<const DeformationNode> nodes, std::uint32_t candidates,
                      std::uint32_t first_moving_node) {
  const auto count = static_cast<int>(std::min<std::size_t>(candidates, nodes.size()));
  std::vector<Eigen::Vector3f> positions(nodes.size());
  std::vector<std::uint32_t> times(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    positions[i] = nodes[i].position_time.head<3>();
    times[i] = nodes[i].time();
  }
  for (Surfel& surfel : surfels) {
    const Eigen::Vector3f p = surfel.position_confidence.head<3>();
    const Eigen::Vector3f n_W = surfel.normal_radius.head<3>();
    const auto time = static_cast<std::uint32_t>(surfel.colour_times.y());
    const int start = loop::candidateWindowStart(times, time, static_cast<int>(candidates));
    if (start + count <= static_cast<int>(first_moving_node)) continue;
    const loop::NodeBinding<float> binding =
        loop::bindToNodes<float>(p, time, positions, times, static_cast<int>(candidates));
    Eigen::Vector3f position = Eigen::Vector3f::Zero();
    Eigen::Vector3f normal = Eigen::Vector3f::Zero();
    for (int k = 0; k < loop::kBoundNodes; ++k) {
      const float w = binding.weight[static_cast<std::size_t>(k)];
      const DeformationNode& node = nodes[static_cast<std::size_t>(binding.node[static_cast<std::size_t>(k)])];
      Eigen::Matrix3f A, A_inverse_transpose;
      for (int c = 0; c < 3; ++c) {
        A.col(c) = node.columns[c].head<3>();
        A_inverse_transpose.col(c) = node.inverse_transpose_columns[c].head<3>();
      }
      const Eigen::Vector3f t(node.columns[0].w(), node.columns[1].w(), node.columns[2].w());
      const Eigen::Vector3f g = node.position_time.head<3>();
      position += w * (A * (p - g) + g + t);
      normal += w * (A_inverse_transpose * n_W);
    }
    const float length = normal.norm();
    surfel.position_confidence.head<3>() = position;
    surfel.normal_radius.head<3>() = length > 0.0f ? Eigen::Vector3f(normal / length) : n_W;
  }
}

}  // namespace vifusion::map
