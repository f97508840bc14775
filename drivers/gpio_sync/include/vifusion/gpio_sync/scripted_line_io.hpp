#pragma once
// A GPIO line in memory, for tests and for replaying recorded edges: the test queues edges (and failures)
// from its own thread; the driver thread waits for and reads them through the GpioLineIo calls exactly as
// it would from a chip. Waits block on a condition variable for up to their timeout in real time, so an
// idle scripted line costs no CPU and stop() is seen as on a real line.
//
// The scripted clock (nowNs()) is what the driver reads as "now" on the events' clock: it starts at
// `start_ns`, moves to kReadLatencyNs after the newest edge handed out by a read, and on by the timeout
// on every wait that times out, so the driver sees a consistent, deterministic clock; setNowNs() pins it
// (to script edges stamped on another clock, which must then look like the future).
//
// Storage for `max_edges` queued edges is reserved at construction; the wait/read calls allocate nothing.

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "vifusion/core/time.hpp"
#include "vifusion/gpio_sync/gpio_line_io.hpp"

namespace vifusion::gpio_sync {

class ScriptedLineIo final : public GpioLineIo {
 public:
  /// Time between an edge and the read that returns it on the scripted clock [ns]: a typical interrupt
  /// to thread wake-up delay; only its sign matters to the driver (reads come after edges).
  static constexpr std::int64_t kReadLatencyNs = 50 * kNsPerMicrosecond;

  /// Default storage [edges]: two minutes of a 30 Hz strobe, more than any test streams.
  static constexpr std::size_t kDefaultMaxEdges = 4096;
  /// Default start of the scripted clock [ns]: 1 s after "boot", so no edge time is zero or negative.
  static constexpr std::int64_t kDefaultStartNs = kNsPerSecond;

  explicit ScriptedLineIo(std::size_t max_edges = kDefaultMaxEdges, std::int64_t start_ns = kDefaultStartNs);

  // ---- script (test thread) ----

  /// Queues one event; readEvents() hands queued events out in this order, up to its buffer size at a time.
  /// @throws vifusion::Error when max_edges events have been queued.
  void pushEdge(std::int64_t t_ns, EdgeType type = EdgeType::kRising);
  /// After the queued events are read, waits return `status` (kGone or kError) with `text` as errorText();
  /// kEvents clears a scripted failure (the chip is back).
  void failAfterQueued(LineStatus status, const char* text);
  /// The next open() throws vifusion::Error(message).
  void failOpen(std::string message);
  /// Sets the scripted clock [ns] and pins it there: reads and timeouts no longer move it.
  void setNowNs(std::int64_t now_ns);

  // ---- observe (any thread) ----

  bool isOpen() const;
  int openCount() const;
  std::string openedChip() const;
  unsigned openedLine() const;
  EdgeDetection openedEdges() const;
  /// Events handed out by readEvents() so far.
  std::size_t eventsRead() const;
  /// Queued events not read yet.
  std::size_t eventsPending() const;

  // ---- GpioLineIo (driver thread) ----

  void open(std::string_view chip, unsigned line_offset, EdgeDetection edges) override;
  LineStatus waitEvent(int timeout_ms) override;
  LineStatus readEvents(std::span<LineEvent> out, std::size_t& count) override;
  std::int64_t nowNs() override;
  const char* errorText() const override;
  void close() override;

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<LineEvent> events_;  ///< every event queued, reserved to max_edges
  std::size_t max_edges_;
  std::size_t next_ = 0;  ///< first event not read yet
  std::int64_t now_ns_;
  bool clock_pinned_ = false;
  LineStatus failure_ = LineStatus::kEvents;  ///< kEvents: no failure scripted
  const char* failure_text_ = "";
  const char* error_text_ = "";
  std::string open_failure_;
  bool open_ = false;
  int open_count_ = 0;
  std::string chip_;
  unsigned line_offset_ = 0;
  EdgeDetection edges_ = EdgeDetection::kRising;
};

}  // namespace vifusion::gpio_sync
