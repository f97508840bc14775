#pragma once
// vifusiond's sync line (config sync.*, drivers/gpio_sync): the camera's strobe or an external trigger,
// its kernel-stamped edges read by the line's driver thread. The main thread drains the ring into the
// recording (when vifusiond records) and publishes the edges' count and rate in rt/vifusion/status; the
// timestamp-sync check (`vifusion synccheck`) reads them from a recording or live.

#include <memory>

#include "vifusion/config/daemon_config.hpp"
#include "vifusion/daemon/shared_state.hpp"
#include "vifusion/gpio_sync/sync_line.hpp"
#include "vifusion/recording/recorder.hpp"

namespace vifusion::daemon {

/// Requests the configured line and starts its thread.
/// @throws vifusion::Error naming the chip and line (no such chip, line out of range, line busy, a build
///         without libgpiod).
std::unique_ptr<gpio_sync::SyncLine> openSyncLine(const config::SyncConfig& config);

/// Drains the line's edge ring (into `recorder` when given) and copies its edge count and rate into `state`
/// (main thread; no allocation).
void reportSyncLine(gpio_sync::SyncLine& line, SharedState& state, recording::Recorder* recorder = nullptr);

}  // namespace vifusion::daemon
