#pragma once
// Which edges of the sync line the kernel reports (the request made on the line).

#include <cstdint>
#include <optional>
#include <string_view>

namespace vifusion::gpio_sync {

enum class EdgeDetection : std::uint8_t {
  kRising,   ///< low → high only: a strobe's start of exposure, or a trigger pulse's leading edge
  kFalling,  ///< high → low only
  kBoth,     ///< both: pulse widths (exposure lengths) can be measured from consecutive edges
};

/// "rising", "falling" or "both".
std::string_view edgeDetectionName(EdgeDetection edges);
/// The inverse of edgeDetectionName(); nullopt for anything else (the caller names the config key).
std::optional<EdgeDetection> parseEdgeDetection(std::string_view text);

}  // namespace vifusion::gpio_sync
