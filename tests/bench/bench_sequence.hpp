#pragma once
// The benchmark's sequence: the first --frames frames of sim:living_room_0 at one size, generated
// once by `vifusion sim` into --data_dir and decoded into memory once per size.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bench_options.hpp"
#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/eval/trajectory_io.hpp"

namespace vifusion::bench {

/// One size of the living-room sequence in memory, with the ground truth at every frame.
struct Sequence {
  RigCalibration calibration;
  std::vector<RgbdFrame> frames;
  std::vector<eval::StampedPose> ground_truth;  ///< T_world_camera at each frame's stamp, in frame order
  /// The reader's whole IMU stream (DatasetReader::imu(), on the IMU clock), for --mode=rgbdi: handed to
  /// Slam::process with every frame, as `vifusion run`'s RecordedImuFeed does.
  std::vector<ImuSample> imu;
  std::string describe;
};

/// The sequence of `size` (generated if missing or short; cached for the process's lifetime).
const Sequence& sequenceFor(const Size& size);

/// The frame of a sequence of `n` ≥ 2 frames played as 0, 1, …, n−1, n−2, …, 1, 0, 1, … that comes j-th: a
/// continuous camera path of any length.
inline std::size_t pingPongFrame(std::size_t n, std::int64_t j) {
  const auto period = static_cast<std::int64_t>(2 * n - 2);
  const std::int64_t phase = j % period;
  return static_cast<std::size_t>(phase < static_cast<std::int64_t>(n) ? phase : period - phase);
}

/// With --trajectory_dir, writes `trajectory` as <dir>/<name>.txt (TUM) for `vifusion eval --plots`.
void writeTrajectory(const std::string& name, const std::vector<eval::StampedPose>& trajectory);

}  // namespace vifusion::bench
