#include "vifusion/gpu/gpu_context.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>

#include "vifusion/core/error.hpp"
#include "vifusion/gpu/vulkan_check.hpp"

namespace vifusion::gpu {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT types,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  const bool is_problem =
      (severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)) !=
      0;
  // Loader chatter arrives as GENERAL messages; only the validation layer's findings count.
  const bool from_validation =
      (types & (VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT)) != 0;
  if (is_problem && from_validation) {
    auto* counter = static_cast<ValidationCounter*>(user);
    std::lock_guard lock(counter->mutex);
    if (counter->messages.fetch_add(1) == 0) counter->first_message = data->pMessage;
    std::fprintf(stderr, "[vulkan validation] %s\n", data->pMessage);
  }
  return VK_FALSE;
}

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string versionString(uint32_t version) {
  return std::to_string(VK_API_VERSION_MAJOR(version)) + "." + std::to_string(VK_API_VERSION_MINOR(version)) + "." +
         std::to_string(VK_API_VERSION_PATCH(version));
}

int typeRank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 3;
    default:
      return 4;
  }
}

std::string icdHint() {
  const char* icd = std::getenv("VK_ICD_FILENAMES");
  std::string hint = "install a Vulkan driver (Debian: mesa-vulkan-drivers provides the CPU device lavapipe)";
  if (icd != nullptr) hint += "; VK_ICD_FILENAMES is set to '" + std::string(icd) + "'";
  return hint;
}

bool hasLayer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  return std::any_of(layers.begin(), layers.end(),
                     [&](const VkLayerProperties& layer) { return std::strcmp(layer.layerName, name) == 0; });
}

bool hasDeviceExtension(VkPhysicalDevice device, const char* name) {
  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data());
  return std::any_of(extensions.begin(), extensions.end(), [&](const VkExtensionProperties& extension) {
    return std::strcmp(extension.extensionName, name) == 0;
  });
}

/// A queue family with compute, preferring a compute-only one (async compute on real GPUs).
std::optional<uint32_t> findComputeQueueFamily(VkPhysicalDevice device) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  std::optional<uint32_t> any_compute;
  for (uint32_t i = 0; i < count; ++i) {
    if ((families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) == 0) continue;
    if ((families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) == 0) return i;
    if (!any_compute) any_compute = i;
  }
  return any_compute;
}

uint32_t queueFamilyTimestampBits(VkPhysicalDevice device, uint32_t family) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  return family < count ? families[family].timestampValidBits : 0;
}

struct Candidate {
  VkPhysicalDevice device = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties{};
  uint32_t queue_family = 0;
};

/// Why a device cannot run vifusion, or empty when it can.
std::string unsuitableReason(VkPhysicalDevice device, const VkPhysicalDeviceProperties& properties) {
  if (properties.apiVersion < VK_API_VERSION_1_2) {
    return "Vulkan " + versionString(properties.apiVersion) + " < 1.2";
  }
  if (!findComputeQueueFamily(device)) return "no compute queue";
  VkPhysicalDeviceVulkan12Features features12{};
  features12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
  VkPhysicalDeviceFeatures2 features{};
  features.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
  features.pNext = &features12;
  vkGetPhysicalDeviceFeatures2(device, &features);
  if (!features12.timelineSemaphore) return "no timeline semaphores";
  return {};
}

Candidate chooseDevice(VkInstance instance, const GpuOptions& options) {
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance, &count, nullptr);
  if (count == 0) throw Error("no Vulkan device found: " + icdHint());
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance, &count, devices.data());

  std::vector<Candidate> usable;
  std::string seen;
  for (VkPhysicalDevice device : devices) {
    Candidate candidate{device, {}, 0};
    vkGetPhysicalDeviceProperties(device, &candidate.properties);
    const std::string name = candidate.properties.deviceName;
    const std::string reason = unsuitableReason(device, candidate.properties);
    seen += "\n  '" + name + "' (" + deviceTypeName(candidate.properties.deviceType) + ")" +
            (reason.empty() ? "" : ": unusable, " + reason);
    if (!reason.empty()) continue;
    if (!options.device.empty() && lowercase(name).find(lowercase(options.device)) == std::string::npos) continue;
    candidate.queue_family = *findComputeQueueFamily(device);
    usable.push_back(candidate);
  }
  if (usable.empty()) {
    const std::string wanted = options.device.empty() ? std::string("a usable Vulkan 1.2 device")
                                                      : "a device named like '" + options.device + "'";
    throw Error("no " + wanted + " among the devices found:" + seen);
  }
  std::stable_sort(usable.begin(), usable.end(), [](const Candidate& a, const Candidate& b) {
    return typeRank(a.properties.deviceType) < typeRank(b.properties.deviceType);
  });
  return usable.front();
}

}  // namespace

