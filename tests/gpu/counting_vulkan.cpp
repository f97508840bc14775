#include "counting_vulkan.hpp"

#include <dlfcn.h>
#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace vifusion::test {
namespace {

std::atomic<uint64_t> g_allocate_memory{0};
std::atomic<uint64_t> g_create_or_update{0};

template <typename Fn>
Fn realFunction(const char* name) {
  void* symbol = dlsym(RTLD_NEXT, name);
  if (symbol == nullptr) {
    std::fprintf(stderr, "counting_vulkan: %s not found in libvulkan\n", name);
    std::abort();
  }
  return reinterpret_cast<Fn>(symbol);
}

}  // namespace

VulkanCallCounts vulkanCallCounts() { return {g_allocate_memory.load(), g_create_or_update.load()}; }

}  // namespace vifusion::test

using vifusion::test::g_allocate_memory;
using vifusion::test::g_create_or_update;
using vifusion::test::realFunction;

// Each wrapper counts, then forwards to the loader's implementation.
#define VIFUSION_COUNTED(counter, name, params, args)                      \
  extern "C" VKAPI_ATTR VkResult VKAPI_CALL name params {                  \
    static const auto real = realFunction<PFN_##name>(#name);              \
    ++counter;                                                             \
    return real args;                                                      \
  }

VIFUSION_COUNTED(g_allocate_memory, vkAllocateMemory,
                 (VkDevice d, const VkMemoryAllocateInfo* i, const VkAllocationCallbacks* a, VkDeviceMemory* m),
                 (d, i, a, m))
VIFUSION_COUNTED(g_create_or_update, vkCreateBuffer,
                 (VkDevice d, const VkBufferCreateInfo* i, const VkAllocationCallbacks* a, VkBuffer* b), (d, i, a, b))
VIFUSION_COUNTED(g_create_or_update, vkCreateShaderModule,
                 (VkDevice d, const VkShaderModuleCreateInfo* i, const VkAllocationCallbacks* a, VkShaderModule* m),
                 (d, i, a, m))
VIFUSION_COUNTED(g_create_or_update, vkCreateComputePipelines,
                 (VkDevice d, VkPipelineCache c, uint32_t n, const VkComputePipelineCreateInfo* i,
                  const VkAllocationCallbacks* a, VkPipeline* p),
                 (d, c, n, i, a, p))
VIFUSION_COUNTED(g_create_or_update, vkCreateDescriptorPool,
                 (VkDevice d, const VkDescriptorPoolCreateInfo* i, const VkAllocationCallbacks* a, VkDescriptorPool* p),
                 (d, i, a, p))
VIFUSION_COUNTED(g_create_or_update, vkAllocateDescriptorSets,
                 (VkDevice d, const VkDescriptorSetAllocateInfo* i, VkDescriptorSet* s), (d, i, s))
VIFUSION_COUNTED(g_create_or_update, vkCreateCommandPool,
                 (VkDevice d, const VkCommandPoolCreateInfo* i, const VkAllocationCallbacks* a, VkCommandPool* p),
                 (d, i, a, p))
VIFUSION_COUNTED(g_create_or_update, vkAllocateCommandBuffers,
                 (VkDevice d, const VkCommandBufferAllocateInfo* i, VkCommandBuffer* b), (d, i, b))
VIFUSION_COUNTED(g_create_or_update, vkCreateSemaphore,
                 (VkDevice d, const VkSemaphoreCreateInfo* i, const VkAllocationCallbacks* a, VkSemaphore* s),
                 (d, i, a, s))

extern "C" VKAPI_ATTR void VKAPI_CALL vkUpdateDescriptorSets(VkDevice d, uint32_t n, const VkWriteDescriptorSet* w,
                                                             uint32_t m, const VkCopyDescriptorSet* c) {
  static const auto real = realFunction<PFN_vkUpdateDescriptorSets>("vkUpdateDescriptorSets");
  ++g_create_or_update;
  real(d, n, w, m, c);
}
