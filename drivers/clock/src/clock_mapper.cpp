#include "vifusion/clock/clock_mapper.hpp"

#include <algorithm>
#include <cmath>

namespace vifusion::clock {
namespace {

constexpr double kPpm = 1e-6;
/// Where the skew chord meets the hull: this fraction of the window's span in from each end (so the chord
/// spans the middle half of the window; clock_mapper.hpp says why).
constexpr double kChordInset = 0.25;

bool inClockRange(std::int64_t t_ns) { return t_ns >= 0 && t_ns <= kMaxClockTimeNs; }

const ClockMapperOptions& validated(const ClockMapperOptions& options) {
  options.validate();
  return options;
}

}  // namespace

const char* clockMapperStateName(ClockMapperState state) {
  switch (state) {
    case ClockMapperState::kEmpty:
      return "empty";
    case ClockMapperState::kWarmingUp:
      return "warming up";
    case ClockMapperState::kValid:
      return "valid";
  }
  return "unknown";
}

std::int64_t ClockEstimate::toHostNs(std::int64_t device_ns) const {
  const std::int64_t dx_ns = std::clamp<std::int64_t>(device_ns, 0, kMaxClockTimeNs) - ref_device_ns;
  return ref_host_ns + dx_ns + std::llround(skew * static_cast<double>(dx_ns));
}

double ClockEstimate::skewPpm() const { return skew / kPpm; }

ClockMapper::ClockMapper(const ClockMapperOptions& options)
    : options_(validated(options)),
      window_ns_(options.windowNs()),
      min_span_ns_(options.minSpanNs()),
      hull_(options.window_samples) {}

ClockSampleResult ClockMapper::addSample(std::int64_t device_ns, std::int64_t host_receive_ns) {
  ++stats_.samples;
  ClockSampleResult result;
  result.device_ns = device_ns;
  result.host_ns = host_receive_ns;
  if (!inClockRange(device_ns) || !inClockRange(host_receive_ns)) {
    ++stats_.out_of_range;
    result.outcome = ClockSampleOutcome::kOutOfRange;
    return result;
  }
  const ClockPoint point{device_ns, host_receive_ns - options_.fixed_latency_ns};

  if (!hull_.empty()) {
    const ClockPoint newest = hull_.newest();
    std::uint64_t* rejection_count = nullptr;
    if (point.device_ns <= newest.device_ns) {
      result.outcome = ClockSampleOutcome::kDeviceNotIncreasing;
      result.reference_ns = newest.device_ns;
      rejection_count = &stats_.device_not_increasing;
    } else if (point.host_ns < newest.host_ns) {
      // CLOCK_MONOTONIC cannot go back: the caller mixed up clocks or samples. Never a clock step.
      ++stats_.host_backwards;
      result.outcome = ClockSampleOutcome::kHostBackwards;
      result.reference_ns = newest.host_ns + options_.fixed_latency_ns;
      return result;
    } else if (state_ == ClockMapperState::kValid) {
      const std::int64_t predicted_ns = estimate_.toHostNs(point.device_ns);
      if (point.host_ns < predicted_ns - options_.max_early_ns) {
        result.outcome = ClockSampleOutcome::kEarly;
        result.reference_ns = predicted_ns + options_.fixed_latency_ns;
        rejection_count = &stats_.early;
      }
    }
    if (rejection_count != nullptr) {
      if (!holdBack(point)) {
        ++*rejection_count;
        return result;
      }
      result.outcome = ClockSampleOutcome::kRestarted;
      result.reference_ns = static_cast<std::int64_t>(held_back_count_);
      restartFromHeldBack();
      ++stats_.accepted;
      return result;
    }
  }
  held_back_count_ = 0;
  accept(point);
  ++stats_.accepted;
  result.outcome = ClockSampleOutcome::kAccepted;
  return result;
}

std::optional<std::int64_t> ClockMapper::toHostNs(std::int64_t device_ns) const {
  if (state_ == ClockMapperState::kEmpty) return std::nullopt;
  return estimate_.toHostNs(device_ns);
}

std::int64_t ClockMapper::offsetNs() const {
  if (state_ == ClockMapperState::kEmpty) return 0;
  const std::int64_t newest_device_ns = hull_.newest().device_ns;
  return estimate_.toHostNs(newest_device_ns) - newest_device_ns;
}

std::int64_t ClockMapper::spanNs() const {
  return hull_.empty() ? 0 : hull_.newest().device_ns - hull_.oldest().device_ns;
}

void ClockMapper::reset() {
  hull_.clear();
  held_back_count_ = 0;
  last_valid_skew_ = 0.0;
  updateEstimate();
}

bool ClockMapper::holdBack(ClockPoint point) {
  if (held_back_count_ > 0) {
    const ClockPoint last = held_back_[held_back_count_ - 1];
    // A repeated transfer neither confirms nor breaks a run.
    if (point.device_ns == last.device_ns) return false;
    // Held-back samples must agree with each other to be a step; otherwise this one starts a new run (so
    // one corrupt sample cannot block a real step that follows it).
    if (point.device_ns < last.device_ns || point.host_ns < last.host_ns) held_back_count_ = 0;
  }
  held_back_[held_back_count_++] = point;
  return held_back_count_ >= options_.step_confirm_samples;
}

void ClockMapper::restartFromHeldBack() {
  hull_.clear();
  for (std::size_t i = 0; i < held_back_count_; ++i) hull_.push(held_back_[i]);
  ++stats_.restarts;
  // The last held-back sample is the one that confirmed the step; it is counted as accepted instead.
  stats_.held_back_used += held_back_count_ - 1;
  held_back_count_ = 0;
  updateEstimate();
}

void ClockMapper::accept(ClockPoint point) {
  hull_.push(point);
  hull_.expireBefore(point.device_ns - window_ns_);
  updateEstimate();
}

void ClockMapper::updateEstimate() {
  if (hull_.empty()) {
    state_ = ClockMapperState::kEmpty;
    estimate_ = ClockEstimate{};
    return;
  }
  if (hull_.size() >= options_.min_samples && spanNs() >= min_span_ns_ && hull_.vertexCount() >= 2) {
    // Skew: the chord of the hull between the points kChordInset of the span in from each end.
    const std::int64_t inset_ns = std::llround(kChordInset * static_cast<double>(spanNs()));
    const std::int64_t early_ns = hull_.oldest().device_ns + inset_ns;
    const std::int64_t late_ns = hull_.newest().device_ns - inset_ns;
    const ClockPoint origin = hull_.vertex(0);
    estimate_.skew =
        (hullExcessNs(late_ns, origin) - hullExcessNs(early_ns, origin)) / static_cast<double>(late_ns - early_ns);
    // Offset: the vertex where a line of that slope touches the hull, so the line stays under every sample.
    const ClockPoint support = hull_.vertex(hull_.supportingVertex(estimate_.skew));
    estimate_.ref_device_ns = support.device_ns;
    estimate_.ref_host_ns = support.host_ns;
    last_valid_skew_ = estimate_.skew;
    state_ = ClockMapperState::kValid;
    return;
  }
  const ClockPoint lowest = hull_.vertex(hull_.supportingVertex(last_valid_skew_));
  estimate_.ref_device_ns = lowest.device_ns;
  estimate_.ref_host_ns = lowest.host_ns;
  estimate_.skew = last_valid_skew_;
  state_ = ClockMapperState::kWarmingUp;
}

double ClockMapper::hullExcessNs(std::int64_t device_ns, ClockPoint origin) const {
  const std::size_t edge = hull_.edgeAt(device_ns);
  const ClockPoint a = hull_.vertex(edge);
  const ClockPoint b = hull_.vertex(edge + 1);
  const std::int64_t origin_excess_ns = origin.host_ns - origin.device_ns;
  const std::int64_t a_excess_ns = (a.host_ns - a.device_ns) - origin_excess_ns;
  const std::int64_t b_excess_ns = (b.host_ns - b.device_ns) - origin_excess_ns;
  const double along = static_cast<double>(device_ns - a.device_ns) / static_cast<double>(b.device_ns - a.device_ns);
  return static_cast<double>(a_excess_ns) + along * static_cast<double>(b_excess_ns - a_excess_ns);
}

}  // namespace vifusion::clock
