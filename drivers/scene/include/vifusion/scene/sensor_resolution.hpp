#pragma once
// Smaller images from the simulated depth sensor, as a real one gives them: subsampled from its native
// 640×480 disparity image, not measured by a coarser sensor.
//
// The noise model (sensor_noise.hpp) is a 640×480 Kinect-like sensor's: its lateral jitter (0.5 px), dot
// pattern (one dot per 3×3 px) and hole filling (r² ≤ 9 px²) are in that sensor's pixels. Applied to a
// 160×120 render they act on pixels 4× larger, and depth noise at 3 m grew from 26 mm (640×480) to 41 mm
// (320×240) and 84 mm (160×120): low-resolution datasets were a different, far worse sensor, and tracking
// at 160×120 failed on them. So depth for a W×H camera that divides 640×480 by an integer s is rendered
// and made noisy at s·W × s·H with the camera scaled by s (fx, fy, cx, cy all ×s, so native pixel (s·x,
// s·y) sees exactly the ray of pixel (x, y)), then subsampled at those pixels: the same metric noise as at
// 640×480, on fewer pixels. Colour is rendered at W×H directly (its anti-aliasing is per output pixel).

#include <cstdint>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"

namespace vifusion::scene {

/// The depth sensor's native image size [px].
inline constexpr int kSensorWidth = 640;
inline constexpr int kSensorHeight = 480;

/// s such that camera is the sensor's image subsampled by s (s·W = 640 and s·H = 480); 1 when the
/// camera is not an integer subsampling of it (the noise is then applied at the camera's own pixels).
int sensorSubsampling(const PinholeCamera& camera);

/// The native camera whose pixel (s·x, s·y) has the same ray as camera's pixel (x, y).
PinholeCamera sensorCamera(const PinholeCamera& camera, int subsampling);

/// out(x, y) = native(s·x, s·y). Throws std::invalid_argument unless native is s·out's size.
void subsampleDepth(ImageView<const std::uint16_t> native, int subsampling, ImageView<std::uint16_t> out);

}  // namespace vifusion::scene
