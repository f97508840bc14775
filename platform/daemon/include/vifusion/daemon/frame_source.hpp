#pragma once
// Opens vifusiond's source. Dataset specs go to datasets::openDataset; `sim:NAME` is generated
// once into <out>/sim_NAME by the `vifusion sim` program installed beside vifusiond (the simulator
// lives in the CLI), then replayed like any dataset directory; `zr300[:SERIAL]` opens the live camera
// (drivers/zr300 open_zr300.hpp) with the configured calibration.

#include <functional>
#include <memory>
#include <string>

#include "vifusion/config/daemon_config.hpp"
#include "vifusion/core/imu_feed.hpp"
#include "vifusion/daemon/shared_state.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/datasets/fault_injection.hpp"
#ifdef VIFUSION_WITH_ZR300
#include "vifusion/zr300/zr300_backend.hpp"
#endif

namespace vifusion::daemon {

/// The source and, for the live camera, what the service needs of it beyond DatasetReader. The functions
/// are set only for a live source; they are made at start and called without allocating.
struct OpenedSource {
  std::unique_ptr<datasets::DatasetReader> reader;
  ImuFeed* live_imu = nullptr;         ///< the live camera's IMU feed (null: recorded, or rgbd mode)
  std::function<void()> request_stop;  ///< ends the reader's wait for the next frame (shutdown)
  /// Copies the camera's state (present, clock offset and skew, IMU ring) into `state`; main thread.
  std::function<void(SharedState& state)> report;
  /// Why the camera is absent (for the log and systemd's STATUS=); allocates, so not per frame.
  std::function<std::string()> problem;
};

/// `inertial`: the mode needs the IMU (the live camera then streams its motion module). `faults`: config `inject`,
/// parsed by the caller (a typo there is a configuration error), applied to a recorded source.
/// Throws vifusion::Error saying what failed (generation, the dataset's own error, discovery's message).
OpenedSource openSource(const config::DaemonConfig& config, bool inertial, const datasets::FaultPlan& faults);
#ifdef VIFUSION_WITH_ZR300
/// The same with the live camera reached through `backend` (null: the real devices).
OpenedSource openSource(const config::DaemonConfig& config, bool inertial, const datasets::FaultPlan& faults,
                        std::unique_ptr<zr300::Zr300Backend> backend);
#endif

}  // namespace vifusion::daemon
