#include "vifusion/gpio_sync/sync_line_options.hpp"

#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::gpio_sync {
namespace {

void require(bool ok, const char* field, const std::string& what) {
  if (!ok) throw Error(std::string("SyncLineOptions.") + field + " " + what);
}

}  // namespace

void SyncLineOptions::validate() const {
  require(!chip.empty(), "chip", "is empty: give a chip name such as \"gpiochip0\" or a path such as /dev/gpiochip0");
  require(chip.front() == '/' || chip.find('/') == std::string::npos, "chip",
          "\"" + chip + "\" is neither a name under /dev (no '/') nor an absolute path");
  require(line_offset >= 0 && line_offset <= kMaxLineOffset, "line_offset",
          "must be in [0, " + std::to_string(kMaxLineOffset) + "], got " + std::to_string(line_offset));
  require(edges == EdgeDetection::kRising || edges == EdgeDetection::kFalling || edges == EdgeDetection::kBoth, "edges",
          "must be rising, falling or both, got " + std::to_string(static_cast<int>(edges)));
  require(ring_capacity >= 1, "ring_capacity", "must be >= 1, got 0");
  require(wait_timeout_ms > 0 && wait_timeout_ms <= kMaxWaitTimeoutMs, "wait_timeout_ms",
          "must be in (0, " + std::to_string(kMaxWaitTimeoutMs) + "] ms, got " + std::to_string(wait_timeout_ms));
  require(rate_window_ns > 0 && rate_window_ns <= kMaxRateWindowNs, "rate_window_ns",
          "must be in (0, " + std::to_string(kMaxRateWindowNs) + "] ns, got " + std::to_string(rate_window_ns));
  require(rate_capacity >= 2 && rate_capacity <= kMaxRateCapacity, "rate_capacity",
          "must be in [2, " + std::to_string(kMaxRateCapacity) + "], got " + std::to_string(rate_capacity));
}

}  // namespace vifusion::gpio_sync
