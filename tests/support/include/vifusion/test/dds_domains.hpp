#pragma once
// DDS domains of the test suite. ctest runs tests in parallel, and a Cyclone participant discovers
// every participant of its domain on loopback whatever their partitions; discovering one allocates
// its proxies with malloc (≈ 68 KiB, measured: the daemon allocation test failed its malloc bound
// when a parallel test drew the same random domain). So a test that counts malloc bytes gets a
// domain of its own, and every other test draws from the shared range
// (tests/service/service_harness.py keeps the same range for the Python tests).

#include <cstdint>
#include <random>

namespace vifusion::test {

inline constexpr std::uint32_t kSharedDomainFirst = 1;
inline constexpr std::uint32_t kSharedDomainLast = 228;
/// tests/service/test_daemon_allocations.cpp, rgbd and rgbdi (Cyclone's port mapping allows up to 232).
inline constexpr std::uint32_t kDaemonAllocationsRgbdDomain = 229;
inline constexpr std::uint32_t kDaemonAllocationsRgbdiDomain = 230;
/// tests/live/test_live_daemon_allocations.cpp.
inline constexpr std::uint32_t kLiveDaemonAllocationsDomain = 231;

/// A random domain of the shared range.
template <typename Generator>
std::uint32_t randomSharedDomain(Generator& generator) {
  return std::uniform_int_distribution<std::uint32_t>(kSharedDomainFirst, kSharedDomainLast)(generator);
}

}  // namespace vifusion::test
