// builtin_interfaces/Time from and to int64 nanoseconds, negative times included.

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "vifusion/core/time.hpp"
#include "vifusion/ros2_msgs/time_header.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::ros2_msgs {
namespace {

TEST(Time, SplitsPositiveNanoseconds) {
  EXPECT_EQ(Time::fromNs(0), (Time{0, 0}));
  EXPECT_EQ(Time::fromNs(1'700'000'000), (Time{1, 700'000'000}));
  EXPECT_EQ(Time::fromNs(1'234'567'890'123), (Time{1'234, 567'890'123}));
}

TEST(Time, NegativeTimesKeepNanosecondsInRange) {
  // ROS's own example: −1.7 s is {sec: −2, nanosec: 3e8}.
  EXPECT_EQ(Time::fromNs(-1'700'000'000), (Time{-2, 300'000'000}));
  EXPECT_EQ(Time::fromNs(-1), (Time{-1, 999'999'999}));
  EXPECT_EQ(Time::fromNs(-kNsPerSecond), (Time{-1, 0}));
}

TEST(Time, RoundTripsThroughNanosecondsAtTheEdgesOfItsRange) {
  const std::int64_t max_ns = std::int64_t{std::numeric_limits<std::int32_t>::max()} * kNsPerSecond + 999'999'999;
  const std::int64_t min_ns = std::int64_t{std::numeric_limits<std::int32_t>::min()} * kNsPerSecond;
  for (std::int64_t t_ns : {std::int64_t{0}, std::int64_t{-1}, std::int64_t{1}, std::int64_t{-1'700'000'000},
                            std::int64_t{86'400} * kNsPerSecond + 5, max_ns, min_ns}) {
    EXPECT_EQ(Time::fromNs(t_ns).toNs(), t_ns) << t_ns;
  }
  EXPECT_EQ(Time::fromNs(max_ns), (Time{std::numeric_limits<std::int32_t>::max(), 999'999'999}));
}

TEST(Time, OutsideInt32SecondsIsAnError) {
  const std::int64_t max_ns = std::int64_t{std::numeric_limits<std::int32_t>::max()} * kNsPerSecond + 999'999'999;
  vifusion::test::expectError([&] { Time::fromNs(max_ns + 1); }, "outside its range");
  vifusion::test::expectError(
      [&] { Time::fromNs(std::int64_t{std::numeric_limits<std::int32_t>::min()} * kNsPerSecond - 1); },
      "builtin_interfaces/msg/Time: -2147483648000000001 ns is outside its range");
}

TEST(Header, MakeHeaderStampsAndNamesTheFrame) {
  const Header header = makeHeader(5 * kNsPerSecond + 25, "imu");
  EXPECT_EQ(header.stamp, (Time{5, 25}));
  EXPECT_EQ(header.frame_id, "imu");
}

}  // namespace
}  // namespace vifusion::ros2_msgs
