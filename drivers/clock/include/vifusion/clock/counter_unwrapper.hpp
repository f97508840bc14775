#pragma once
// Unwraps an N-bit hardware counter (the ZR300's 12-bit sample and frame numbers, its 32-bit 32 MHz
// tick counter) into a monotone int64 count.
//
// Rule: the modular step d = (raw − last_raw) mod 2^N decides what happened.
//  - 0 < d < 2^(N−1): progress by d, across a wrap or not; d − 1 counts were skipped (a frame counter
//    uses that for dropped-frame detection; for a tick counter it is just elapsed time).
//  - d == 0: the same value again (a duplicated packet or a stalled counter), reported as kRepeat.
//  - d >= 2^(N−1): the counter went BACK by 2^N − d. That is NOT taken as a wrap: librealsense v1 adds a
//    period whenever new < last, so one corrupt or reordered value moves every later timestamp forward by
//    a whole period (134 s for the ticks). Here the value is reported (kBackward, with how far) and not
//    applied, so the caller drops that sample with a message and the next good value continues the count.
// Ambiguity it cannot remove: a forward step of half a period or more (the stream paused for over 67 s of
// ticks, or over 2048 frames) looks like a backward step. A caller that sees its host clock advance that
// much between two values calls reset() and starts again. A device that restarts its counter shows as a
// run of kBackward steps; the caller resets after a few in a row (consecutiveBackward()).
//
// The first value starts the count at the raw value itself, so the unwrapped count equals the raw count
// until the first wrap. No heap memory; one thread.

#include <cstdint>
#include <string>
#include <string_view>

namespace vifusion::clock {

/// What one raw value did to the count.
enum class CounterStep {
  kFirst,       ///< first value since construction or reset(): the count starts at it
  kProgress,    ///< moved forward (possibly across a wrap); see CounterUpdate::skipped
  kRepeat,      ///< same value as the last one; count unchanged
  kBackward,    ///< went back; not applied, count unchanged; see CounterUpdate::backward_by
  kOutOfRange,  ///< raw value has bits set above the counter width (corrupt input); not applied
};

/// The result of CounterUnwrapper::update().
struct CounterUpdate {
  CounterStep step = CounterStep::kFirst;
  std::int64_t count = 0;        ///< the unwrapped count after this value (unchanged unless kFirst/kProgress)
  std::int64_t skipped = 0;      ///< kProgress: counts skipped between the last value and this one (d − 1)
  std::int64_t backward_by = 0;  ///< kBackward: how far the raw value went back, in counts

  /// True when the caller may use this value (kFirst or kProgress).
  bool applied() const { return step == CounterStep::kFirst || step == CounterStep::kProgress; }
};

/// Running totals of what update() saw since construction (reset() keeps them).
struct CounterStats {
  std::uint64_t values = 0;          ///< update() calls
  std::uint64_t skipped = 0;         ///< sum of CounterUpdate::skipped
  std::uint64_t gaps = 0;            ///< kProgress steps with skipped > 0
  std::uint64_t repeats = 0;         ///< kRepeat
  std::uint64_t backward_steps = 0;  ///< kBackward
  std::uint64_t out_of_range = 0;    ///< kOutOfRange
  std::uint64_t wraps = 0;           ///< kProgress steps that crossed the counter's wrap
};

class CounterUnwrapper {
 public:
  /// Smallest and largest supported counter widths [bits]. 62 keeps the period and every unwrapped count
  /// of a stream far inside int64.
  static constexpr int kMinBits = 2;
  static constexpr int kMaxBits = 62;

  /// @throws vifusion::Error naming `bits` when it is outside [kMinBits, kMaxBits].
  explicit CounterUnwrapper(int bits);

  /// Feeds the next raw counter value (as read from the device) and says what it did.
  CounterUpdate update(std::uint64_t raw);

  /// The unwrapped count of `raw` that lies nearest the last applied count (within half a period either
  /// way), without changing any state: for values that share this counter's clock but arrive in their own
  /// order. The ZR300 stamps accelerometer, gyro and frame events with one tick counter, but a transfer may
  /// hold a gyro sample a few ticks older than the accelerometer sample before it; unwrapping every source
  /// against one reference (the transfer's newest tick, fed to update()) keeps them on one time base, where
  /// separate unwrappers that start on either side of a wrap would differ by a whole period.
  /// Precondition: started() and raw < period(); otherwise returns count().
  std::int64_t nearestCount(std::uint64_t raw) const;

  /// Forgets the last value: the next update() is kFirst and starts the count afresh. Statistics stay.
  void reset();

  int bits() const { return bits_; }
  std::int64_t period() const { return period_; }  ///< 2^bits counts
  bool started() const { return started_; }
  std::int64_t count() const { return count_; }  ///< the last applied unwrapped count (0 before the first)
  /// kBackward results since the last applied value: a run of them means the device restarted its counter.
  std::uint64_t consecutiveBackward() const { return consecutive_backward_; }
  const CounterStats& stats() const { return stats_; }

 private:
  int bits_;
  std::int64_t period_;
  bool started_ = false;
  std::uint64_t last_raw_ = 0;
  std::int64_t count_ = 0;
  std::uint64_t consecutive_backward_ = 0;
  CounterStats stats_;
};

/// Counter widths of the ZR300 motion module (sensors.md §1.4, §1.5).
inline constexpr int kZr300SampleCounterBits = 12;  ///< IMU sample and frame-event numbers, wrap at 4096
inline constexpr int kZr300TickCounterBits = 32;    ///< 32 MHz tick counter, wraps every ≈134.2 s

/// A short text for a step ("backward", …) for messages.
const char* counterStepName(CounterStep step);

/// What a value did, for the caller's log, naming the field: e.g. "frame_number = 4093 goes back by 5
/// counts (12-bit counter)", "frame_number = 9 skips 3 counts", "sample_ticks = 5000000000 is out of
/// range for a 32-bit counter". kFirst and gap-free kProgress give "field = raw ok". Builds a string:
/// for the error path only.
std::string counterUpdateMessage(std::string_view field, std::uint64_t raw, const CounterUpdate& update, int bits);

}  // namespace vifusion::clock
