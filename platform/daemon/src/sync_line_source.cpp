#include "vifusion/daemon/sync_line_source.hpp"

#include "vifusion/core/error.hpp"
#include "vifusion/gpio_sync/edge_detection.hpp"
#if VIFUSION_GPIO_SYNC_HAVE_LIBGPIOD
#include "vifusion/gpio_sync/libgpiod_line_io.hpp"
#endif

namespace vifusion::daemon {

std::unique_ptr<gpio_sync::SyncLine> openSyncLine(const config::SyncConfig& config) {
#if VIFUSION_GPIO_SYNC_HAVE_LIBGPIOD
  gpio_sync::SyncLineOptions options;
  options.chip = config.chip;
  options.line_offset = static_cast<int>(config.line);  // validate() bounded it
  const std::optional<gpio_sync::EdgeDetection> edges = gpio_sync::parseEdgeDetection(config.edges);
  if (!edges) throw Error("key 'sync.edges' = '" + config.edges + "' is unknown: rising, falling or both");
  options.edges = *edges;
  auto line = std::make_unique<gpio_sync::SyncLine>(std::make_unique<gpio_sync::LibgpiodLineIo>(), options);
  line->start();
  return line;
#else
  throw Error("sync.chip = '" + config.chip + "': this vifusiond was built without libgpiod (libgpiod-dev < 2)");
#endif
}

void reportSyncLine(gpio_sync::SyncLine& line, SharedState& state, recording::Recorder* recorder) {
  gpio_sync::SyncEdge edge;
  while (line.edgeRing().tryPop(edge)) {
    if (recorder != nullptr) recorder->pushSyncEdge(edge.t_ns, edge.rising, edge.sequence);
  }
  const gpio_sync::SyncLineStats stats = line.stats();
  state.sync_edge_rate_hz = stats.edge_rate_hz;
  state.sync_edges = stats.edges_read;
}

}  // namespace vifusion::daemon
