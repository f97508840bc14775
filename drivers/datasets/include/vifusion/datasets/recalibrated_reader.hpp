#pragma once
// A recording read with the rig's calibration in place of the one it carries (`vifusion run --calibration`):
// a calibration measured once on the rig — intrinsics, extrinsics, IMU noise, and the depth noise and
// inverse-depth bias `vifusion calib noise` writes — applies to every later recording of that rig, the way a
// real sensor is calibrated once and not per sequence. Frames, IMU and ground truth pass through unchanged,
// so the replacement must describe the same images: the same size and the same depth units.

#include <memory>
#include <string>

#include "vifusion/datasets/dataset_reader.hpp"

namespace vifusion::datasets {

/// `recording` with `calibration` (read from `calibration_name`, which errors and describe() name) in place of
/// its own.
/// @throws vifusion::Error naming `calibration_name` when its image size or depth_scale_m differs from the
/// recording's.
std::unique_ptr<DatasetReader> withCalibration(std::unique_ptr<DatasetReader> recording,
                                               const RigCalibration& calibration, const std::string& calibration_name);

/// The same with the calibration read from `calibration_yaml` (kalibr.hpp's calibration.yaml schema).
/// @throws vifusion::Error naming the file for a file it cannot read, or as above.
std::unique_ptr<DatasetReader> withCalibrationFile(std::unique_ptr<DatasetReader> recording,
                                                   const std::string& calibration_yaml);

}  // namespace vifusion::datasets
