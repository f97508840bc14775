#include "vifusion/daemon/frame_reader.hpp"

#include <algorithm>
#include <thread>

#include "vifusion/config/daemon_config.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/service/log.hpp"

namespace vifusion::daemon {
namespace {

/// Sleeps until `until_ns` (CLOCK_MONOTONIC) in short steps, so a stop request is seen quickly.
void sleepUntil(std::int64_t until_ns, const std::atomic<bool>& stop) {
  constexpr std::int64_t kStepNs = 20 * kNsPerMillisecond;
  for (std::int64_t now = monotonicNowNs(); now < until_ns && !stop; now = monotonicNowNs()) {
    std::this_thread::sleep_for(std::chrono::nanoseconds(std::min(until_ns - now, kStepNs)));
  }
}

}  // namespace

void runFrameReader(datasets::DatasetReader& source, bool realtime, SharedState& state, recording::Recorder* recorder) {
  // A camera comes at its own pace: never paced by timestamps.
  const bool paced = realtime && !source.live();
  FrameSlot slot = FrameSlot();
  std::int64_t first_t_ns = 0, start_ns = 0;
  bool first = true;
  std::uint64_t index = 0;  ///< frames taken from the source, the unreadable ones included
  try {
    while (!state.stop) {
      bool more = false;
      try {
        more = source.nextFrame(slot.frame);
      } catch (const Error& error) {
        if (source.live()) throw;
        service::logLine(service::LogLevel::Warning, "frame %llu unreadable, passed over: %s",
                         static_cast<unsigned long long>(index++), error.what());
        ++state.frames_unreadable;
        continue;
      }
      if (!more) break;
      ++index;
      if (first) {
        first_t_ns = slot.frame.t_ns;
        start_ns = monotonicNowNs();
        first = false;
      } else if (paced) {
        sleepUntil(start_ns + (slot.frame.t_ns - first_t_ns), state.stop);
      }
      if (!realtime) {
        // size() seen by the producer can only overstate the fill, so a free slot stays free.
        while (state.frames.size() == state.frames.capacity() && !state.stop) {
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
      }
      if (recorder != nullptr) recorder->pushFrame(slot.frame);
      slot.read_ns = monotonicNowNs();
      slot.sensor_ns = source.live() ? slot.frame.t_ns
                       : paced       ? start_ns + (slot.frame.t_ns - first_t_ns)
                                     : slot.read_ns;
      // Swapping hands the frame over and gets a recycled slot back, its buffers already sized.
      state.frames.tryPush(std::move(slot));
    }
  } catch (const std::exception& error) {
    service::logLine(service::LogLevel::Error, "source failed: %s", error.what());
    state.fail(config::kExitSource);
  }
  state.source_done = true;
}

}  // namespace vifusion::daemon
