#include "vifusion/zr300/zr300_options.hpp"

#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::zr300 {
namespace {

constexpr int kMinBuffers = 2;
constexpr int kMaxBuffers = 32;
constexpr std::size_t kMaxFrameRing = 64;

void checkRange(const char* field, std::int64_t value, std::int64_t low, std::int64_t high) {
  if (value < low || value > high) {
    throw Error(std::string("Zr300Options.") + field + " = " + std::to_string(value) + " is outside [" +
                std::to_string(low) + ", " + std::to_string(high) + "]");
  }
}

}  // namespace

void Zr300Options::validate() const {
  bool known = false;
  for (const StreamPreset& p : kPresets) {
    known = known || (p.width_px == preset.width_px && p.height_px == preset.height_px && p.fps == preset.fps);
  }
  if (!known) {
    throw Error("Zr300Options.preset " + std::to_string(preset.width_px) + "x" + std::to_string(preset.height_px) +
                " at " + std::to_string(preset.fps) + " Hz is not one of 640x480@30, 320x240@30, 480x360@60");
  }
  checkRange("buffer_count", buffer_count, kMinBuffers, kMaxBuffers);
  checkRange("frame_ring_capacity", static_cast<std::int64_t>(frame_ring_capacity), 1, kMaxFrameRing);
  checkRange("poll_timeout_ns", poll_timeout_ns, kNsPerMillisecond, kNsPerSecond);
  checkRange("frame_event_wait_ns", frame_event_wait_ns, 0, kNsPerSecond);
  checkRange("frame_event_tolerance_ns", frame_event_tolerance_ns, 1, kNsPerSecond);
  checkRange("reopen_backoff_min_ns", reopen_backoff_min_ns, kNsPerMillisecond, 10 * kNsPerSecond);
  checkRange("reopen_backoff_max_ns", reopen_backoff_max_ns, reopen_backoff_min_ns, 60 * kNsPerSecond);
  motion.validate();
  imu_feed.validate();
}

}  // namespace vifusion::zr300
