#include "vifusion/gpio_sync/edge_decoder.hpp"

#include <cinttypes>
#include <limits>
#include <utility>

namespace vifusion::gpio_sync {
namespace {

const char* edgeTypeName(EdgeType type) {
  switch (type) {
    case EdgeType::kRising:
      return "rising";
    case EdgeType::kFalling:
      return "falling";
    case EdgeType::kUnknown:
      return "unknown";
  }
  return "invalid";
}

const SyncLineOptions& validated(const SyncLineOptions& options) {
  options.validate();
  return options;
}

}  // namespace

EdgeDecoder::EdgeDecoder(std::string line_name, const SyncLineOptions& options, SpscRing<SyncEdge>& ring,
                         ProblemNote& problems)
    : line_name_(std::move(line_name)),
      requested_edges_(validated(options).edges),
      ring_(ring),
      problems_(problems),
      meter_(options.rate_capacity, options.rate_window_ns) {}

void EdgeDecoder::decode(std::span<const LineEvent> events, std::int64_t read_ns) {
  for (const LineEvent& event : events) {
    const std::uint64_t sequence = next_sequence_++;
    bump(edges_read_);
    if (!accepts(event, sequence, read_ns)) continue;
    have_previous_ = true;
    previous_t_ns_ = event.t_ns;
    last_edge_t_ns_.store(event.t_ns, std::memory_order_relaxed);
    meter_.add(event.t_ns);
    const SyncEdge edge{event.t_ns, event.type == EdgeType::kRising, sequence};
    if (ring_.tryPush(edge)) {
      bump(edges_);
    } else {
      bump(overruns_);
    }
  }
}

bool EdgeDecoder::accepts(const LineEvent& event, std::uint64_t sequence, std::int64_t read_ns) {
  const char* line = line_name_.c_str();
  if (!requested(event.type)) {
    bump(bad_event_type_);
    problems_.set("%s: edge %" PRIu64 " has event type %s, but %s edges were requested (dropped)", line, sequence,
                  edgeTypeName(event.type), edgeDetectionName(requested_edges_).data());
    return false;
  }
  if (event.t_ns == kUnrepresentableTimeNs || event.t_ns < 0) {
    bump(bad_timestamp_);
    if (event.t_ns == kUnrepresentableTimeNs) {
      problems_.set("%s: edge %" PRIu64 " timestamp does not fit in int64 ns (dropped)", line, sequence);
    } else {
      problems_.set("%s: edge %" PRIu64 " timestamp %" PRId64 " ns is negative (dropped)", line, sequence, event.t_ns);
    }
    return false;
  }
  if (read_ns <= std::numeric_limits<std::int64_t>::max() - kClockSlackNs && event.t_ns > read_ns + kClockSlackNs) {
    bump(clock_mismatch_);
    problems_.set("%s: edge %" PRIu64
                  " timestamp is %.6f s after it was read on CLOCK_MONOTONIC: the kernel stamps "
                  "another clock (Linux < 5.7 stamps CLOCK_REALTIME) (dropped)",
                  line, sequence, nsToSeconds(event.t_ns - read_ns));
    return false;
  }
  if (have_previous_ && event.t_ns < previous_t_ns_) {
    bump(time_backwards_);
    problems_.set("%s: edge %" PRIu64 " time goes backwards by %.6f ms (dropped)", line, sequence,
                  static_cast<double>(previous_t_ns_ - event.t_ns) / static_cast<double>(kNsPerMillisecond));
    return false;
  }
  return true;
}

bool EdgeDecoder::requested(EdgeType type) const {
  switch (type) {
    case EdgeType::kRising:
      return requested_edges_ != EdgeDetection::kFalling;
    case EdgeType::kFalling:
      return requested_edges_ != EdgeDetection::kRising;
    case EdgeType::kUnknown:
      return false;
  }
  return false;
}

void EdgeDecoder::publishRate(std::int64_t now_ns) {
  edge_rate_hz_.store(meter_.rateHz(now_ns), std::memory_order_relaxed);
}

SyncLineStats EdgeDecoder::stats() const {
  SyncLineStats out;
  out.edges_read = edges_read_.load(std::memory_order_relaxed);
  out.edges = edges_.load(std::memory_order_relaxed);
  out.overruns = overruns_.load(std::memory_order_relaxed);
  out.time_backwards = time_backwards_.load(std::memory_order_relaxed);
  out.bad_event_type = bad_event_type_.load(std::memory_order_relaxed);
  out.bad_timestamp = bad_timestamp_.load(std::memory_order_relaxed);
  out.clock_mismatch = clock_mismatch_.load(std::memory_order_relaxed);
  out.last_edge_t_ns = last_edge_t_ns_.load(std::memory_order_relaxed);
  out.edge_rate_hz = edge_rate_hz_.load(std::memory_order_relaxed);
  return out;
}

void EdgeDecoder::reset() {
  next_sequence_ = 0;
  have_previous_ = false;
  previous_t_ns_ = 0;
  meter_.reset();
  edge_rate_hz_.store(0.0, std::memory_order_relaxed);
}

}  // namespace vifusion::gpio_sync
