#include "vifusion/zr300/open_zr300.hpp"

#include "vifusion/core/error.hpp"
#include "vifusion/datasets/kalibr.hpp"
#include "vifusion/zr300/system_backend.hpp"

namespace vifusion::zr300 {

std::optional<StreamPreset> presetForSize(int width_px, int height_px) {
  for (const StreamPreset& preset : kPresets) {
    if (preset.width_px == width_px && preset.height_px == height_px) return preset;
  }
  return std::nullopt;
}

std::unique_ptr<Zr300Source> openZr300(const discovery::Zr300SourceSpec& spec,
                                       const std::filesystem::path& calibration_yaml, Zr300Options options,
                                       std::unique_ptr<Zr300Backend> backend) {
  if (!backend) backend = makeSystemBackend();
  discovery::CameraCheckOptions check;
  check.require_adapter = options.imu;
  backend->findCamera(spec, check);  // the camera's absence is the first thing to report
  if (calibration_yaml.empty()) {
    throw Error(
        "the zr300 source needs the rig calibration: --calibration FILE (calibration.yaml with Kalibr's cam0 "
        "(colour), cam1 (depth) and imu0 keys); reading the factory calibration from the adapter EEPROM is not "
        "implemented");
  }
  const RigCalibration calibration = datasets::readCalibrationYaml(calibration_yaml);
  const std::optional<StreamPreset> preset = presetForSize(calibration.camera.width, calibration.camera.height);
  if (!preset) {
    throw Error(calibration_yaml.string() + ": cam0 resolution " + std::to_string(calibration.camera.width) + "x" +
                std::to_string(calibration.camera.height) +
                " is not a ZR300 stream size (640x480 or 320x240 at 30 Hz, 480x360 at 60 Hz)");
  }
  options.preset = *preset;
  return std::make_unique<Zr300Source>(std::move(backend), spec, calibration, options);
}

}  // namespace vifusion::zr300
