#include "sync_line_spec.hpp"

#include <charconv>
#include <utility>

#include "vifusion/core/error.hpp"
#include "vifusion/gpio_sync/edge_detection.hpp"
#if VIFUSION_GPIO_SYNC_HAVE_LIBGPIOD
#include "vifusion/gpio_sync/libgpiod_line_io.hpp"
#endif

namespace vifusion::cli {

std::unique_ptr<gpio_sync::SyncLine> openSyncLineSpec(const std::string& spec, const std::string& edges,
                                                      std::unique_ptr<gpio_sync::GpioLineIo> io) {
  const std::size_t colon = spec.rfind(':');
  int line = -1;
  const char* first = spec.data() + (colon == std::string::npos ? spec.size() : colon + 1);
  const char* last = spec.data() + spec.size();
  const auto parsed = std::from_chars(first, last, line);
  if (colon == std::string::npos || colon == 0 || parsed.ec != std::errc() || parsed.ptr != last || line < 0) {
    throw Error("--gpio '" + spec + "': expected CHIP:LINE, e.g. gpiochip0:17");
  }
  gpio_sync::SyncLineOptions options;
  options.chip = spec.substr(0, colon);
  options.line_offset = line;
  const std::optional<gpio_sync::EdgeDetection> detection = gpio_sync::parseEdgeDetection(edges);
  if (!detection) throw Error("--edges '" + edges + "' is unknown: rising, falling or both");
  options.edges = *detection;
  options.validate();
#if VIFUSION_GPIO_SYNC_HAVE_LIBGPIOD
  if (!io) io = std::make_unique<gpio_sync::LibgpiodLineIo>();
#else
  if (!io) throw Error("--gpio '" + spec + "': this vifusion was built without libgpiod (libgpiod-dev < 2)");
#endif
  auto sync_line = std::make_unique<gpio_sync::SyncLine>(std::move(io), options);
  sync_line->start();
  return sync_line;
}

}  // namespace vifusion::cli
