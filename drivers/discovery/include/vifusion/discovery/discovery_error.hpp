#pragma once
// Why a ZR300 could not be found or used. The message says what is missing and what to do about it; the
// problem code lets the live source decide (exit at start, or wait for hotplug while running).

#include <cstdint>
#include <string>
#include <string_view>

#include "vifusion/core/error.hpp"

namespace vifusion::discovery {

enum class DiscoveryProblem : std::uint8_t {
  kBadSpec,           ///< the source spec is not "zr300" or "zr300:SERIAL"
  kUdevUnavailable,   ///< libudev could not be used at all
  kNoCamera,          ///< no 8086:0acb on any USB bus
  kSerialNotFound,    ///< cameras present, none with the requested serial
  kAmbiguous,         ///< "zr300" without a serial, but several cameras present
  kUvcNotBound,       ///< the 8086:0acb has no video nodes: uvcvideo is not bound to it
  kMissingStreams,    ///< video nodes present, but not the three capture nodes IR, depth, colour
  kNoAdapter,         ///< no adapter board 8086:0ad0 on the camera's hub: no IMU, no fisheye
  kNodeMissing,       ///< sysfs lists a node that /dev lacks (udev did not create it)
  kPermissionDenied,  ///< this process may not open a node (udev rules, groups)
  kNodeInaccessible,  ///< a node cannot be checked for another reason (errno in the message)
};

/// "no camera", "permission denied", …: short names for logs and status.
std::string_view problemName(DiscoveryProblem problem);

class DiscoveryError : public Error {
 public:
  DiscoveryError(DiscoveryProblem problem, const std::string& message) : Error(message), problem_(problem) {}
  DiscoveryProblem problem() const { return problem_; }

 private:
  DiscoveryProblem problem_;
};

}  // namespace vifusion::discovery
