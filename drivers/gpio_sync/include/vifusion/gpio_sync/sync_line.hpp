#pragma once
// The sync line (the camera's strobe or an external trigger on a GPIO) as a driver thread: requests edge
// events on the configured chip and line through a GpioLineIo, waits for them with a bounded timeout (so
// stop() is seen within options.wait_timeout_ms), reads each batch into a fixed array, checks and pushes
// the edges through an EdgeDecoder into edgeRing(), which the consumer pops.
//
// Time: every edge keeps the kernel's timestamp, taken in the GPIO interrupt, on host CLOCK_MONOTONIC
// (Linux >= 5.7; older kernels stamp CLOCK_REALTIME and every edge is dropped as clock_mismatch, with a
// message saying so). The thread's own wake-up latency therefore never enters an edge's time.
//
// Chip gone (ENODEV: a USB GPIO expander unplugged) ends the stream in kGone, never an exception; other
// failures leave kFailed and lastError(). stop() is safe in every state; start() again re-opens the line.
//
// Threads: start(), stop() and the destructor on one owning thread; the ring's consumer side on one
// consumer thread; state(), stats(), lastProblem() and lastError() from any thread.

#include <array>
#include <atomic>
#include <memory>
#include <string>
#include <thread>

#include "vifusion/core/spsc_ring.hpp"
#include "vifusion/gpio_sync/edge_decoder.hpp"
#include "vifusion/gpio_sync/gpio_line_io.hpp"
#include "vifusion/gpio_sync/problem_note.hpp"
#include "vifusion/gpio_sync/sync_edge.hpp"
#include "vifusion/gpio_sync/sync_line_options.hpp"
#include "vifusion/gpio_sync/sync_line_stats.hpp"

namespace vifusion::gpio_sync {

class SyncLine {
 public:
  /// @throws vifusion::Error if options.validate() does or `io` is null.
  explicit SyncLine(std::unique_ptr<GpioLineIo> io, const SyncLineOptions& options = {});
  /// Stops the thread and releases the line.
  ~SyncLine();
  SyncLine(const SyncLine&) = delete;
  SyncLine& operator=(const SyncLine&) = delete;

  /// Requests the line and starts the driver thread; sequence numbers restart at 0. Calls stop() first if
  /// already started. @throws vifusion::Error from GpioLineIo::open(), naming the chip and line.
  void start();
  /// Ends the thread and releases the line. Never throws; leaves kClosed, or kGone/kFailed as they were.
  void stop();

  SyncLineState state() const { return state_.load(std::memory_order_acquire); }
  /// Snapshot of every counter and the edge rate, readable from any thread.
  SyncLineStats stats() const;
  /// The most recent dropped edge, e.g. "gpiochip0 line 17: edge 12 time goes backwards by 1.500000 ms
  /// (dropped)"; empty if none.
  std::string lastProblem() const { return problems_.text(); }
  /// What ended the stream in kGone or kFailed; empty otherwise.
  std::string lastError() const { return errors_.text(); }
  /// "gpiochip0 line 17": how every message names the line.
  const std::string& lineName() const { return decoder_.lineName(); }

  /// Consumer side of the ring (capacity options.ring_capacity).
  SpscRing<SyncEdge>& edgeRing() { return ring_; }

 private:
  void threadMain();
  /// Ends the stream after a failed wait or read: kGone or kFailed, with a message naming the step.
  void endStream(LineStatus status, const char* step);

  SyncLineOptions options_;
  std::unique_ptr<GpioLineIo> io_;
  SpscRing<SyncEdge> ring_;
  ProblemNote problems_;
  ProblemNote errors_;
  EdgeDecoder decoder_;
  std::array<LineEvent, kMaxEventsPerRead> events_{};
  std::atomic<SyncLineState> state_{SyncLineState::kClosed};
  std::atomic<bool> running_{false};
  bool opened_ = false;
  std::thread thread_;
};

}  // namespace vifusion::gpio_sync
