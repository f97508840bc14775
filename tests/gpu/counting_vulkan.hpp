#pragma once
// Counts the Vulkan calls that allocate memory or create objects, by interposing them in this
// test executable (the definitions below win over libvulkan's; the real ones are found with
// dlsym(RTLD_NEXT)). Used to prove the per-frame path allocates nothing.

#include <cstdint>

namespace vifusion::test {

struct VulkanCallCounts {
  uint64_t allocate_memory = 0;   ///< vkAllocateMemory
  uint64_t create_or_update = 0;  ///< every other vkCreate*/vkAllocate*/vkUpdateDescriptorSets
};

VulkanCallCounts vulkanCallCounts();

}  // namespace vifusion::test
