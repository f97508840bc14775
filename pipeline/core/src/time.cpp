#include "vifusion/core/time.hpp"

#include <time.h>

namespace vifusion {

std::int64_t monotonicNowNs() {
  timespec ts{};
  // CLOCK_MONOTONIC cannot fail with a valid timespec pointer (EINVAL/EFAULT only), so no error path.
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerSecond + static_cast<std::int64_t>(ts.tv_nsec);
}

}  // namespace vifusion
