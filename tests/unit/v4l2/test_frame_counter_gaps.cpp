#include <gtest/gtest.h>

#include "vifusion/v4l2/frame_counter_gaps.hpp"

namespace vifusion::v4l2 {
namespace {

TEST(FrameCounterGaps, CountsSkippedFramesAcrossTheWrap) {
  FrameCounterGaps gaps;
  EXPECT_EQ(gaps.observe(0xFFFFFFFDu).missing, 0);  // first: base only
  EXPECT_EQ(gaps.observe(0xFFFFFFFEu).missing, 0);
  const auto across_wrap = gaps.observe(1u);  // 0xFFFFFFFF and 0 skipped
  EXPECT_EQ(across_wrap.missing, 2);
  EXPECT_EQ(across_wrap.previous, 0xFFFFFFFEu);
  EXPECT_FALSE(across_wrap.went_back);
  EXPECT_EQ(gaps.observe(2u).missing, 0);
  EXPECT_EQ(gaps.observe(7u).missing, 4);
  EXPECT_EQ(gaps.missingFrames(), 6);
  EXPECT_EQ(gaps.regressions(), 0);
}

TEST(FrameCounterGaps, RepeatsAndStepsBackAreRegressionsNotLosses) {
  FrameCounterGaps gaps;
  gaps.observe(100);
  EXPECT_TRUE(gaps.observe(100).went_back);                    // repeat
  EXPECT_TRUE(gaps.observe(40).went_back);                     // device reset
  EXPECT_EQ(gaps.observe(41).missing, 0);                      // counting restarts from the new value
  EXPECT_TRUE(gaps.observe(41u + (1u << 31) + 1u).went_back);  // more than half the range ahead
  EXPECT_EQ(gaps.regressions(), 3);
  EXPECT_EQ(gaps.missingFrames(), 0);
  gaps.reset();
  EXPECT_EQ(gaps.observe(5).missing, 0);  // after reset: base only
  EXPECT_EQ(gaps.regressions(), 3);       // totals survive reset
}

}  // namespace
}  // namespace vifusion::v4l2
