#pragma once
// Deterministic contents for recording tests: a rig with a separate depth camera, frames whose every byte and
// every stamp is known, IMU samples, sync edges and clock mappings, and a temporary directory.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/recording/recording_file.hpp"

namespace vifusion::recording::test {

inline constexpr int kWidth = 32;
inline constexpr int kHeight = 24;
inline constexpr std::int64_t kStartNs = 5'000'000'000'000;  ///< an uptime of 5000 s
inline constexpr std::int64_t kFramePeriodNs = 33'333'333;
inline constexpr std::int64_t kImuPeriodNs = 5'000'000;

/// A removed-on-destruction directory under the system's temp dir.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

RigCalibration rigCalibration();
RecordingHeader recordingHeader();
/// Frame k: its images filled from k, its stamps (kernel, device event on both clocks, counter) from k.
RgbdFrame makeFrame(int k);
ImuSample makeImu(int k);
ClockRecord makeClock(int k);
/// True when every field and pixel of `a` equals `b`'s.
bool sameFrame(const RgbdFrame& a, const RgbdFrame& b);

}  // namespace vifusion::recording::test
