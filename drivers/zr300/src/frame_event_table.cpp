#include "vifusion/zr300/frame_event_table.hpp"

#include <cstdlib>

#include "vifusion/motion/packet_format.hpp"

namespace vifusion::zr300 {

void FrameEventTable::add(const usb_imu::DepthFrameEvent& event) {
  events_[next_] = event;
  next_ = (next_ + 1) % kCapacity;
  if (count_ < kCapacity) ++count_;
}

std::optional<usb_imu::DepthFrameEvent> FrameEventTable::find(std::uint32_t frame_counter, std::int64_t kernel_ns,
                                                              std::int64_t tolerance_ns) const {
  const auto wanted = static_cast<std::uint16_t>(frame_counter % motion::kCounterModulus);
  std::optional<usb_imu::DepthFrameEvent> best;
  std::int64_t best_distance = tolerance_ns + 1;
  for (std::size_t i = 0; i < count_; ++i) {
    const usb_imu::DepthFrameEvent& event = events_[i];
    if (event.frame_counter != wanted) continue;
    const std::int64_t distance = std::llabs(event.t_ns - kernel_ns);
    if (distance < best_distance) {
      best_distance = distance;
      best = event;
    }
  }
  return best;
}

}  // namespace vifusion::zr300
