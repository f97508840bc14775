#pragma once
// `zr300` / `zr300:SERIAL` as a source spec in `vifusion run` and vifusiond (DESIGN.md §5).
//
// The camera is looked for first, so that on a machine without it both programs fail at once with the
// discovery message ("no ZR300 found: no USB device 8086:0acb …", exit code 3) whatever else is missing;
// then the rig calibration is read (our calibration.yaml, whose cam0/imu0 keys are Kalibr's: see
// datasets/kalibr.hpp) and the stream preset follows from its image size (640×480 and 320×240 stream at
// 30 Hz, 480×360 at 60 Hz). Reading the factory calibration from the adapter EEPROM is not implemented, so
// the calibration file is required.

#include <filesystem>
#include <memory>
#include <optional>

#include "vifusion/discovery/source_spec.hpp"
#include "vifusion/zr300/zr300_backend.hpp"
#include "vifusion/zr300/zr300_options.hpp"
#include "vifusion/zr300/zr300_source.hpp"

namespace vifusion::zr300 {

/// Opens the live source. `backend` null: the system backend. `options.preset` is replaced by the preset
/// that matches the calibration's image size.
/// @throws discovery::DiscoveryError when the camera cannot be found or used (exit code 3);
///         vifusion::Error for a missing or invalid calibration (naming the file) or a device that refuses.
std::unique_ptr<Zr300Source> openZr300(const discovery::Zr300SourceSpec& spec,
                                       const std::filesystem::path& calibration_yaml, Zr300Options options,
                                       std::unique_ptr<Zr300Backend> backend = nullptr);

/// The preset streaming `width`×`height`, or nullopt when there is none.
std::optional<StreamPreset> presetForSize(int width_px, int height_px);

}  // namespace vifusion::zr300
