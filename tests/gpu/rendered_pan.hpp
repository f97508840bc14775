#pragma once
// A slow pan through the synthetic living room, rendered noise-free at 160×120, for the GPU tests
// that run the whole RGB-D pipeline (test_slam_allocation.cpp, test_slam_map_full.cpp).

#include <vector>

#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"

namespace vifusion::test {

struct Pan {
  std::vector<RgbdFrame> frames;
  std::vector<SE3d> T_W_C;  ///< ground truth, living-room world
};

/// 40 frames along the pan (2 mm and 0.23° per frame); played forwards and backwards (panFrameIndex)
/// they make a continuous sequence that keeps tracking and fusing.
Pan renderPan(const PinholeCamera& camera);
/// The same pan with depth seen by a second camera `depth` beside the colour camera (its images the colour
/// camera's size): the frames carry what a ZR300 delivers before depth is registered to colour.
Pan renderPan(const PinholeCamera& camera, const DepthCameraCalibration& depth);

/// The pan's frame at step `step` of the back-and-forth sequence 0, 1, …, 39, 38, …, 1, 0, 1, …
std::size_t panFrameIndex(std::size_t step, std::size_t pan_frames);

/// 160×120, f = 120 px, depth in millimetres.
RigCalibration panCalibration();

}  // namespace vifusion::test
