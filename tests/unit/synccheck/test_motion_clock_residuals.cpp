// The clock mapper's residuals from motion-module transfers as received: packets encoded from the documented
// layout with known device ticks arrive at host = offset + (1 + skew)·device + latency, latency = a fixed part
// plus an exponential one; the residuals are that latency above the fitted lower bound, so their median is the
// exponential's (ln 2 · mean) and none is far below zero.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "vifusion/clock/tick_clock.hpp"
#include "vifusion/motion/packet_encoder.hpp"
#include "vifusion/synccheck/motion_clock_residuals.hpp"

namespace vifusion::synccheck {
namespace {

constexpr std::int64_t kTransferPeriodNs = 10'000'000;  ///< two 200 Hz gyro samples per transfer
constexpr int kTransfers = 3000;                        ///< 30 s
constexpr std::int64_t kHostOffsetNs = 1'000'000'000'000;
constexpr double kSkew = 30e-6;
constexpr double kFixedLatencyNs = 300'000.0;
constexpr double kMeanExtraLatencyNs = 100'000.0;

TEST(MotionClockResiduals, AreTheLatencyAboveTheLowerBound) {
  std::mt19937_64 random(7);
  std::exponential_distribution<double> extra(1.0 / kMeanExtraLatencyNs);
  std::vector<std::array<std::uint8_t, motion::kPacketBytes>> packets(kTransfers);
  std::vector<MotionTransferBytes> transfers;
  std::uint16_t counter = 0;
  for (int k = 0; k < kTransfers; ++k) {
    motion::MotionPacket packet;
    packet.header.cx3_packet_counter = static_cast<std::uint8_t>(k % 16);
    packet.header.imu_entry_count = 2;
    const std::int64_t device_ns = k * kTransferPeriodNs;
    for (int i = 0; i < 2; ++i) {
      motion::ImuEntry& entry = packet.imu[i];
      entry.source = motion::EventSource::kGyroscope;
      entry.sample_counter = counter;
      counter = static_cast<std::uint16_t>((counter + 1) % motion::kCounterModulus);
      const std::int64_t sample_ns = device_ns - (1 - i) * kTransferPeriodNs / 2;
      entry.ticks = static_cast<std::uint32_t>(std::llround(static_cast<double>(sample_ns) * 32e6 / 1e9));
    }
    motion::encodePacket(packet, packets[k]);
    const double host_ns =
        kHostOffsetNs + (1.0 + kSkew) * static_cast<double>(device_ns) + kFixedLatencyNs + extra(random);
    transfers.push_back({static_cast<std::int64_t>(host_ns), packets[k]});
  }
  const std::vector<ClockResidualSample> residuals = motionClockResiduals(transfers);
  ASSERT_GT(residuals.size(), static_cast<std::size_t>(kTransfers) * 8 / 10) << "the fit becomes valid early";
  std::vector<double> values;
  for (const ClockResidualSample& sample : residuals) values.push_back(sample.residual_ns);
  std::sort(values.begin(), values.end());
  const double median = values[values.size() / 2];
  EXPECT_NEAR(median, std::log(2.0) * kMeanExtraLatencyNs, 10'000.0) << "ns";
  EXPECT_GT(values.front(), -5'000.0) << "no transfer maps far after its arrival";
}

}  // namespace
}  // namespace vifusion::synccheck
