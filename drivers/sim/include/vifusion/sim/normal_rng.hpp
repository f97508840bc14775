#pragma once
// Standard normal numbers that are the same on every standard library. std::mt19937_64's output sequence
// is fixed by the C++ standard, but std::normal_distribution's algorithm is not (libstdc++, libc++ and MSVC
// produce different numbers from the same engine), so simulated data would differ between platforms.
// The Box–Muller transform here is fixed; only the last bits of log/sin/cos may differ between libms.

#include <cstdint>
#include <random>

namespace vifusion::sim {

class NormalRng {
 public:
  explicit NormalRng(std::uint64_t seed) : engine_(seed) {}

  /// One N(0, 1) number.
  double operator()();

 private:
  /// Uniform in (0, 1]: the top 53 bits of one engine output, never 0 so log() is finite.
  double uniformOpenClosed();

  std::mt19937_64 engine_;
  double spare_ = 0.0;  ///< Box–Muller makes two numbers at a time; the second waits here
  bool has_spare_ = false;
};

}  // namespace vifusion::sim
