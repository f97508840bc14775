#include "vifusion/core/thread_cpu_time.hpp"

#include <pthread.h>
#include <time.h>

#include "vifusion/core/time.hpp"

namespace vifusion {
namespace {

std::int64_t readClock(clockid_t clock) {
  timespec now{};
  if (clock_gettime(clock, &now) != 0) return 0;
  return static_cast<std::int64_t>(now.tv_sec) * kNsPerSecond + now.tv_nsec;
}

}  // namespace

std::int64_t threadCpuTimeNs(std::thread& thread) {
  clockid_t clock{};
  if (!thread.joinable() || pthread_getcpuclockid(thread.native_handle(), &clock) != 0) return 0;
  return readClock(clock);
}

std::int64_t currentThreadCpuTimeNs() { return readClock(CLOCK_THREAD_CPUTIME_ID); }

}  // namespace vifusion
