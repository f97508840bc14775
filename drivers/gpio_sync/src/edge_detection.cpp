#include "vifusion/gpio_sync/edge_detection.hpp"

#include <array>

namespace vifusion::gpio_sync {
namespace {

constexpr std::array kAllEdgeDetections = {EdgeDetection::kRising, EdgeDetection::kFalling, EdgeDetection::kBoth};

}  // namespace

std::string_view edgeDetectionName(EdgeDetection edges) {
  switch (edges) {
    case EdgeDetection::kRising:
      return "rising";
    case EdgeDetection::kFalling:
      return "falling";
    case EdgeDetection::kBoth:
      return "both";
  }
  return "invalid";
}

std::optional<EdgeDetection> parseEdgeDetection(std::string_view text) {
  for (const EdgeDetection edges : kAllEdgeDetections) {
    if (edgeDetectionName(edges) == text) return edges;
  }
  return std::nullopt;
}

}  // namespace vifusion::gpio_sync
