#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "scripted_motion_device.hpp"
#include "vifusion/clock/tick_clock.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/motion/imu_scaling.hpp"
#include "vifusion/motion/power_sequence.hpp"
#include "vifusion/usb_imu/motion_module.hpp"

namespace vifusion::usb_imu {
namespace {

using test::ScriptedMotionDevice;
using test::ScriptOptions;

constexpr auto kWaitLimit = std::chrono::seconds(10);
constexpr std::int64_t kGyroPeriodNs = 5'000'000;
constexpr std::int64_t kFramePeriodNs = 33'333'333;
/// The mapped times may differ from the minimum-latency truth by the hull's error: µs, not the 100–500 µs
/// of one transfer's latency.
constexpr std::int64_t kTimeToleranceNs = 20'000;
/// 5 s of ticks before the 32-bit wrap, so a 10 s stream crosses it.
constexpr std::uint32_t kTicksBeforeWrap = 5u * 32'000'000u;
constexpr std::uint32_t kFirstTickNearWrap = 0u - kTicksBeforeWrap;

struct Rig {
  ScriptedMotionDevice* device = nullptr;  // owned by module
  std::unique_ptr<MotionModule> module;
};

Rig makeRig(const ScriptOptions& script, const MotionModuleOptions& options = {}) {
  auto device = std::make_unique<ScriptedMotionDevice>(script);
  Rig rig;
  rig.device = device.get();
  rig.module = std::make_unique<MotionModule>(std::move(device), options);
  return rig;
}

template <class Predicate>
bool waitFor(Predicate predicate) {
  const auto deadline = std::chrono::steady_clock::now() + kWaitLimit;
  while (!predicate()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

std::vector<ImuSample> drainImu(MotionModule& module) {
  std::vector<ImuSample> out;
  ImuSample sample;
  while (module.imuRing().tryPop(sample)) out.push_back(sample);
  return out;
}

std::vector<DepthFrameEvent> drainFrames(MotionModule& module) {
  std::vector<DepthFrameEvent> out;
  DepthFrameEvent event;
  while (module.frameEventRing().tryPop(event)) out.push_back(event);
  return out;
}

TEST(MotionModule, StartAndStopSendTheDocumentedCommandsInOrder) {
  ScriptOptions script;
  script.duration_s = 0.5;
  Rig rig = makeRig(script);
  ASSERT_TRUE(rig.module->start());
  EXPECT_EQ(rig.module->state(), ModuleState::kStreaming);
  EXPECT_EQ(rig.device->claimedInterface(), 2);
  EXPECT_EQ(rig.device->interruptEndpoint(), 0x84);
  rig.module->stop();
  EXPECT_EQ(rig.module->state(), ModuleState::kClosed);
  EXPECT_TRUE(rig.device->closed());

  const std::vector<test::RecordedRequest> requests = rig.device->requests();
  using motion::AdapterOpcode;
  const std::vector<std::pair<AdapterOpcode, std::uint32_t>> expected = {
      {AdapterOpcode::kMotionModuleActivate, 0}, {AdapterOpcode::kMotionModulePower, 0},
      {AdapterOpcode::kMotionModulePower, 1},    {AdapterOpcode::kMotionModuleActivate, 1},
      {AdapterOpcode::kMotionModuleActivate, 0}, {AdapterOpcode::kMotionModulePower, 0}};
  ASSERT_EQ(requests.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(requests[i].endpoint, 0x01) << i;
    EXPECT_EQ(requests[i].opcode, expected[i].first) << i;
    EXPECT_EQ(requests[i].param, expected[i].second) << i;
  }
  // MMPWR = 1, byte for byte: length 20 (bytes after length and magic), magic 0xCDAB, opcode 0x0A, params 1,0,0,0.
  const std::vector<std::uint8_t> power_on = {0x14, 0x00, 0xAB, 0xCD, 0x0A, 0, 0, 0, 1, 0, 0, 0,
                                              0,    0,    0,    0,    0,    0, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(requests[2].bytes, power_on);
}

TEST(MotionModule, StreamsScaledImuAndFrameEventsOnMappedHostTimeAcrossTheTickWrap) {
  ScriptOptions script;
  script.duration_s = 10.0;
  script.first_tick = kFirstTickNearWrap;
  Rig rig = makeRig(script);
  ASSERT_TRUE(rig.module->start());
  ASSERT_TRUE(waitFor([&] { return rig.device->finished(); }));
  const MotionModuleStats stats = rig.module->stats();
  rig.module->stop();

  EXPECT_EQ(stats.transfers, rig.device->transferCount());
  EXPECT_EQ(stats.transfers, 2500u);
  EXPECT_EQ(stats.packets_accepted, 2500u);
  for (std::uint64_t drops : stats.parse_drops) EXPECT_EQ(drops, 0u);
  EXPECT_EQ(stats.tick_backward, 0u);
  EXPECT_EQ(stats.imu_overruns, 0u);
  EXPECT_EQ(stats.clock_state, clock::ClockMapperState::kValid);
  EXPECT_NEAR(stats.clock_skew_ppm, 50.0, 1.0);

  const motion::ImuScaler scaler;
  const std::vector<ImuSample> samples = drainImu(*rig.module);
  // The clock fit needs min_span_s = 2 s, so ≈ 8 of 10 s come through: 1600 gyro samples, less the merge
  // edges.
  ASSERT_GE(samples.size(), 1590u);
  EXPECT_LE(samples.size(), 1602u);
  EXPECT_EQ(stats.imu_samples, samples.size());
  std::int64_t previous_t_ns = 0;
  std::int64_t worst_error_ns = 0;
  for (const ImuSample& sample : samples) {
    EXPECT_GT(sample.t_ns, previous_t_ns);
    previous_t_ns = sample.t_ns;
    const double counter = sample.gyro_rad_s.x() / scaler.gyroRadSPerCount();
    ASSERT_NEAR(counter, std::round(counter), 1e-6);
    EXPECT_NEAR(sample.gyro_rad_s.y(), -200 * 1000.0 * std::numbers::pi / 180.0 / 32767.0, 1e-12);
    EXPECT_NEAR(sample.gyro_rad_s.z(), 3000 * 1000.0 * std::numbers::pi / 180.0 / 32767.0, 1e-12);
    EXPECT_NEAR(sample.accel_mps2.x(), 0.0, 1e-12);
    EXPECT_NEAR(sample.accel_mps2.z(), motion::kStandardGravityMps2, 1e-9);
    const auto true_t_ns = rig.device->trueHostNs(static_cast<std::int64_t>(std::round(counter)) * kGyroPeriodNs);
    worst_error_ns = std::max(worst_error_ns, std::abs(sample.t_ns - true_t_ns));
  }
  EXPECT_LE(worst_error_ns, kTimeToleranceNs);
  std::printf("IMU: %zu samples, worst |t - truth| = %lld ns, skew %.3f ppm\n", samples.size(),
              static_cast<long long>(worst_error_ns), stats.clock_skew_ppm);

  const std::vector<DepthFrameEvent> frames = drainFrames(*rig.module);
  ASSERT_GE(frames.size(), 235u);  // 30 Hz over the ≈8 s after the clock fit
  EXPECT_EQ(stats.frame_events, frames.size());
  std::int64_t worst_frame_error_ns = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (i > 0) {
      EXPECT_EQ(frames[i].frame_counter, (frames[i - 1].frame_counter + 1) % motion::kCounterModulus);
      EXPECT_GT(frames[i].t_ns, frames[i - 1].t_ns);
    }
    const std::int64_t true_t_ns = rig.device->trueHostNs(frames[i].frame_counter * kFramePeriodNs);
    worst_frame_error_ns = std::max(worst_frame_error_ns, std::abs(frames[i].t_ns - true_t_ns));
  }
  EXPECT_LE(worst_frame_error_ns, kTimeToleranceNs);
}

// For recordings the module also keeps every transfer as it came off the bus (bytes, arrival time, index), so
// the device's own ticks and counters of every IMU sample survive; off by default.
TEST(MotionModule, KeepsEveryRawTransferForARecorderWhenAsked) {
  ScriptOptions script;
  script.duration_s = 2.0;
  MotionModuleOptions options;
  options.raw_transfer_ring_capacity = 1024;
  Rig rig = makeRig(script, options);
  ASSERT_TRUE(rig.module->start());
  ASSERT_TRUE(waitFor([&] { return rig.device->finished(); }));
  rig.module->stop();
  const std::uint64_t transfers = rig.device->transferCount();
  ASSERT_GT(transfers, 0u);
  RawTransfer raw;
  std::uint64_t kept = 0;
  std::int64_t previous_ns = 0;
  while (rig.module->rawTransferRing().tryPop(raw)) {
    EXPECT_EQ(raw.index, kept) << "no transfer skipped";
    EXPECT_EQ(raw.size, motion::kPacketBytes);
    EXPECT_GT(raw.host_receive_ns, previous_ns);
    previous_ns = raw.host_receive_ns;
    ++kept;
  }
  EXPECT_EQ(kept, transfers);
  EXPECT_EQ(rig.module->rawTransferRing().overruns(), 0u);

  Rig without = makeRig(script);
  ASSERT_TRUE(without.module->start());
  ASSERT_TRUE(waitFor([&] { return without.device->finished(); }));
  without.module->stop();
  EXPECT_FALSE(without.module->rawTransferRing().tryPop(raw)) << "nothing kept by default";
}

TEST(MotionModule, CorruptTransfersAreCountedAndTheStreamGoesOn) {
  ScriptOptions script;
  script.duration_s = 6.0;
  script.corrupt_at = {1000, 1001, 1002};
  Rig rig = makeRig(script);
  ASSERT_TRUE(rig.module->start());
  ASSERT_TRUE(waitFor([&] { return rig.device->finished(); }));
  const MotionModuleStats stats = rig.module->stats();
  EXPECT_EQ(stats.state, ModuleState::kStreaming);
  rig.module->stop();

  using motion::PacketDropReason;
  EXPECT_EQ(stats.parseDrops(PacketDropReason::kDeviceError), 1u);
  EXPECT_EQ(stats.parseDrops(PacketDropReason::kShortTransfer), 1u);
  EXPECT_EQ(stats.parseDrops(PacketDropReason::kImuCountTooLarge), 1u);
  EXPECT_EQ(stats.packets_accepted, 1500u - 3u);
  const std::vector<ImuSample> samples = drainImu(*rig.module);
  // 4 s after the clock fit at 200 Hz, less the ≈3 gyro samples the corrupt transfers replaced.
  EXPECT_GE(samples.size(), 790u);
  for (std::size_t i = 1; i < samples.size(); ++i) ASSERT_GT(samples[i].t_ns, samples[i - 1].t_ns);
}

TEST(MotionModule, UnplugMidStreamLeavesUnpluggedStateAndStopsCleanly) {
  ScriptOptions script;
  script.duration_s = 10.0;
  script.unplug_after = 700;
  Rig rig = makeRig(script);
  ASSERT_TRUE(rig.module->start());
  ASSERT_TRUE(waitFor([&] { return rig.module->state() == ModuleState::kUnplugged; }));
  EXPECT_EQ(rig.device->transfersDelivered(), 700u);
  rig.module->stop();
  EXPECT_EQ(rig.module->state(), ModuleState::kUnplugged);
  EXPECT_TRUE(rig.device->closed());
  EXPECT_EQ(rig.device->requests().size(), motion::kStartImuSequence.size());  // no power-down to a gone device
  EXPECT_EQ(rig.module->lastError(), "");
  EXPECT_EQ(rig.module->stats().transfers, 700u);
  // Until hotplug brings it back, start() reports the absence instead of throwing.
  EXPECT_FALSE(rig.module->start());
  EXPECT_EQ(rig.module->state(), ModuleState::kUnplugged);
}

TEST(MotionModule, AWrongReplyFailsStartNamingTheCommand) {
  ScriptOptions script;
  script.duration_s = 0.5;
  script.wrong_reply_opcode = true;
  Rig rig = makeRig(script);
  try {
    rig.module->start();
    FAIL() << "start() accepted a reply echoing the wrong opcode";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("reply to MM_ACTIVATE=0"), std::string::npos) << error.what();
  }
  EXPECT_EQ(rig.module->state(), ModuleState::kClosed);
  EXPECT_TRUE(rig.device->closed());
}

TEST(MotionModule, SteadyStateTransfersAllocateNothing) {
  ScriptOptions script;
  script.duration_s = 6.0;
  Rig rig = makeRig(script);
  ASSERT_TRUE(rig.module->start());
  ASSERT_TRUE(waitFor([&] { return rig.device->finished(); }));
  rig.module->stop();
  ASSERT_GT(rig.device->allocationsAtProbe(), 0u);
  // Transfers 500…1499 decoded, mapped, merged and pushed without one heap allocation.
  EXPECT_EQ(rig.device->allocationsAtEnd(), rig.device->allocationsAtProbe());
  EXPECT_GT(rig.module->stats().imu_samples, 700u);
}

TEST(MotionModule, DestructorStopsAStreamingModule) {
  ScriptOptions script;
  script.duration_s = 10.0;
  script.transfers_per_pump = 1;
  Rig rig = makeRig(script);
  ASSERT_TRUE(rig.module->start());
  const auto started = std::chrono::steady_clock::now();
  rig.module.reset();
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(1));
}

}  // namespace
}  // namespace vifusion::usb_imu
