#pragma once
// GpioLineIo over libgpiod v1 (Debian 12: libgpiod 1.6), built only when libgpiod is found and live drivers
// are on. libgpiod 1.6 speaks the kernel's v1 GPIO character-device uAPI (GPIO_GET_LINEEVENT_IOCTL):
//  - the request is gpiod_line_request_{rising_edge,falling_edge,both_edges}_events with consumer
//    kSyncConsumerName ("vifusion-sync");
//  - the kernel stamps each event in its interrupt handler. Since Linux 5.7 that stamp is CLOCK_MONOTONIC
//    (ktime_get_ns), the clock of V4L2 buffers and of vifusion::monotonicNowNs(); Linux 4.8 to 5.6 stamped
//    CLOCK_REALTIME, which NTP or settimeofday can step. Those edges lie decades after CLOCK_MONOTONIC's
//    "now", so EdgeDecoder drops them as clock_mismatch with a message naming the kernel, never passing a
//    wrong clock on silently. (The v2 uAPI of Linux >= 5.10 can choose the clock; libgpiod 1.6 does not
//    use it.)
//  - gpiod_line_event_wait polls the line's event fd with the timeout; gpiod_line_event_read_multiple
//    reads up to kMaxEventsPerRead events into a fixed member array, then they are converted in place:
//    no allocation per batch. libgpiod 1.6 reports every uAPI event id other than rising as falling, so
//    EdgeType::kUnknown cannot come from this line (a malformed id shows up as an unrequested falling edge).

#include <memory>

#include "vifusion/gpio_sync/gpio_line_io.hpp"

struct gpiod_chip;
struct gpiod_line;
struct gpiod_line_event;

namespace vifusion::gpio_sync {

class LibgpiodLineIo final : public GpioLineIo {
 public:
  LibgpiodLineIo();
  ~LibgpiodLineIo() override;
  LibgpiodLineIo(const LibgpiodLineIo&) = delete;
  LibgpiodLineIo& operator=(const LibgpiodLineIo&) = delete;

  /// @throws vifusion::Error with gpio_errors.hpp's messages: missing chip, not a GPIO chip, permission,
  ///         line out of range (naming the chip's line count), line busy (naming its holder).
  void open(std::string_view chip, unsigned line_offset, EdgeDetection edges) override;
  LineStatus waitEvent(int timeout_ms) override;
  LineStatus readEvents(std::span<LineEvent> out, std::size_t& count) override;
  std::int64_t nowNs() override;
  const char* errorText() const override { return error_text_; }
  void close() override;

 private:
  /// kGone for ENODEV (the chip went away), kError otherwise; remembers the errno text.
  LineStatus failure(int error_number);

  gpiod_chip* chip_ = nullptr;
  gpiod_line* line_ = nullptr;
  const char* error_text_ = "";
  std::unique_ptr<gpiod_line_event[]> raw_events_;  ///< kMaxEventsPerRead libgpiod event records, allocated once
};

}  // namespace vifusion::gpio_sync
