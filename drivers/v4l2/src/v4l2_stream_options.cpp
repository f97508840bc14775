#include "vifusion/v4l2/v4l2_stream_options.hpp"

#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::v4l2 {
namespace {
void requireInRange(const char* field, long long value, long long lowest, long long highest) {
  if (value < lowest || value > highest) {
    throw Error("V4l2StreamOptions." + std::string(field) + " = " + std::to_string(value) + " is outside [" +
                std::to_string(lowest) + ", " + std::to_string(highest) + "]");
  }
}
}  // namespace

void V4l2StreamOptions::validate() const {
  if (node_path.empty()) throw Error("V4l2StreamOptions.node_path is empty (" + label + " stream)");
  if (bytesPerPixel(fourcc) == 0) {
    throw Error("V4l2StreamOptions.fourcc '" + std::string(fourccText(fourcc).data()) +
                "' is not a format this driver lays out (Z16, YUYV, GREY)");
  }
  requireInRange("width_px", width_px, 1, kMaxFrameDimensionPx);
  requireInRange("height_px", height_px, 1, kMaxFrameDimensionPx);
  requireInRange("fps", fps, 1, kMaxFrameRateHz);
  requireInRange("buffer_count", buffer_count, kMinStreamingBuffers, kMaxStreamingBuffers);
  requireInRange("timing.exposure_ns", timing.exposure_ns, 0, kNsPerSecond / fps);
  requireInRange("timing.readout_ns", timing.readout_ns, 0, kNsPerSecond / fps);
}

}  // namespace vifusion::v4l2
