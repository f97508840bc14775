#include "vifusion/gpu/compute_kernel.hpp"

#include "vifusion/core/error.hpp"
#include "vifusion/gpu/vulkan_check.hpp"

namespace vifusion::gpu {
namespace {

constexpr uint32_t kSpirvMagic = 0x07230203;
constexpr uint32_t kSpirvMaxVersionForVulkan12 = 0x00010500;  // SPIR-V 1.5

/// Catches corrupt or truncated SPIR-V before a driver sees it (some crash instead of failing).
void checkSpirvHeader(const KernelSpec& spec) {
  const std::string where = "shader '" + spec.name + "': ";
  if (spec.spirv.size() < 5) throw Error(where + "SPIR-V is empty or truncated (" + std::to_string(spec.spirv.size()) + " words)");
  if (spec.spirv[0] != kSpirvMagic) throw Error(where + "not SPIR-V (bad magic number)");
  if (spec.spirv[1] > kSpirvMaxVersionForVulkan12) {
    throw Error(where + "SPIR-V version " + std::to_string(spec.spirv[1] >> 16) + "." +
                std::to_string((spec.spirv[1] >> 8) & 0xff) + " is newer than Vulkan 1.2 accepts");
  }
}

}  // namespace

std::unique_ptr<ComputeKernel> ComputeKernel::create(const GpuContext& context, KernelSpec spec) {
  checkSpirvHeader(spec);
  const GpuFeatures& features = context.features();
  const std::string where = "shader '" + spec.name + "'";
  if (spec.push_constant_bytes > features.max_push_constants_bytes || spec.push_constant_bytes % 4 != 0) {
    throw Error(where + ": " + std::to_string(spec.push_constant_bytes) +
                " bytes of push constants (must be a multiple of 4 and at most " +
                std::to_string(features.max_push_constants_bytes) + ")");
  }
  const uint64_t invocations = uint64_t{spec.workgroup_size[0]} * spec.workgroup_size[1] * spec.workgroup_size[2];
  if (invocations == 0 || invocations > features.max_workgroup_invocations) {
    throw Error(where + ": workgroup of " + std::to_string(invocations) + " invocations (device allows 1.." +
                std::to_string(features.max_workgroup_invocations) + ")");
  }
  if (spec.max_binding_sets == 0) throw Error(where + ": max_binding_sets must be at least 1");

  std::unique_ptr<ComputeKernel> kernel(new ComputeKernel(context.device(), std::move(spec)));
  ComputeKernel& k = *kernel;
  const VkDevice device = context.device();

  VkShaderModuleCreateInfo module_info{};
  module_info.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
  module_info.codeSize = k.spec_.spirv.size() * sizeof(uint32_t);
  module_info.pCode = k.spec_.spirv.data();
  checkVk(vkCreateShaderModule(device, &module_info, nullptr, &k.module_), "creating the module of " + where);

  std::vector<VkDescriptorSetLayoutBinding> bindings(k.spec_.storage_buffers);
  for (uint32_t i = 0; i < k.spec_.storage_buffers; ++i) {
    bindings[i].binding = i;
    bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[i].descriptorCount = 1;
    bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo set_layout_info{};
  set_layout_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  set_layout_info.bindingCount = static_cast<uint32_t>(bindings.size());
  set_layout_info.pBindings = bindings.data();
  checkVk(vkCreateDescriptorSetLayout(device, &set_layout_info, nullptr, &k.set_layout_),
          "creating the descriptor layout of " + where);

  VkPushConstantRange push_range{VK_SHADER_STAGE_COMPUTE_BIT, 0, k.spec_.push_constant_bytes};
  VkPipelineLayoutCreateInfo layout_info{};
  layout_info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &k.set_layout_;
  layout_info.pushConstantRangeCount = k.spec_.push_constant_bytes > 0 ? 1 : 0;
  layout_info.pPushConstantRanges = &push_range;
  checkVk(vkCreatePipelineLayout(device, &layout_info, nullptr, &k.pipeline_layout_),
          "creating the pipeline layout of " + where);

  std::vector<SpecializationConstant> constants = {
      {0, k.spec_.workgroup_size[0]}, {1, k.spec_.workgroup_size[1]}, {2, k.spec_.workgroup_size[2]}};
  constants.insert(constants.end(), k.spec_.constants.begin(), k.spec_.constants.end());
  std::vector<VkSpecializationMapEntry> entries(constants.size());
  for (std::size_t i = 0; i < constants.size(); ++i) {
    entries[i] = {constants[i].id, static_cast<uint32_t>(i * sizeof(SpecializationConstant) + sizeof(uint32_t)),
                  sizeof(uint32_t)};
  }
  VkSpecializationInfo specialization{};
  specialization.mapEntryCount = static_cast<uint32_t>(entries.size());
  specialization.pMapEntries = entries.data();
  specialization.dataSize = constants.size() * sizeof(SpecializationConstant);
  specialization.pData = constants.data();

  VkComputePipelineCreateInfo pipeline_info{};
  pipeline_info.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
  pipeline_info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  pipeline_info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  pipeline_info.stage.module = k.module_;
  pipeline_info.stage.pName = "main";
  pipeline_info.stage.pSpecializationInfo = &specialization;
  pipeline_info.layout = k.pipeline_layout_;
  checkVk(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipeline_info, nullptr, &k.pipeline_),
          "creating the compute pipeline of " + where);

  if (k.spec_.storage_buffers > 0) {
    VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, k.spec_.storage_buffers * k.spec_.max_binding_sets};
    VkDescriptorPoolCreateInfo pool_info{};
    pool_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    pool_info.maxSets = k.spec_.max_binding_sets;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &pool_size;
    checkVk(vkCreateDescriptorPool(device, &pool_info, nullptr, &k.pool_), "creating the descriptor pool of " + where);
  }
  return kernel;
}

