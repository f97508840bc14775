#pragma once
// Options for choosing and opening the Vulkan device. Every field has a default; the environment
// can override them so a deployed service or a CI job can pin a device without a rebuild.

#include <string>

namespace vifusion::gpu {

struct GpuOptions {
  /// Use the first device whose name contains this text (case-insensitive), e.g. "llvmpipe" for
  /// Mesa's CPU device lavapipe. Empty: discrete GPU first, then integrated, virtual, CPU.
  /// Environment: VIFUSION_GPU_DEVICE.
  std::string device;

  /// Load VK_LAYER_KHRONOS_validation (with synchronisation validation) and count its messages.
  /// Environment: VIFUSION_GPU_VALIDATION=1.
  bool validation = false;

  /// Behave as if the device lacked subgroup arithmetic, so the shared-memory fallback kernels run
  /// on devices that have it (tests, and SBC drivers with broken subgroup support).
  /// Environment: VIFUSION_GPU_NO_SUBGROUP_ARITHMETIC=1.
  bool disable_subgroup_arithmetic = false;

  /// Behave as if the device lacked 64-bit storage-buffer atomics, so the 32-bit two-pass kernels
  /// run where the single-pass 64-bit ones would (tests; Mali and V3D lack them anyway).
  /// Environment: VIFUSION_GPU_NO_INT64_ATOMICS=1.
  bool disable_int64_atomics = false;

  /// Returns these options with the environment variables above applied on top.
  GpuOptions withEnvironment() const;
};

}  // namespace vifusion::gpu
