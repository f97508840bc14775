#include "vifusion/core/time.hpp"

#include <time.h>

namespace vifusion {

std::int64_t monotonicNowNs() {
  timespec ts{};
  // CLOCK_MONOTONIC cannot fail with a valid timespec pointer (EINVAL/EFAULT only), so no error path.
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerSecond + static_cast<std::int64_t>(ts.tv_nsec);
}

std::optional<std::int64_t> decimalSecondsToNs(std::string_view text) {
  const std::size_t dot = text.find('.');
  const std::string_view whole = text.substr(0, dot);
  const std::string_view fraction = dot == std::string_view::npos ? std::string_view() : text.substr(dot + 1);
  if (whole.empty() || whole.size() > 10 || fraction.size() > 9) return std::nullopt;
  std::int64_t seconds = 0;
  for (const char c : whole) {
    if (c < '0' || c > '9') return std::nullopt;
    seconds = seconds * 10 + (c - '0');
  }
  std::int64_t fraction_ns = 0;
  for (std::size_t k = 0; k < 9; ++k) {
    const char c = k < fraction.size() ? fraction[k] : '0';
    if (c < '0' || c > '9') return std::nullopt;
    fraction_ns = fraction_ns * 10 + (c - '0');
  }
  // Checked in seconds first, so the product below cannot overflow.
  if (seconds > kMaxFileStampNs / kNsPerSecond) return std::nullopt;
  const std::int64_t t_ns = seconds * kNsPerSecond + fraction_ns;
  if (t_ns > kMaxFileStampNs) return std::nullopt;
  return t_ns;
}

}  // namespace vifusion
