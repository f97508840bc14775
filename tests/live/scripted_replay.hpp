#pragma once
// A recording replayed by the scripted ZR300 (scripted_camera.hpp): its frames and IMU turned into what the
// camera would deliver (colour through YUYV, IMU readings in whole counts, times on whole µs, a still IMU
// lead before the first sample for the clock mapping's warm-up), as a CameraScript, and the same data written
// as a dataset directory, so that a run on the camera can be compared with a run on files.

#include <cstddef>
#include <filesystem>

#include "scripted_camera.hpp"

namespace vifusion::live_test {

/// The recording's times start at 0; the camera's clock is an uptime, this much later.
inline constexpr std::int64_t kUptimeNs = 1'000'000'000'000;

struct Replay {
  CameraScript script;
  std::filesystem::path files;  ///< the dataset directory of what the camera delivers (with calibration.yaml)
  std::size_t frames = 0;
};

/// Reads the `dataset:` directory `recording` and writes the delivered data under `work`/delivered.
Replay prepareReplay(const std::filesystem::path& recording, const std::filesystem::path& work);

}  // namespace vifusion::live_test
