#include "vifusion/discovery/discovery_error.hpp"

namespace vifusion::discovery {

std::string_view problemName(DiscoveryProblem problem) {
  switch (problem) {
    case DiscoveryProblem::kBadSpec:
      return "bad source spec";
    case DiscoveryProblem::kUdevUnavailable:
      return "udev unavailable";
    case DiscoveryProblem::kNoCamera:
      return "no camera";
    case DiscoveryProblem::kSerialNotFound:
      return "serial not found";
    case DiscoveryProblem::kAmbiguous:
      return "several cameras";
    case DiscoveryProblem::kUvcNotBound:
      return "uvcvideo not bound";
    case DiscoveryProblem::kMissingStreams:
      return "capture nodes missing";
    case DiscoveryProblem::kNoAdapter:
      return "adapter board missing";
    case DiscoveryProblem::kNodeMissing:
      return "device node missing";
    case DiscoveryProblem::kPermissionDenied:
      return "permission denied";
    case DiscoveryProblem::kNodeInaccessible:
      return "device node inaccessible";
  }
  return "unknown problem";
}

}  // namespace vifusion::discovery
