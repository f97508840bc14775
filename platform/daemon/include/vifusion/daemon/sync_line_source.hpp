#pragma once
// vifusiond's sync line (config sync.*, drivers/gpio_sync): the camera's strobe or an external trigger,
// its kernel-stamped edges read by the line's driver thread. Until the timestamp-sync tool consumes the
// edges, the main thread drains the ring and publishes their count and rate in rt/vifusion/status.

#include <memory>

#include "vifusion/config/daemon_config.hpp"
#include "vifusion/daemon/shared_state.hpp"
#include "vifusion/gpio_sync/sync_line.hpp"

namespace vifusion::daemon {

/// Requests the configured line and starts its thread.
/// @throws vifusion::Error naming the chip and line (no such chip, line out of range, line busy, a build
///         without libgpiod).
std::unique_ptr<gpio_sync::SyncLine> openSyncLine(const config::SyncConfig& config);

/// Drains the line's edge ring and copies its edge count and rate into `state` (main thread; no allocation).
void reportSyncLine(gpio_sync::SyncLine& line, SharedState& state);

}  // namespace vifusion::daemon
