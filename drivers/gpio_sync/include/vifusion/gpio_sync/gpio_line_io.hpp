#pragma once
// The few GPIO operations the sync-line driver needs, behind one interface: LibgpiodLineIo
// (libgpiod_line_io.hpp, libgpiod v1) talks to a real chip; ScriptedLineIo (scripted_line_io.hpp) plays a
// line in memory, so the driver's thread, ring, ordering and rate logic are tested without a GPIO chip.
// The seam sits at libgpiod's level (open a line, wait, read a batch), not at the raw ioctls: what must be
// tested without hardware is our handling of what arrives, and the uAPI framing is libgpiod's concern.
//
// open() throws (set-up: a missing chip or a busy line is a configuration problem for a person to fix);
// waitEvent() and readEvents() return LineStatus values, never throw, and allocate nothing, because they
// run on the driver thread for every batch of edges.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string_view>

#include "vifusion/gpio_sync/edge_detection.hpp"

namespace vifusion::gpio_sync {

/// Events one readEvents() call can return. The kernel's v1 line-event queue holds 16 events per line, so
/// one read of 16 drains it; a larger buffer would never fill.
inline constexpr std::size_t kMaxEventsPerRead = 16;

/// LineEvent::t_ns of an event whose kernel timestamp does not fit int64 nanoseconds (a corrupt timespec).
inline constexpr std::int64_t kUnrepresentableTimeNs = std::numeric_limits<std::int64_t>::min();

enum class EdgeType : std::uint8_t {
  kRising,
  kFalling,
  kUnknown,  ///< an event type the kernel (or libgpiod) reported that is neither
};

/// One event as the line reported it, before any check.
struct LineEvent {
  std::int64_t t_ns = 0;  ///< kernel timestamp [ns] (CLOCK_MONOTONIC on Linux >= 5.7, see libgpiod_line_io.hpp)
  EdgeType type = EdgeType::kRising;
};

enum class LineStatus : std::uint8_t {
  kEvents,   ///< events are waiting (waitEvent) or were read (readEvents)
  kTimeout,  ///< none within the timeout: an idle line is not a failure
  kGone,     ///< the chip disappeared (ENODEV: a USB GPIO expander unplugged, the driver unbound)
  kError,    ///< any other failure; errorText() says which
};

/// snake_case name, e.g. "timeout".
std::string_view lineStatusName(LineStatus status);

class GpioLineIo {
 public:
  virtual ~GpioLineIo() = default;

  /// Requests edge events on line `line_offset` of `chip` (a name under /dev such as "gpiochip0", or a path
  /// starting with '/') with consumer name kSyncConsumerName. Set-up: may allocate.
  /// @throws vifusion::Error naming the chip (and the line) when the chip is missing or not a GPIO chip,
  ///         access is denied, the line is out of range or already requested.
  virtual void open(std::string_view chip, unsigned line_offset, EdgeDetection edges) = 0;
  /// Waits up to `timeout_ms` [ms] for an event: kEvents, kTimeout, kGone or kError.
  virtual LineStatus waitEvent(int timeout_ms) = 0;
  /// Reads up to out.size() (at most kMaxEventsPerRead) queued events in the order the kernel saw them;
  /// `count` is set to how many. Call after waitEvent() said kEvents (it may block otherwise).
  virtual LineStatus readEvents(std::span<LineEvent> out, std::size_t& count) = 0;
  /// Now on the clock the events are stamped with [ns] (CLOCK_MONOTONIC for a real line).
  virtual std::int64_t nowNs() = 0;
  /// Why the last waitEvent()/readEvents() gave kGone or kError (e.g. strerror text); static storage.
  virtual const char* errorText() const = 0;
  /// Releases the line and closes the chip. Safe to call twice and after the chip is gone.
  virtual void close() = 0;
};

/// The consumer name the line is requested with: `gpioinfo` shows it next to the line while we hold it.
inline constexpr const char* kSyncConsumerName = "vifusion-sync";

}  // namespace vifusion::gpio_sync
