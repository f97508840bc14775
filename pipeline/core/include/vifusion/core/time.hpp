#pragma once
// Time in vifusion is an int64_t count of nanoseconds on the host CLOCK_MONOTONIC (device clocks are
// mapped onto it by the drivers). Integers keep timestamps exact and comparable for ~292 years; a
// double of seconds is made only where a duration enters arithmetic (dt in preintegration, rates),
// never stored. Names carry the unit: t_ns, dt_ns, dt_s.

#include <cassert>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>

namespace vifusion {

inline constexpr std::int64_t kNsPerMicrosecond = 1'000;
inline constexpr std::int64_t kNsPerMillisecond = 1'000'000;
inline constexpr std::int64_t kNsPerSecond = 1'000'000'000;

/// Nanoseconds to seconds, correctly rounded (a division; multiplying by the inexact 1e-9 is not).
/// secondsToNs(nsToSeconds(t_ns)) == t_ns for |t_ns| <= 1e15 ns (11.5 days), far above any duration.
constexpr double nsToSeconds(std::int64_t t_ns) {
  return static_cast<double>(t_ns) / static_cast<double>(kNsPerSecond);
}

/// Seconds to nanoseconds, rounded to the nearest nanosecond (halves away from zero).
/// Precondition: t_s is finite and |t_s| < 9.2e9 s, so the result fits in int64_t.
inline std::int64_t secondsToNs(double t_s) {
  const double t_ns = t_s * static_cast<double>(kNsPerSecond);
  assert(std::isfinite(t_ns) && std::abs(t_ns) < 9.2e18);
  return static_cast<std::int64_t>(std::llround(t_ns));
}

/// Largest stamp magnitude a file may hold [ns]: 4e9 s, Unix time in the year 2096 (CLOCK_MONOTONIC
/// stamps are far smaller). Readers refuse stamps outside ±kMaxFileStampNs, so the difference of any
/// two stamps, or a stamp ± a window up to kMaxFileStampNs, fits in int64_t (2 · 4e18 < 9.22e18)
/// and code downstream can subtract stamps without overflow.
inline constexpr std::int64_t kMaxFileStampNs = 4'000'000'000 * kNsPerSecond;

/// Whether a stamp read from a file lies within ±kMaxFileStampNs.
constexpr bool isFileStampInRange(std::int64_t t_ns) { return t_ns >= -kMaxFileStampNs && t_ns <= kMaxFileStampNs; }

/// Current host CLOCK_MONOTONIC time [ns]: the clock V4L2 buffer timestamps and libgpiod edge events
/// use, so sensor times and host times compare without conversion.
std::int64_t monotonicNowNs();

/// Exact conversion of plain decimal seconds text, "digits[.digits]" with at most 10 whole and 9
/// fractional digits (what TUM, ICL-NUIM and EuRoC files hold), to nanoseconds: 1305031098.6659 s
/// becomes exactly 1305031098665900000 ns, where a double would round to ~0.2 µs at this magnitude
/// and break exact stamp comparisons. Anything else (signs, exponents, spaces) gives nullopt, and so
/// does a value beyond kMaxFileStampNs.
std::optional<std::int64_t> decimalSecondsToNs(std::string_view text);

}  // namespace vifusion
