#pragma once
// A compute pipeline built once from embedded SPIR-V: its descriptor layout (storage buffers at
// bindings 0..n−1 of set 0), push-constant range, specialization constants and a descriptor pool
// sized for the binding sets it will ever get. Binding sets are written once at start-up.

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"

namespace vifusion::gpu {

struct SpecializationConstant {
  uint32_t id = 0;
  uint32_t value = 0;  ///< int, uint, bool (0/1) or float bits
};

struct KernelSpec {
  std::string name;                    ///< shader name, used in every error message
  std::span<const uint32_t> spirv;     ///< embedded SPIR-V words
  uint32_t storage_buffers = 0;        ///< bindings 0..storage_buffers−1 of set 0
  uint32_t push_constant_bytes = 0;    ///< 0: no push constants; ≤ device limit (128 B guaranteed)
  /// Workgroup size, passed as specialization constants 0, 1, 2 (local_size_{x,y,z}_id).
  std::array<uint32_t, 3> workgroup_size = {16, 16, 1};
  std::vector<SpecializationConstant> constants;  ///< further specialization constants (ids ≥ 3)
  uint32_t max_binding_sets = 1;       ///< how many times bind() will be called
};

/// Index of a descriptor set of one kernel.
struct BindingSet {
  uint32_t index = UINT32_MAX;
};

class ComputeKernel {
 public:
  /// Throws vifusion::Error naming the shader when its SPIR-V is malformed, a limit is exceeded
  /// (push constants, workgroup size) or the driver rejects the module or pipeline.
  static std::unique_ptr<ComputeKernel> create(const GpuContext& context, KernelSpec spec);
  ~ComputeKernel();
  ComputeKernel(const ComputeKernel&) = delete;
  ComputeKernel& operator=(const ComputeKernel&) = delete;

  /// Writes a descriptor set with `buffers` at bindings 0..n−1 (start-up only).
  BindingSet bind(std::span<const GpuBuffer* const> buffers);
  BindingSet bind(std::initializer_list<const GpuBuffer*> buffers) {
    return bind(std::span<const GpuBuffer* const>(buffers.begin(), buffers.size()));
  }

  /// Workgroups needed to cover an image of width × height with one invocation per pixel.
  std::array<uint32_t, 3> groupsFor(uint32_t width, uint32_t height) const;

  const KernelSpec& spec() const { return spec_; }
  const std::string& name() const { return spec_.name; }
  VkPipeline pipeline() const { return pipeline_; }
  VkPipelineLayout layout() const { return pipeline_layout_; }
  VkDescriptorSet descriptorSet(BindingSet set) const;

 private:
  ComputeKernel(VkDevice device, KernelSpec spec) : device_(device), spec_(std::move(spec)) {}

  VkDevice device_;
  KernelSpec spec_;
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  std::vector<VkDescriptorSet> sets_;
};

}  // namespace vifusion::gpu
