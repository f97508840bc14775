#pragma once
// Wall and process CPU time of bench_rgbd_slam's steps. On a shared machine wall time grows with the
// other load, CPU time much less, so A/B comparisons report both.

#include <time.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <string>
#include <vector>

namespace vifusion::bench {

inline double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// CPU time of this process (every thread: ours and lavapipe's workers) [ms].
inline double processCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

/// A wall time and the process CPU time spent meanwhile [ms].
struct Timing {
  double wall_ms = 0.0;
  double cpu_ms = 0.0;
};

/// Accumulates the wall time of each named step ("ms_<step>") and the CPU time the process spent
/// in it, lavapipe's worker threads included ("cpu_ms_<step>"; up to 2× the wall time on 2 cores).
class StepTimes {
 public:
  template <class Fn>
  void time(const std::string& name, Fn&& fn) {
    const double cpu_start = processCpuMs();
    const auto start = std::chrono::steady_clock::now();
    fn();
    totals_[name] += msSince(start);
    totals_["cpu_" + name] += processCpuMs() - cpu_start;
  }
  void add(const std::string& name, double value) { totals_[name] += value; }
  /// `name` and "cpu_<name>" from a Timing.
  void add(const std::string& name, const Timing& timing) {
    totals_[name] += timing.wall_ms;
    totals_["cpu_" + name] += timing.cpu_ms;
  }
  const std::map<std::string, double>& totals() const { return totals_; }

 private:
  std::map<std::string, double> totals_;
};

/// Median wall time and median process CPU time of `repeats` calls of fn [ms].
template <class Fn>
Timing medianMs(int repeats, Fn&& fn) {
  std::vector<double> wall, cpu;
  for (int r = 0; r < repeats; ++r) {
    const double cpu_start = processCpuMs();
    const auto start = std::chrono::steady_clock::now();
    fn();
    wall.push_back(msSince(start));
    cpu.push_back(processCpuMs() - cpu_start);
  }
  const auto median = [](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  return {median(wall), median(cpu)};
}

}  // namespace vifusion::bench
