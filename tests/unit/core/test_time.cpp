#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <random>
#include <thread>

#include "vifusion/core/time.hpp"

namespace vifusion {
namespace {

TEST(Time, Constants) {
  EXPECT_EQ(kNsPerSecond, 1'000'000'000);
  EXPECT_EQ(kNsPerMillisecond, 1'000'000);
  EXPECT_EQ(kNsPerMicrosecond, 1'000);
  static_assert(nsToSeconds(kNsPerSecond) == 1.0, "usable at compile time");
}

TEST(Time, NsToSeconds) {
  EXPECT_EQ(nsToSeconds(0), 0.0);
  EXPECT_EQ(nsToSeconds(1'500'000'000), 1.5);
  EXPECT_EQ(nsToSeconds(-2'500'000'000), -2.5);
  EXPECT_EQ(nsToSeconds(5 * kNsPerMillisecond), 0.005);  // correctly rounded: equals the literal
  EXPECT_EQ(nsToSeconds(1), 1e-9);
}

TEST(Time, SecondsToNsRoundsToNearest) {
  EXPECT_EQ(secondsToNs(0.0), 0);
  EXPECT_EQ(secondsToNs(1.5), 1'500'000'000);
  EXPECT_EQ(secondsToNs(0.005), 5'000'000);  // 0.005 is not exact in binary; rounding recovers it
  EXPECT_EQ(secondsToNs(0.1), 100'000'000);
  EXPECT_EQ(secondsToNs(2.4e-9), 2);
  EXPECT_EQ(secondsToNs(2.6e-9), 3);
  EXPECT_EQ(secondsToNs(-2.4e-9), -2);
  EXPECT_EQ(secondsToNs(-2.6e-9), -3);
  EXPECT_EQ(secondsToNs(1.0 / 200.0), 5'000'000);  // 200 Hz IMU period
  EXPECT_EQ(secondsToNs(1.0 / 30.0), 33'333'333);  // 30 Hz frame period
}

TEST(Time, RoundTripUpToElevenDays) {
  std::mt19937_64 engine(7);
  std::uniform_int_distribution<std::int64_t> dist(-1'000'000'000'000'000, 1'000'000'000'000'000);
  for (int i = 0; i < 100'000; ++i) {
    const std::int64_t t_ns = dist(engine);
    ASSERT_EQ(secondsToNs(nsToSeconds(t_ns)), t_ns) << "t_ns = " << t_ns;
  }
  EXPECT_EQ(secondsToNs(nsToSeconds(1'000'000'000'000'000)), 1'000'000'000'000'000);
}

TEST(Time, MonotonicNowIsMonotonicAndTracksSteadyClock) {
  // On Linux std::chrono::steady_clock is CLOCK_MONOTONIC.
  const std::int64_t steady_before_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
  const std::int64_t t0_ns = monotonicNowNs();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const std::int64_t t1_ns = monotonicNowNs();
  const std::int64_t steady_after_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();

  EXPECT_GE(t0_ns, steady_before_ns);
  EXPECT_LE(t1_ns, steady_after_ns);
  EXPECT_GE(t1_ns - t0_ns, 20 * kNsPerMillisecond);
  EXPECT_LT(t1_ns - t0_ns, 2 * kNsPerSecond);  // generous: loaded CI machines
  std::int64_t previous_ns = monotonicNowNs();
  for (int i = 0; i < 10'000; ++i) {
    const std::int64_t now_ns = monotonicNowNs();
    ASSERT_GE(now_ns, previous_ns);
    previous_ns = now_ns;
  }
}

}  // namespace
}  // namespace vifusion

namespace vifusion {
namespace {

TEST(DecimalSecondsToNs, ConvertsPlainDecimalsExactly) {
  EXPECT_EQ(decimalSecondsToNs("1305031098.6659"), 1305031098665900000);
  EXPECT_EQ(decimalSecondsToNs("0.033333"), 33333000);
  EXPECT_EQ(decimalSecondsToNs("12"), 12 * kNsPerSecond);
  EXPECT_EQ(decimalSecondsToNs("1.123456789"), 1123456789);
}

TEST(DecimalSecondsToNs, StopsAtTheFileStampRange) {
  EXPECT_EQ(decimalSecondsToNs("4000000000"), kMaxFileStampNs);
  EXPECT_FALSE(decimalSecondsToNs("4000000000.000000001").has_value());
  // Ten whole digits above 9223372036 s would overflow int64_t nanoseconds.
  EXPECT_FALSE(decimalSecondsToNs("9999999999.999999999").has_value());
  EXPECT_TRUE(isFileStampInRange(-kMaxFileStampNs));
  EXPECT_FALSE(isFileStampInRange(kMaxFileStampNs + 1));
}

TEST(DecimalSecondsToNs, RejectsEverythingElse) {
  for (const char* text : {"", "-1.0", "1e3", "1.0123456789", "12345678901.0", " 1.0", "1.0 ", "1..0", ".5", "nan"}) {
    EXPECT_FALSE(decimalSecondsToNs(text).has_value()) << "'" << text << "'";
  }
}

}  // namespace
}  // namespace vifusion
