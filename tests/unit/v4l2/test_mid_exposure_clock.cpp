#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include "vifusion/v4l2/mid_exposure_clock.hpp"

namespace vifusion::v4l2 {
namespace {

constexpr std::uint32_t kSoe = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_SOE;
constexpr std::uint32_t kEof = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_EOF;
constexpr std::int64_t kT0 = 5'000'000'000'000;  // 5000 s of uptime

TEST(MidExposureClock, StartOfExposurePlusHalfTheExposure) {
  MidExposureClock clock;
  ProblemText problem;
  EXPECT_EQ(clock.midExposureNs(kSoe, kT0, {10'000'000, 0}, problem), kT0 + 5'000'000);
  EXPECT_EQ(clock.midExposureNs(kSoe, kT0 + 33'333'000, {3'000'001, 0}, problem), kT0 + 33'333'000 + 1'500'000);
  EXPECT_EQ(clock.refusals(), 0);
}

TEST(MidExposureClock, EndOfFrameMinusReadoutAndHalfTheExposure) {
  MidExposureClock clock;
  ProblemText problem;
  EXPECT_EQ(clock.midExposureNs(kEof, kT0, {10'000'000, 8'000'000}, problem), kT0 - 13'000'000);
  // SOE and EOF differ only in the flag: the same stamp gives times 18 ms apart here.
  EXPECT_EQ(clock.midExposureNs(kSoe, kT0 + 1, {10'000'000, 8'000'000}, problem), kT0 + 1 + 5'000'000);
}

TEST(MidExposureClock, RefusesOtherClocksZeroAndBackwardsStampsNamingTheField) {
  MidExposureClock clock;
  ProblemText problem;
  const ExposureTiming timing{1'000'000, 0};
  EXPECT_FALSE(clock.midExposureNs(V4L2_BUF_FLAG_TIMESTAMP_COPY | V4L2_BUF_FLAG_TSTAMP_SRC_SOE, kT0, timing, problem));
  EXPECT_EQ(problem.view(),
            "buffer flags 0x00014000: timestamp clock is COPY (copied from an output buffer), not "
            "CLOCK_MONOTONIC");
  EXPECT_FALSE(clock.midExposureNs(V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN, kT0, timing, problem));
  EXPECT_NE(problem.view().find("UNKNOWN"), std::string_view::npos);
  EXPECT_FALSE(clock.midExposureNs(kSoe, 0, timing, problem));
  EXPECT_NE(problem.view().find("did not stamp"), std::string_view::npos);

  ASSERT_TRUE(clock.midExposureNs(kSoe, kT0, timing, problem));
  EXPECT_FALSE(clock.midExposureNs(kSoe, kT0 - 2000, timing, problem));
  EXPECT_EQ(problem.view(),
            "buffer timestamp 4999999998000 ns is not after the previous one (5000000000000 ns): "
            "back by 2000 ns");
  EXPECT_FALSE(clock.midExposureNs(kSoe, kT0, timing, problem));                            // a repeat
  EXPECT_EQ(clock.midExposureNs(kSoe, kT0 + 1000, timing, problem), kT0 + 1000 + 500'000);  // recovers
  EXPECT_EQ(clock.refusals(), 5);
}

TEST(MidExposureClock, RefusesMidExposureGoingBackAndNegativeTimes) {
  MidExposureClock clock;
  ProblemText problem;
  ASSERT_EQ(clock.midExposureNs(kEof, kT0, {0, 0}, problem), kT0);
  // 1 ms later, but the exposure grew to 4 ms: mid-exposure would be 1 ms before the previous frame's.
  EXPECT_FALSE(clock.midExposureNs(kEof, kT0 + 1'000'000, {4'000'000, 0}, problem));
  EXPECT_EQ(problem.view(),
            "mid-exposure time is not after the previous frame's: back by 1000000 ns (exposure "
            "4000000 ns)");
  EXPECT_FALSE(clock.midExposureNs(kSoe, kT0 + 2'000'000, {-1, 0}, problem));
  EXPECT_NE(problem.view().find("exposure -1 ns"), std::string_view::npos);
  EXPECT_EQ(clock.refusals(), 2);
  clock.reset();
  EXPECT_EQ(clock.midExposureNs(kSoe, 1, {0, 0}, problem), 1);  // after reset any positive stamp is accepted
}

}  // namespace
}  // namespace vifusion::v4l2
