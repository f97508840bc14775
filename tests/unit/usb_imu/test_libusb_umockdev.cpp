// MotionModule over the REAL libusb (LibusbLink) against the adapter board emulated by umockdev at the
// usbdevfs level (umockdev_adapter.hpp). Runs under umockdev-wrapper.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <thread>
#include <vector>

#include "umockdev_adapter.hpp"
#include "vifusion/motion/imu_scaling.hpp"
#include "vifusion/motion/power_sequence.hpp"
#include "vifusion/usb_imu/libusb_link.hpp"
#include "vifusion/usb_imu/motion_module.hpp"

namespace vifusion::usb_imu {
namespace {

using test::ScriptOptions;
using test::UmockdevAdapter;

constexpr auto kWaitLimit = std::chrono::seconds(10);
/// Streams here are paced in real time, so the clock fit is asked for after 0.3 s instead of 2 s.
constexpr double kShortMinSpanS = 0.3;

template <class Predicate>
bool waitFor(Predicate predicate) {
  const auto deadline = std::chrono::steady_clock::now() + kWaitLimit;
  while (!predicate()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

MotionModuleOptions fastClockOptions() {
  MotionModuleOptions options;
  options.clock.min_span_s = kShortMinSpanS;
  return options;
}

TEST(LibusbUmockdev, RealLibusbRunsTheCommandsAndStreamsImuFromTheEmulatedAdapter) {
  ScriptOptions script;
  script.duration_s = 1.2;  // real time: the interrupt URBs complete at the script's 4 ms period
  UmockdevAdapter adapter(script);
  const MotionModuleOptions options = fastClockOptions();
  MotionModule module(std::make_unique<LibusbLink>(UmockdevAdapter::kDevnode, options.transfers_in_flight), options);
  ASSERT_TRUE(module.start()) << module.lastError();
  ASSERT_TRUE(waitFor([&] { return adapter.interruptUrbsCompleted() == adapter.device().transferCount(); }));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the last reaped URBs reach the decoder
  const MotionModuleStats stats = module.stats();
  module.stop();

  const std::vector<test::RecordedRequest> requests = adapter.device().requests();
  ASSERT_EQ(requests.size(), motion::kStartImuSequence.size() + motion::kStopImuSequence.size());
  for (std::size_t i = 0; i < motion::kStartImuSequence.size(); ++i) {
    EXPECT_EQ(requests[i].opcode, motion::kStartImuSequence[i].opcode) << i;
    EXPECT_EQ(requests[i].param, motion::kStartImuSequence[i].param) << i;
  }
  EXPECT_EQ(requests.back().opcode, motion::AdapterOpcode::kMotionModulePower);
  EXPECT_EQ(requests.back().param, motion::kSwitchOff);

  EXPECT_EQ(stats.transfers, adapter.device().transferCount());
  EXPECT_EQ(stats.packets_accepted, adapter.device().transferCount());
  EXPECT_EQ(stats.clock_state, clock::ClockMapperState::kValid);
  std::vector<ImuSample> samples;
  ImuSample sample;
  while (module.imuRing().tryPop(sample)) samples.push_back(sample);
  // ≈0.9 s after the fit at 200 Hz; scheduling on a loaded machine may delay some completions.
  EXPECT_GE(samples.size(), 120u);
  const motion::ImuScaler scaler;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (i > 0) {
      EXPECT_GT(samples[i].t_ns, samples[i - 1].t_ns);
    }
    EXPECT_NEAR(samples[i].gyro_rad_s.y(), -200 * scaler.gyroRadSPerCount(), 1e-12);
    EXPECT_NEAR(samples[i].accel_mps2.z(), motion::kStandardGravityMps2, 1e-9);
  }
  std::printf("libusb/umockdev: %zu URBs submitted, %llu transfers, %zu ImuSamples, skew %.1f ppm\n",
              adapter.urbsSubmitted(), static_cast<unsigned long long>(stats.transfers), samples.size(),
              stats.clock_skew_ppm);
}

TEST(LibusbUmockdev, EnodevFromUsbfsMidStreamIsUnpluggedNotAnError) {
  ScriptOptions script;
  script.duration_s = 2.0;
  script.unplug_after = 100;
  UmockdevAdapter adapter(script);
  const MotionModuleOptions options = fastClockOptions();
  MotionModule module(std::make_unique<LibusbLink>(UmockdevAdapter::kDevnode, options.transfers_in_flight), options);
  ASSERT_TRUE(module.start()) << module.lastError();
  ASSERT_TRUE(waitFor([&] { return module.state() == ModuleState::kUnplugged; })) << module.lastError();
  module.stop();
  EXPECT_EQ(module.state(), ModuleState::kUnplugged);
  EXPECT_EQ(module.stats().transfers, 100u);
  EXPECT_EQ(adapter.device().requests().size(), motion::kStartImuSequence.size());
  EXPECT_EQ(module.lastError(), "");
}

}  // namespace
}  // namespace vifusion::usb_imu
