#pragma once
// One batch of line events → SyncEdges in the ring, the driver thread's whole per-batch path, kept free of
// GPIO and threads so it is tested on events alone. Each event gets the next sequence number, then:
//
//   type neither rising nor falling, or a kind that was not requested  → bad_event_type, dropped
//   timestamp unrepresentable or negative                              → bad_timestamp, dropped
//   timestamp after the moment the batch was read (+ kClockSlackNs)     → clock_mismatch, dropped
//   timestamp before the previous good edge                             → time_backwards, dropped
//   otherwise → the rate meter, and pushed (a full ring: overruns)
//
// Every drop also writes a message naming the line, the edge's sequence number and what was wrong into a
// ProblemNote. Equal timestamps pass: two edges in one interrupt can share a stamp, which is not disorder.
//
// Threads: decode(), publishRate() and reset() on the driver thread only; stats() from any thread (relaxed
// atomics, each counter exact, the set not one instant). No allocation after construction.

#include <atomic>
#include <cstdint>
#include <span>
#include <string>

#include "vifusion/core/spsc_ring.hpp"
#include "vifusion/gpio_sync/edge_detection.hpp"
#include "vifusion/gpio_sync/edge_rate_meter.hpp"
#include "vifusion/gpio_sync/gpio_line_io.hpp"
#include "vifusion/gpio_sync/problem_note.hpp"
#include "vifusion/gpio_sync/sync_edge.hpp"
#include "vifusion/gpio_sync/sync_line_options.hpp"
#include "vifusion/gpio_sync/sync_line_stats.hpp"

namespace vifusion::gpio_sync {

class EdgeDecoder {
 public:
  /// How far after its read an edge may be stamped [ns]. Zero would be exact for one clock (an edge cannot
  /// happen after it was read); 1 ms forgives a clock read that rounds, and is still ~10⁹ times smaller than
  /// the gap between CLOCK_REALTIME (seconds since 1970) and CLOCK_MONOTONIC (seconds since boot).
  static constexpr std::int64_t kClockSlackNs = kNsPerMillisecond;

  /// `line_name` ("gpiochip0 line 17") prefixes every message. Uses options.edges, rate_capacity and
  /// rate_window_ns. @throws vifusion::Error if options.validate() does.
  EdgeDecoder(std::string line_name, const SyncLineOptions& options, SpscRing<SyncEdge>& ring, ProblemNote& problems);

  /// Checks and pushes `events`, read at `read_ns` on the events' clock [ns]. Never throws.
  void decode(std::span<const LineEvent> events, std::int64_t read_ns);
  /// Updates the published edge rate for `now_ns` [ns] (after every wait, so a silent line decays to 0).
  void publishRate(std::int64_t now_ns);
  /// Counters (state field: kClosed; SyncLine fills it in).
  SyncLineStats stats() const;
  /// Starts a new stream: sequence numbers from 0, no previous edge, an empty meter. Counters stay.
  void reset();

  const std::string& lineName() const { return line_name_; }

 private:
  using Counter = std::atomic<std::uint64_t>;

  bool accepts(const LineEvent& event, std::uint64_t sequence, std::int64_t read_ns);
  bool requested(EdgeType type) const;
  static void bump(Counter& counter) { counter.fetch_add(1, std::memory_order_relaxed); }

  std::string line_name_;
  EdgeDetection requested_edges_;
  SpscRing<SyncEdge>& ring_;
  ProblemNote& problems_;
  EdgeRateMeter meter_;
  std::uint64_t next_sequence_ = 0;
  bool have_previous_ = false;
  std::int64_t previous_t_ns_ = 0;

  Counter edges_read_{0};
  Counter edges_{0};
  Counter overruns_{0};
  Counter time_backwards_{0};
  Counter bad_event_type_{0};
  Counter bad_timestamp_{0};
  Counter clock_mismatch_{0};
  std::atomic<std::int64_t> last_edge_t_ns_{0};
  std::atomic<double> edge_rate_hz_{0.0};
};

}  // namespace vifusion::gpio_sync
