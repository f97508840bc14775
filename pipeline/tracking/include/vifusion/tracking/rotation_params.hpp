#pragma once
// Parameters of the rotation-only pre-alignment (shaders/rotation_reduce.comp), shared verbatim by the
// shader (a storage buffer with the layout of shaders/include/tracking/rotation_params.glsl) and the CPU
// reference. Its noise model is the photometric term's (PhotometricOptions), so nothing is set twice.

#include <cstddef>
#include <cstdint>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/tracking/photometric_params.hpp"

namespace vifusion::tracking {

/// std430 mirror of RotationParams in the shader (24 four-byte words).
struct RotationParams {
  float R_prev_cur_rows[3][4] = {};  ///< rows of the rotation current → previous camera (w = 0)
  float fx = 0, fy = 0, cx = 0, cy = 0;
  std::int32_t width = 0, height = 0;
  float sigma_intensity = 0;
  float huber_k = 0;
  float min_gradient = 0;
  /// Current pixels this close to the border are not used: their neighbours in the Sobel gradient and
  /// the pyramid's Gaussian are clamped copies of the border [px].
  std::int32_t border_px = 0;
  std::int32_t pad[2] = {};

  static RotationParams make(const Eigen::Quaterniond& q_prev_cur, const PinholeCamera& camera,
                             const PhotometricOptions& options);
};
static_assert(sizeof(RotationParams) == 24 * 4);
static_assert(offsetof(RotationParams, fx) == 48);
static_assert(offsetof(RotationParams, width) == 64);
static_assert(offsetof(RotationParams, border_px) == 84);

}  // namespace vifusion::tracking
