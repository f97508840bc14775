#pragma once
// One RGB-D frame as the noise measurement sees it: inverse depth with the calibrated bias removed, and the
// grey level the tracker uses, both on the colour camera's pixel grid.

#include "vifusion/core/image.hpp"
#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/sensor_data.hpp"

namespace vifusion::calib {

/// Depths the measurement uses [m]: the sensor's working range, wider than tracking's so that the depth
/// dependence of the noise is seen from near to far.
struct DepthWindow {
  double min_depth_m = 0.3;  ///< > 0
  double max_depth_m = 8.0;  ///< > min_depth_m
};

struct FrameSignals {
  Image<float> inverse_depth_per_m;  ///< 1/z [1/m] after removing RigCalibration::inverse_depth_bias_per_m; 0 = none
  Image<float> grey;                 ///< Rec. 601 luma of R, G, B on the 0–255 scale (preprocessing's weights)

  /// Fills both images from `frame` (resizing only when the size changes). Throws vifusion::Error when the
  /// frame's depth is not in the colour camera's pixels (a rig with its own depth camera) or its depth and
  /// colour differ in size from calibration.camera.
  void assign(const RgbdFrame& frame, const RigCalibration& calibration, const DepthWindow& window);

 private:
  Image<float> depth_m_;  ///< scratch: metric depth from preprocessing's CPU reference
};

}  // namespace vifusion::calib
