#pragma once
// Turns a failed Vulkan call into a vifusion::Error that names the call and the result code.

#include <vulkan/vulkan.h>

#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::gpu {

/// "VK_ERROR_OUT_OF_DEVICE_MEMORY" etc.; the numeric value for codes this header does not know.
std::string vkResultName(VkResult result);

/// Throws vifusion::Error("<what>: <result name>") unless result is VK_SUCCESS.
void checkVk(VkResult result, const std::string& what);

/// Per-frame variant: the message "<action> '<subject>': <result name>" is only built on failure,
/// so a successful call allocates nothing.
inline void checkVk(VkResult result, const char* action, const std::string& subject) {
  if (result != VK_SUCCESS) checkVk(result, std::string(action) + " '" + subject + "'");
}

}  // namespace vifusion::gpu
