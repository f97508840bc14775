#pragma once
// Rig calibration from Kalibr YAML, and our own calibration.yaml in the same schema.
//
// EXTRINSIC DIRECTION: Kalibr's `T_cam_imu` maps IMU points into the camera, p_C = T_cam_imu · p_S,
// i.e. it is T_C_S. RigCalibration stores T_S_C (camera → IMU), so every reader here sets
// T_S_C = T_cam_imu⁻¹ and the writer writes T_cam_imu = T_S_C⁻¹. (The opposite reading is the most
// common calibration bug in peer projects: okvis#38, open_vins#540.)
//
// camchain-imucam.yaml (Kalibr output), one camera:
//   cam0:
//     T_cam_imu: [[r r r t], [r r r t], [r r r t], [0 0 0 1]]   # T_C_S
//     camera_model: pinhole
//     intrinsics: [fu, fv, pu, pv]          # fx, fy, cx, cy [px]
//     resolution: [width, height]           # [px]
//     distortion_model: radtan / none       # coefficients must be zero: images are rectified
//     distortion_coeffs: [0, 0, 0, 0]
//     timeshift_cam_imu: 0.0                # [s], t_imu = t_cam + shift
//   cam1:                                   # optional: the depth camera, when depth is not in cam0's pixels
//     T_cn_cnm1: [[...]]                    # T_D_C, p_D = T_cn_cnm1 · p_C (Kalibr's chain: cam0 → cam1)
//     T_cam_imu: [[...]]                    # optional, T_D_S; must agree with cam0's and T_cn_cnm1
//     camera_model, intrinsics, resolution, distortion_*: as cam0 (the depth stream is rectified)
// imu.yaml (Kalibr input format, or its output nested under `imu0:`):
//   accelerometer_noise_density [m/s²/√Hz], accelerometer_random_walk [m/s³/√Hz],
//   gyroscope_noise_density [rad/s/√Hz], gyroscope_random_walk [rad/s²/√Hz], update_rate [Hz]
//
// calibration.yaml (our dataset directories) = `cam0:` (and `cam1:`) as above + `imu0:` with the imu.yaml keys and
// our optional gyroscope_saturation [rad/s], accelerometer_saturation [m/s²], gyroscope_bias_prior
// [rad/s], accelerometer_bias_prior [m/s²], + top-level depth_scale_m [m per depth unit],
// inverse_depth_bias_per_m [1/m] (RigCalibration: the sensor's 1/z reads this much too high),
// gravity_world: [x, y, z] [m/s², dataset world W], static_accel_bias: [x, y, z] [m/s²], and, once measured by
// `vifusion calib noise`, the camera's noise (core/camera_noise_model.hpp), both mappings together:
//   depth_noise:      disparity_sigma_px [px], focal_baseline_px_m [px·m], quantisation_m [m] (optional, 0),
//                     lateral_sigma_px [px] (optional, 0), correlation_px [px] (optional, 0),
//                     pixels_per_sample (optional, 1)
//   intensity_noise:  sigma [grey level, 0–255], lateral_sigma_px, correlation_px, pixels_per_sample (optional
//                     as above)
//
// Every mapping's keys are checked: an unknown or misspelt key is an error naming it and its line,
// because a typo in an optional key (say `timeshift_cam_imu`) would otherwise pass silently.

#include <filesystem>
#include <string>

#include "vifusion/core/rig_calibration.hpp"

namespace vifusion::datasets {

/// Reads a Kalibr camchain-imucam.yaml and imu.yaml. Values Kalibr does not know keep RigCalibration's
/// defaults: depth_scale_m (1/5000), g_W (y-up world), the IMU saturations and bias priors.
/// @throws vifusion::Error naming file, line and key for a syntax error, unknown key, missing or
/// malformed value, non-pinhole model, non-zero distortion, non-rigid T_cam_imu or invalid IMU noise.
RigCalibration readKalibr(const std::filesystem::path& camchain_imucam_yaml, const std::filesystem::path& imu_yaml);

/// Reads our calibration.yaml (schema above); missing optional keys keep RigCalibration's defaults.
/// @throws vifusion::Error as readKalibr.
RigCalibration readCalibrationYaml(const std::filesystem::path& path);

/// Reads calibration.yaml's schema from `text` (a recording's copy); `name` stands for the file in errors.
/// @throws vifusion::Error as readKalibr.
RigCalibration readCalibrationYamlText(const std::string& text, const std::string& name);

/// The calibration.yaml text of `calibration` (what writeCalibrationYaml writes).
std::string calibrationYamlText(const RigCalibration& calibration);

/// Writes `calibration` as calibration.yaml with 17 significant digits, so readCalibrationYaml gives it
/// back (T_S_C to rounding of one inversion; imu.gravity_mps2 comes back as |g_W|).
/// @throws vifusion::Error if the file cannot be written.
void writeCalibrationYaml(const std::filesystem::path& path, const RigCalibration& calibration);

}  // namespace vifusion::datasets
