#pragma once
// The small map the map-sampling and reactivation GPU tests share: a wall facing the camera at the origin of W,
// in blocks of every surfel state.

#include <cstdint>
#include <vector>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/map/surfel.hpp"

namespace vifusion::test {

/// 80 × 60 pinhole, f = 60 px: small enough for CPU references of whole images, large enough for a scene.
inline const PinholeCamera kBlockWallCamera = PinholeCamera::create(80, 60, 60, 60, 39.5, 29.5);
inline constexpr float kBlockWallDepth_m = 2.0f;
inline constexpr std::uint32_t kBlockWallFrame = 1000;       ///< the frame the map is predicted in
inline constexpr std::uint32_t kBlockWallInactiveAge = 300;  ///< > δ_t = 200 frames
inline constexpr float kBlockWallStableConfidence = 20.0f;   ///< ≥ the threshold of 10
inline constexpr float kBlockWallUnstableConfidence = 1.0f;

/// The wall at kBlockWallDepth_m, one surfel per pixel left of x = 60 (the rest of the image sees nothing), in
/// 8 × 8-pixel blocks that take turns being active and stable, active and unstable, inactive and stable, inactive
/// and unstable (at kBlockWallFrame). Creation frames follow the index.
inline std::vector<map::Surfel> blockWallSurfels() {
  const PinholeCamera& camera = kBlockWallCamera;
  std::vector<map::Surfel> surfels;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < 60; ++x) {
      const int kind = (x / 8 + y / 8) % 4;
      const float z = kBlockWallDepth_m;
      map::Surfel s;
      s.position_confidence << (static_cast<float>(x) - 39.5f) * z / 60.0f, (static_cast<float>(y) - 29.5f) * z / 60.0f,
          z, kind % 2 == 0 ? kBlockWallStableConfidence : kBlockWallUnstableConfidence;
      s.normal_radius << 0.0f, 0.0f, -1.0f, 1.5f * z / 60.0f;
      s.setPackedColour(static_cast<std::uint32_t>(x * 3 + y * 7) & 0xffffffu);
      s.colour_times.y() = static_cast<float>(surfels.size() / 64);
      s.colour_times.z() = static_cast<float>(kind < 2 ? kBlockWallFrame - 3 : kBlockWallFrame - kBlockWallInactiveAge);
      surfels.push_back(s);
    }
  }
  return surfels;
}

}  // namespace vifusion::test