const char* deviceTypeName(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "CPU";
    default:
      return "other";
  }
}

std::unique_ptr<GpuContext> GpuContext::create(const GpuOptions& options) {
  std::unique_ptr<GpuContext> context(new GpuContext());
  GpuContext& ctx = *context;

  uint32_t loader_version = 0;
  if (vkEnumerateInstanceVersion(&loader_version) != VK_SUCCESS || loader_version < VK_API_VERSION_1_2) {
    throw Error("the Vulkan loader supports only " + versionString(loader_version) + "; vifusion needs 1.2");
  }

  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "vifusion";
  app.pEngineName = "vifusion";
  app.apiVersion = VK_API_VERSION_1_2;

  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  VkDebugUtilsMessengerCreateInfoEXT messenger_info{};
  VkValidationFeaturesEXT validation_features{};
  const VkValidationFeatureEnableEXT enabled_checks[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  if (options.validation) {
    if (!hasLayer(kValidationLayer)) {
      throw Error(std::string("GPU validation was requested but ") + kValidationLayer +
                  " is not installed (Debian package vulkan-validationlayers)");
    }
    ctx.validation_ = std::make_unique<ValidationCounter>();
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
    messenger_info.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
    messenger_info.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                 VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                 VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messenger_info.pfnUserCallback = onValidationMessage;
    messenger_info.pUserData = ctx.validation_.get();
    validation_features.sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT;
    validation_features.enabledValidationFeatureCount = 1;
    validation_features.pEnabledValidationFeatures = enabled_checks;
    validation_features.pNext = &messenger_info;  // also catches messages from instance creation
  }

  VkInstanceCreateInfo instance_info{};
  instance_info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  instance_info.pNext = options.validation ? &validation_features : nullptr;
  instance_info.pApplicationInfo = &app;
  instance_info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  instance_info.ppEnabledLayerNames = layers.data();
  instance_info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  instance_info.ppEnabledExtensionNames = extensions.data();
  const VkResult instance_result = vkCreateInstance(&instance_info, nullptr, &ctx.instance_);
  if (instance_result == VK_ERROR_INCOMPATIBLE_DRIVER) throw Error("no Vulkan driver found: " + icdHint());
  checkVk(instance_result, "vkCreateInstance");

  if (options.validation) {
    auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(ctx.instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (create_messenger == nullptr) throw Error("validation layer loaded but VK_EXT_debug_utils is missing");
    checkVk(create_messenger(ctx.instance_, &messenger_info, nullptr, &ctx.messenger_),
            "vkCreateDebugUtilsMessengerEXT");
  }

  const Candidate chosen = chooseDevice(ctx.instance_, options);
  ctx.physical_device_ = chosen.device;
  ctx.queue_family_ = chosen.queue_family;

  // Query what the device offers; optional features only select kernel variants.
  VkPhysicalDeviceSubgroupProperties subgroup{};
  subgroup.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES;
  VkPhysicalDeviceDriverProperties driver{};
  driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
  driver.pNext = &subgroup;
  VkPhysicalDeviceProperties2 properties{};
  properties.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  properties.pNext = &driver;
  vkGetPhysicalDeviceProperties2(ctx.physical_device_, &properties);

  const bool has_atomic_float = hasDeviceExtension(ctx.physical_device_, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomic_float{};
  atomic_float.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT;
  VkPhysicalDeviceVulkan12Features features12{};
  features12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
  features12.pNext = has_atomic_float ? &atomic_float : nullptr;
  VkPhysicalDeviceFeatures2 features{};
  features.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
  features.pNext = &features12;
  vkGetPhysicalDeviceFeatures2(ctx.physical_device_, &features);
  vkGetPhysicalDeviceMemoryProperties(ctx.physical_device_, &ctx.memory_properties_);

  GpuFeatures& f = ctx.features_;
  const VkPhysicalDeviceLimits& limits = properties.properties.limits;
  f.device_name = properties.properties.deviceName;
  f.device_type = properties.properties.deviceType;
  f.api_version = properties.properties.apiVersion;
  f.driver_info = std::string(driver.driverName) + " " + driver.driverInfo;
  f.subgroup_size = subgroup.subgroupSize;
  f.subgroup_arithmetic = !options.disable_subgroup_arithmetic &&
                          (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) != 0 &&
                          (subgroup.supportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT) != 0;
  f.float32_atomic_add = has_atomic_float && atomic_float.shaderBufferFloat32AtomicAdd;
  f.float64 = features.features.shaderFloat64 == VK_TRUE;
  f.int64_atomics = !options.disable_int64_atomics && features.features.shaderInt64 == VK_TRUE &&
                    features12.shaderBufferInt64Atomics == VK_TRUE;
  f.max_push_constants_bytes = limits.maxPushConstantsSize;
  f.max_storage_buffer_range_bytes = limits.maxStorageBufferRange;
  f.max_workgroup_invocations = limits.maxComputeWorkGroupInvocations;
  f.max_shared_memory_bytes = limits.maxComputeSharedMemorySize;
  f.max_memory_allocations = limits.maxMemoryAllocationCount;
  f.timestamp_valid_bits = queueFamilyTimestampBits(ctx.physical_device_, ctx.queue_family_);
  f.timestamp_period_ns = limits.timestampPeriod;
  for (uint32_t i = 0; i < ctx.memory_properties_.memoryTypeCount; ++i) {
    const VkMemoryPropertyFlags flags = ctx.memory_properties_.memoryTypes[i].propertyFlags;
    const VkMemoryPropertyFlags uma = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
    if ((flags & uma) == uma) f.unified_memory = true;
  }

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{};
  queue_info.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  queue_info.queueFamilyIndex = ctx.queue_family_;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;

  VkPhysicalDeviceVulkan12Features enable12{};
  enable12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
  enable12.timelineSemaphore = VK_TRUE;
  enable12.shaderBufferInt64Atomics = f.int64_atomics ? VK_TRUE : VK_FALSE;
  VkPhysicalDeviceFeatures2 enable{};
  enable.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
  enable.pNext = &enable12;
  enable.features.shaderInt64 = f.int64_atomics ? VK_TRUE : VK_FALSE;
  VkDeviceCreateInfo device_info{};
  device_info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  device_info.pNext = &enable;
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
  checkVk(vkCreateDevice(ctx.physical_device_, &device_info, nullptr, &ctx.device_),
          "vkCreateDevice on '" + f.device_name + "'");
  vkGetDeviceQueue(ctx.device_, ctx.queue_family_, 0, &ctx.queue_);
  return context;
}

GpuContext::~GpuContext() {
  if (device_ != VK_NULL_HANDLE) {
    vkDeviceWaitIdle(device_);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_ != VK_NULL_HANDLE) {
    auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy_messenger != nullptr) destroy_messenger(instance_, messenger_, nullptr);
  }
  if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
}

VkResult GpuContext::submit(const VkSubmitInfo& info) {
  std::lock_guard lock(queue_mutex_);
  if (device_lost_) return VK_ERROR_DEVICE_LOST;
  const VkResult result = vkQueueSubmit(queue_, 1, &info, VK_NULL_HANDLE);
  if (result == VK_ERROR_DEVICE_LOST) device_lost_ = true;
  return result;
}

uint32_t GpuContext::validationMessageCount() const { return validation_ ? validation_->messages.load() : 0; }

std::string GpuContext::firstValidationMessage() const {
  if (!validation_) return {};
  std::lock_guard lock(validation_->mutex);
  return validation_->first_message;
}

}  // namespace vifusion::gpu
