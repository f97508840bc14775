#pragma once
// A real Kinect frame from ../shared/data/7scenes-50 (640×480, depth in millimetres, 0 = invalid).
// Colour and depth are not registered in 7-Scenes; the kernels do not care.

#include <cstdint>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/preprocess/pixel_types.hpp"

namespace vifusion::test {

struct SevenScenesFrame {
  Image<std::uint16_t> depth_mm;
  Image<preprocess::Rgb8> rgb;
  PinholeCamera camera;  ///< 585, 585, 320, 240 (camera-intrinsics.txt)
  SE3d T_W_C;            ///< camera-to-world pose from KinectFusion (frame-XXXXXX.pose.txt)
};

/// Loads frame-000<index>.{depth,color}.png and .pose.txt (index 150..199); throws vifusion::Error if missing.
SevenScenesFrame loadSevenScenesFrame(int index);

}  // namespace vifusion::test
