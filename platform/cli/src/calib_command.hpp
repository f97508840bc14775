#pragma once
// `vifusion calib noise`: measures an RGB-D camera's depth and intensity noise (core/camera_noise_model.hpp)
// and the inverse-depth bias (the disparity offset of RigCalibration::inverse_depth_bias_per_m) from a dataset
// with ground-truth poses (calib/noise_estimator.hpp), prints them and the per-depth table as one JSON object,
// and optionally writes the dataset's calibration.yaml with the measured `depth_noise:`, `intensity_noise:` and
// `inverse_depth_bias_per_m` (its standard error in depth_noise: inverse_depth_bias_sigma_per_m).

#include <string>

namespace vifusion::cli {

struct CalibNoiseOptions {
  std::string source;  ///< dataset spec with ground truth (datasets/dataset_reader.hpp: dataset:, 7scenes:, tum:, …)
  /// Frames between the two frames of a pair, ≥ 1: far enough apart that the depth of a surface changes by
  /// more than the device's depth step (rounding then differs between them, as noise does), near enough to
  /// overlap. 10 frames is 0.33 s at 30 Hz.
  int frame_step = 10;
  int max_pairs = 60;  ///< pairs spread evenly over the sequence, ≥ 1
  /// f·b of the sensor's disparity d = f·b / z [px·m]; 0: the calibration's depth_noise value (an error if
  /// it has none). The simulated Kinect: 480 px × 0.075 m = 36; Kinect v1 (7-Scenes): 585 px × 0.075 m.
  double focal_baseline_px_m = 0.0;
  std::string out;  ///< calibration.yaml to write with the measured noise (optional)
};

/// Returns 0 once measured. @throws vifusion::Error for a source without ground truth, too few residuals, or
/// an unwritable output (exit 2).
int runCalibNoise(const CalibNoiseOptions& options);

}  // namespace vifusion::cli
