#include <gtest/gtest.h>

#include <vector>

#include "fixtures.hpp"
#include "memory_recording.hpp"
#include "vifusion/datasets/looped_replay.hpp"

namespace vifusion::datasets {
namespace {

using test::kFramePeriodNs;
using test::MemoryRecording;

TEST(LoopedReplay, EveryPassRepeatsTheFramesLaterSoTimeKeepsIncreasing) {
  int opened = 0;
  const auto reader = loopedReplay(
      [&] {
        ++opened;
        return std::make_unique<MemoryRecording>(10);
      },
      3);
  EXPECT_EQ(opened, 1);
  EXPECT_EQ(reader->frameCount(), 30u);
  const std::int64_t pass_ns = 10 * kFramePeriodNs;  // its span (9 periods) and one period more
  RgbdFrame frame;
  std::int64_t last_t_ns = 0;
  for (std::size_t i = 0; i < 30; ++i) {
    ASSERT_TRUE(reader->nextFrame(frame)) << i;
    const std::size_t pass = i / 10;
    EXPECT_EQ(frame.index, static_cast<std::int64_t>(i));
    EXPECT_EQ(frame.depth(0, 0), 1000 + i % 10) << "frame " << i << " is not its pass's frame " << i % 10;
    EXPECT_EQ(frame.t_ns, MemoryRecording::timeOf(i % 10) + static_cast<std::int64_t>(pass) * pass_ns);
    EXPECT_EQ(reader->listedFrameTimeNs(i), frame.t_ns);
    if (i > 0) {
      EXPECT_GT(frame.t_ns, last_t_ns);
    }
    last_t_ns = frame.t_ns;
  }
  EXPECT_FALSE(reader->nextFrame(frame));
  EXPECT_EQ(opened, 3);  // once a pass
  const std::span<const ImuSample> imu = reader->imu();
  for (std::size_t i = 1; i < imu.size(); ++i) ASSERT_LT(imu[i - 1].t_ns, imu[i].t_ns) << i;
  EXPECT_EQ(imu.back().t_ns, MemoryRecording(10).imu().back().t_ns + 2 * pass_ns);
  EXPECT_NE(reader->describe().find("replayed 3 times"), std::string::npos);
}

TEST(LoopedReplay, ARecordingThatRewindsIsOpenedOnce) {
  int opened = 0;
  const auto reader = loopedReplay(
      [&] {
        ++opened;
        return std::make_unique<MemoryRecording>(5, true, true);
      },
      3);
  RgbdFrame frame;
  for (std::size_t i = 0; i < 15; ++i) {
    ASSERT_TRUE(reader->nextFrame(frame)) << i;
    EXPECT_EQ(frame.index, static_cast<std::int64_t>(i));
    EXPECT_EQ(frame.depth(0, 0), 1000 + i % 5) << "frame " << i << " is not its pass's frame " << i % 5;
    EXPECT_EQ(frame.t_ns, reader->listedFrameTimeNs(i));
  }
  EXPECT_FALSE(reader->nextFrame(frame));
  EXPECT_EQ(opened, 1);  // rewound at each seam: nothing read or allocated again
}

TEST(LoopedReplay, OnePassIsTheRecordingItself) {
  const auto reader = loopedReplay([] { return std::make_unique<MemoryRecording>(4); }, 1);
  EXPECT_EQ(reader->frameCount(), 4u);
  EXPECT_EQ(reader->imu().size(), MemoryRecording(4).imu().size());
}

TEST(LoopedReplay, RefusesWhatItCannotLoop) {
  test::expectError([] { loopedReplay([] { return std::make_unique<MemoryRecording>(4); }, 0); }, "at least 1 pass");
  test::expectError([] { loopedReplay([] { return std::make_unique<MemoryRecording>(4, false); }, 2); },
                    "memory recording: replaying it in a loop needs at least 2 frames with listed times");
  test::expectError([] { loopedReplay([] { return std::make_unique<MemoryRecording>(1); }, 2); }, "at least 2 frames");
}

}  // namespace
}  // namespace vifusion::datasets