ComputeKernel::~ComputeKernel() {
  if (pool_ != VK_NULL_HANDLE) vkDestroyDescriptorPool(device_, pool_, nullptr);
  if (pipeline_ != VK_NULL_HANDLE) vkDestroyPipeline(device_, pipeline_, nullptr);
  if (pipeline_layout_ != VK_NULL_HANDLE) vkDestroyPipelineLayout(device_, pipeline_layout_, nullptr);
  if (set_layout_ != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
  if (module_ != VK_NULL_HANDLE) vkDestroyShaderModule(device_, module_, nullptr);
}

BindingSet ComputeKernel::bind(std::span<const GpuBuffer* const> buffers) {
  const std::string where = "shader '" + spec_.name + "'";
  if (buffers.size() != spec_.storage_buffers) {
    throw Error(where + " takes " + std::to_string(spec_.storage_buffers) + " buffers, got " +
                std::to_string(buffers.size()));
  }
  if (spec_.storage_buffers == 0) throw Error(where + " takes no buffers, so it needs no binding set");
  if (sets_.size() >= spec_.max_binding_sets) {
    throw Error(where + ": more binding sets than planned (" + std::to_string(spec_.max_binding_sets) + ")");
  }
  VkDescriptorSetAllocateInfo allocate_info{};
  allocate_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  allocate_info.descriptorPool = pool_;
  allocate_info.descriptorSetCount = 1;
  allocate_info.pSetLayouts = &set_layout_;
  VkDescriptorSet set = VK_NULL_HANDLE;
  checkVk(vkAllocateDescriptorSets(device_, &allocate_info, &set), "allocating a descriptor set of " + where);

  std::vector<VkDescriptorBufferInfo> infos(buffers.size());
  std::vector<VkWriteDescriptorSet> writes(buffers.size());
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    if (buffers[i] == nullptr || buffers[i]->handle == VK_NULL_HANDLE) {
      throw Error(where + ": binding " + std::to_string(i) + " has no buffer");
    }
    infos[i] = {buffers[i]->handle, 0, VK_WHOLE_SIZE};
    writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[i].dstSet = set;
    writes[i].dstBinding = static_cast<uint32_t>(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(device_, static_cast<uint32_t>(writes.size()), writes.data(), 0, nullptr);
  sets_.push_back(set);
  return BindingSet{static_cast<uint32_t>(sets_.size() - 1)};
}

std::array<uint32_t, 3> ComputeKernel::groupsFor(uint32_t width, uint32_t height) const {
  return {(width + spec_.workgroup_size[0] - 1) / spec_.workgroup_size[0],
          (height + spec_.workgroup_size[1] - 1) / spec_.workgroup_size[1], 1};
}

VkDescriptorSet ComputeKernel::descriptorSet(BindingSet set) const {
  if (set.index >= sets_.size()) throw Error("shader '" + spec_.name + "': unknown binding set");
  return sets_[set.index];
}

}  // namespace vifusion::gpu
