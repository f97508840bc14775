#pragma once
// The surfel record of the map, identical in layout to shaders/include/map/surfel.glsl (48 bytes,
// three vec4), plus the map's parameters shared by the GPU kernels and their CPU references.

#include <Eigen/Core>
#include <cstdint>
#include <cstring>

namespace vifusion::map {

struct Surfel {
  Eigen::Vector4f position_confidence = Eigen::Vector4f::Zero();  ///< xyz in W [m], w confidence
  Eigen::Vector4f normal_radius = Eigen::Vector4f::Zero();        ///< xyz unit normal in W, w radius [m]
  Eigen::Vector4f colour_times = Eigen::Vector4f::Zero();         ///< x packed RGB8 bits, y created, z updated [frame]

  std::uint32_t packedColour() const {
    std::uint32_t bits;
    std::memcpy(&bits, &colour_times.x(), sizeof(bits));
    return bits;
  }
  void setPackedColour(std::uint32_t bits) { std::memcpy(&colour_times.x(), &bits, sizeof(bits)); }
};
static_assert(sizeof(Surfel) == 48, "must match the std430 layout of shaders/include/map/surfel.glsl");

/// RGB (0..255 each) packed as r | g << 8 | b << 16, rounding and clamping like packRgb8 in GLSL.
std::uint32_t packRgb8(const Eigen::Vector3f& rgb);
Eigen::Vector3f unpackRgb8(std::uint32_t packed);

/// The smallest maxStorageBufferRange a Vulkan device may report (the specification's required limit, 2^27
/// bytes): a storage buffer this large binds on every device.
inline constexpr std::uint64_t kGuaranteedStorageBufferBytes = std::uint64_t{1} << 27;

/// MapOptions::capacity's default: the largest surfel array every Vulkan device binds, 2 796 202 surfels. A
/// revisit at 640×480 needs the first pass's surfels kept until the loop closes, and a map-full eviction
/// (map_maintenance.hpp) takes the oldest of them first; a larger map than this is a device-specific choice.
inline constexpr std::uint32_t kDefaultMapCapacity = kGuaranteedStorageBufferBytes / sizeof(Surfel);

/// ElasticFusion's map parameters (algorithms.md §1.3), shared by every map kernel.
struct MapOptions {
  std::uint32_t capacity = kDefaultMapCapacity;  ///< surfels the map holds (fixed at start-up)
  float confidence_threshold = 10.0f;            ///< stable when confidence ≥ this
  std::uint32_t time_window_frames = 200;        ///< δ_t: active when updated within this many frames
  std::uint32_t unstable_max_age_frames = 20;    ///< unstable surfels not updated for longer are removed
  float max_depth_m = 4.0f;                      ///< depth beyond this is neither fused nor predicted

  /// Throws vifusion::Error naming the field that is out of range.
  void validate() const;
};

}  // namespace vifusion::map
