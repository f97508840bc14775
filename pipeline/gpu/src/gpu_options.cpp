#include "vifusion/gpu/gpu_options.hpp"

#include <cstdlib>
#include <string_view>

#include "vifusion/core/error.hpp"

namespace vifusion::gpu {
namespace {

/// Reads a 0/1 switch; anything else is a configuration error that names the variable.
bool envFlag(const char* name, bool fallback) {
  const char* value = std::getenv(name);
  if (value == nullptr || value[0] == '\0') return fallback;
  const std::string_view text(value);
  if (text == "1" || text == "true" || text == "on") return true;
  if (text == "0" || text == "false" || text == "off") return false;
  throw Error(std::string("environment variable ") + name + "='" + value + "': expected 0 or 1");
}

}  // namespace

GpuOptions GpuOptions::withEnvironment() const {
  GpuOptions options = *this;
  if (const char* device_name = std::getenv("VIFUSION_GPU_DEVICE"); device_name != nullptr) {
    options.device = device_name;
  }
  options.validation = envFlag("VIFUSION_GPU_VALIDATION", options.validation);
  options.disable_subgroup_arithmetic =
      envFlag("VIFUSION_GPU_NO_SUBGROUP_ARITHMETIC", options.disable_subgroup_arithmetic);
  options.disable_int64_atomics = envFlag("VIFUSION_GPU_NO_INT64_ATOMICS", options.disable_int64_atomics);
  return options;
}

}  // namespace vifusion::gpu
