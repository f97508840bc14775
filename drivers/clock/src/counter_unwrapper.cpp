#include "vifusion/clock/counter_unwrapper.hpp"

#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::clock {

CounterUnwrapper::CounterUnwrapper(int bits) : bits_(bits), period_(0) {
  if (bits < kMinBits || bits > kMaxBits) {
    throw Error("counter unwrapper: bits = " + std::to_string(bits) + " must be in [" + std::to_string(kMinBits) +
                ", " + std::to_string(kMaxBits) + "]");
  }
  period_ = std::int64_t{1} << bits;
}

CounterUpdate CounterUnwrapper::update(std::uint64_t raw) {
  ++stats_.values;
  CounterUpdate result;
  result.count = count_;
  const std::uint64_t period = static_cast<std::uint64_t>(period_);
  if (raw >= period) {
    ++stats_.out_of_range;
    result.step = CounterStep::kOutOfRange;
    return result;
  }
  if (!started_) {
    started_ = true;
    last_raw_ = raw;
    count_ = static_cast<std::int64_t>(raw);
    consecutive_backward_ = 0;
    result.step = CounterStep::kFirst;
    result.count = count_;
    return result;
  }
  // Unsigned subtraction is modulo 2^64, and 2^bits divides 2^64, so masking gives the step mod 2^bits.
  const std::uint64_t step = (raw - last_raw_) & (period - 1);
  if (step == 0) {
    ++stats_.repeats;
    result.step = CounterStep::kRepeat;
    return result;
  }
  if (step >= period / 2) {
    ++stats_.backward_steps;
    ++consecutive_backward_;
    result.step = CounterStep::kBackward;
    result.backward_by = static_cast<std::int64_t>(period - step);
    return result;
  }
  if (raw < last_raw_) ++stats_.wraps;
  last_raw_ = raw;
  count_ += static_cast<std::int64_t>(step);
  consecutive_backward_ = 0;
  result.step = CounterStep::kProgress;
  result.count = count_;
  result.skipped = static_cast<std::int64_t>(step) - 1;
  if (result.skipped > 0) {
    ++stats_.gaps;
    stats_.skipped += static_cast<std::uint64_t>(result.skipped);
  }
  return result;
}

std::int64_t CounterUnwrapper::nearestCount(std::uint64_t raw) const {
  const std::uint64_t period = static_cast<std::uint64_t>(period_);
  if (!started_ || raw >= period) return count_;
  const std::uint64_t step = (raw - last_raw_) & (period - 1);
  // Forward by less than half a period, otherwise back by the rest of the period.
  return step < period / 2 ? count_ + static_cast<std::int64_t>(step)
                           : count_ - static_cast<std::int64_t>(period - step);
}

void CounterUnwrapper::reset() {
  started_ = false;
  last_raw_ = 0;
  count_ = 0;
  consecutive_backward_ = 0;
}

const char* counterStepName(CounterStep step) {
  switch (step) {
    case CounterStep::kFirst:
      return "first";
    case CounterStep::kProgress:
      return "progress";
    case CounterStep::kRepeat:
      return "repeat";
    case CounterStep::kBackward:
      return "backward";
    case CounterStep::kOutOfRange:
      return "out of range";
  }
  return "unknown";
}

std::string counterUpdateMessage(std::string_view field, std::uint64_t raw, const CounterUpdate& update, int bits) {
  std::string text = std::string(field) + " = " + std::to_string(raw);
  const std::string width = " (" + std::to_string(bits) + "-bit counter)";
  switch (update.step) {
    case CounterStep::kFirst:
    case CounterStep::kProgress:
      if (update.skipped > 0) return text + " skips " + std::to_string(update.skipped) + " counts";
      return text + " ok";
    case CounterStep::kRepeat:
      return text + " repeats the previous value" + width;
    case CounterStep::kBackward:
      return text + " goes back by " + std::to_string(update.backward_by) + " counts" + width;
    case CounterStep::kOutOfRange:
      return text + " is out of range for a " + std::to_string(bits) + "-bit counter";
  }
  return text;
}

}  // namespace vifusion::clock
