#include "vifusion/discovery/zr300_camera.hpp"

#include <cassert>

#include "udev_helpers.hpp"

namespace vifusion::discovery {

std::string_view streamName(Zr300Stream stream) {
  switch (stream) {
    case Zr300Stream::kInfrared:
      return "IR";
    case Zr300Stream::kDepth:
      return "depth";
    case Zr300Stream::kColour:
      return "colour";
  }
  return "unknown stream";
}

std::string_view Zr300Camera::hubDevpath() const { return detail::parentDevpath(camera_usb.devpath); }

const VideoNodeInfo& Zr300Camera::stream(Zr300Stream which) const {
  assert(hasAllStreams());
  return capture_nodes[static_cast<std::size_t>(which)];
}

std::string Zr300Camera::label() const {
  if (!serial().empty()) return "ZR300 " + serial();
  return "ZR300 at " + camera_usb.syspath + " (no serial)";
}

}  // namespace vifusion::discovery
