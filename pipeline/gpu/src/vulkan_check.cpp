#include "vifusion/gpu/vulkan_check.hpp"

namespace vifusion::gpu {

std::string vkResultName(VkResult result) {
  switch (result) {
#define VIFUSION_VK_CASE(code) \
  case code:                   \
    return #code;
    VIFUSION_VK_CASE(VK_SUCCESS)
    VIFUSION_VK_CASE(VK_NOT_READY)
    VIFUSION_VK_CASE(VK_TIMEOUT)
    VIFUSION_VK_CASE(VK_INCOMPLETE)
    VIFUSION_VK_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    VIFUSION_VK_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    VIFUSION_VK_CASE(VK_ERROR_INITIALIZATION_FAILED)
    VIFUSION_VK_CASE(VK_ERROR_DEVICE_LOST)
    VIFUSION_VK_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    VIFUSION_VK_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    VIFUSION_VK_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    VIFUSION_VK_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    VIFUSION_VK_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    VIFUSION_VK_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    VIFUSION_VK_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    VIFUSION_VK_CASE(VK_ERROR_FRAGMENTED_POOL)
    VIFUSION_VK_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    VIFUSION_VK_CASE(VK_ERROR_INVALID_SHADER_NV)
    VIFUSION_VK_CASE(VK_ERROR_UNKNOWN)
#undef VIFUSION_VK_CASE
    default:
      return "VkResult(" + std::to_string(static_cast<int>(result)) + ")";
  }
}

void checkVk(VkResult result, const std::string& what) {
  if (result != VK_SUCCESS) {
    throw Error(what + ": " + vkResultName(result));
  }
}

}  // namespace vifusion::gpu
