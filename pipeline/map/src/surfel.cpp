#include "vifusion/map/surfel.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::map {

std::uint32_t packRgb8(const Eigen::Vector3f& rgb) {
  const auto channel = [](float value) {
    return static_cast<std::uint32_t>(std::clamp(std::floor(value + 0.5f), 0.0f, 255.0f));
  };
  return channel(rgb.x()) | (channel(rgb.y()) << 8) | (channel(rgb.z()) << 16);
}

Eigen::Vector3f unpackRgb8(std::uint32_t packed) {
  return Eigen::Vector3f(static_cast<float>(packed & 0xffu), static_cast<float>((packed >> 8) & 0xffu),
                         static_cast<float>((packed >> 16) & 0xffu));
}

void MapOptions::validate() const {
  if (capacity == 0 || capacity > (1u << 26)) throw Error("map option 'capacity' must be in 1..67108864");
  if (!(confidence_threshold > 0.0f)) throw Error("map option 'confidence_threshold' must be > 0");
  if (time_window_frames == 0) throw Error("map option 'time_window_frames' must be ≥ 1");
  if (!(max_depth_m > 0.0f)) throw Error("map option 'max_depth_m' must be > 0");
}

}  // namespace vifusion::map
