#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <initializer_list>
#include <string_view>
#include <vector>

#include "fixtures.hpp"
#include "memory_recording.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/datasets/fault_injection.hpp"

namespace vifusion::datasets {
namespace {

using test::kImuPeriodNs;
using test::MemoryRecording;

/// `action` throws a vifusion::Error whose message holds every one of `parts`.
template <typename Action>
void expectErrorNaming(Action&& action, std::initializer_list<std::string_view> parts) {
  try {
    action();
    ADD_FAILURE() << "no vifusion::Error thrown";
  } catch (const Error& error) {
    const std::string message = error.what();
    for (const std::string_view part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << "\"" << message << "\" lacks \"" << part << "\"";
  }
}

struct Delivered {
  std::int64_t index;
  std::int64_t t_ns;
};

std::vector<Delivered> readAll(DatasetReader& reader) {
  std::vector<Delivered> delivered;
  RgbdFrame frame;
  while (reader.nextFrame(frame)) {
    EXPECT_EQ(frame.depth(0, 0), 1000 + frame.index) << "frame " << frame.index << " shows another frame's image";
    delivered.push_back({frame.index, frame.t_ns});
  }
  return delivered;
}

std::unique_ptr<DatasetReader> faulty(std::size_t frames, const std::string& plan) {
  return withFaults(std::make_unique<MemoryRecording>(frames), parseFaultPlan(plan, "--inject"));
}

TEST(FaultPlan, ReadsEveryFaultWithItsDefaultsAndWritesItBack) {
  const FaultPlan plan = parseFaultPlan(
      "imu-gap@3,imu-duplicate@4,imu-reorder@5,imu-nan@6,imu-inf@7,frame-drop@8:3,frame-duplicate@9,"
      "time-backwards@10:0.25,clock-jump@11:-1,stall@12,device-lost@13,frame-blank@14",
      "--inject");
  ASSERT_EQ(plan.faults.size(), 12u);
  EXPECT_EQ(plan.describe(),
            "imu-gap@3:0.1,imu-duplicate@4,imu-reorder@5,imu-nan@6,imu-inf@7,frame-drop@8:3,frame-duplicate@9,"
            "time-backwards@10:0.25,clock-jump@11:-1,stall@12:2,device-lost@13,frame-blank@14:1");
  EXPECT_EQ(plan.deviceLostFrame(), 13u);
  EXPECT_EQ(parseFaultPlan(plan.describe(), "again").describe(), plan.describe());
  EXPECT_FALSE(parseFaultPlan("stall@1", "--inject").deviceLostFrame());
  EXPECT_TRUE(parseFaultPlan("", "--inject").empty());
}

TEST(FaultPlan, RefusesWhatItCannotReadNamingTheEntry) {
  expectErrorNaming([] { parseFaultPlan("frame-drop@2,gpu-melt@3", "--inject"); },
                    {"--inject", "'gpu-melt@3'", "unknown fault", "imu-gap", "device-lost"});
  expectErrorNaming([] { parseFaultPlan("stall", "--inject"); }, {"'stall'", "NAME@FRAME"});
  expectErrorNaming([] { parseFaultPlan("stall@x", "--inject"); }, {"'x'", "not a frame index"});
  expectErrorNaming([] { parseFaultPlan("stall@-1", "--inject"); }, {"not a frame index"});
  expectErrorNaming([] { parseFaultPlan("frame-duplicate@3:2", "--inject"); }, {"takes no value"});
  expectErrorNaming([] { parseFaultPlan("clock-jump@3", "--inject"); }, {"needs its size", "clock-jump@3:+1"});
  expectErrorNaming([] { parseFaultPlan("clock-jump@3:1", "--inject"); }, {"its sign"});
  expectErrorNaming([] { parseFaultPlan("stall@3:-2", "--inject"); }, {"above 0"});
  expectErrorNaming([] { parseFaultPlan("stall@3:nan", "--inject"); }, {"not a number"});
  expectErrorNaming([] { parseFaultPlan("frame-drop@3:1.5", "--inject"); }, {"whole number"});
  expectErrorNaming([] { parseFaultPlan("frame-blank@3:0", "--inject"); }, {"whole number"});
  expectErrorNaming([] { parseFaultPlan("imu-gap@0", "--inject"); }, {"between frames K-1 and K"});
  expectErrorNaming([] { parseFaultPlan("stall@1,", "--inject"); }, {"ends with a comma"});
  expectErrorNaming([] { parseFaultPlan("stall@1,,stall@2", "--inject"); }, {"empty entry"});
}

TEST(FaultInjection, DroppedFramesNeverArriveAndTheRestKeepTheirIndexAndTime) {
  const auto reader = faulty(10, "frame-drop@2:3");
  EXPECT_EQ(reader->frameCount(), 7u);
  const std::vector<Delivered> delivered = readAll(*reader);
  ASSERT_EQ(delivered.size(), 7u);
  const std::vector<std::int64_t> expected = {0, 1, 5, 6, 7, 8, 9};
  for (std::size_t i = 0; i < delivered.size(); ++i) {
    EXPECT_EQ(delivered[i].index, expected[i]);
    EXPECT_EQ(delivered[i].t_ns, MemoryRecording::timeOf(static_cast<std::size_t>(expected[i])));
    EXPECT_EQ(reader->listedFrameTimeNs(i), delivered[i].t_ns);
  }
}

TEST(FaultInjection, BlankFramesArriveAtTheirTimesWithNoDepthAndBlackColour) {
  const auto reader = faulty(10, "frame-blank@2:3,frame-duplicate@3");
  EXPECT_EQ(reader->frameCount(), 11u);
  RgbdFrame frame;
  std::vector<std::int64_t> indices;
  while (reader->nextFrame(frame)) {
    indices.push_back(frame.index);
    EXPECT_EQ(frame.t_ns, MemoryRecording::timeOf(static_cast<std::size_t>(frame.index)));
    ASSERT_EQ(frame.depth.width(), 4);  // the recorded size, every pixel blank or none
    ASSERT_EQ(frame.rgb.height(), 3);
    const bool blank = frame.index >= 2 && frame.index < 5;
    for (int y = 0; y < frame.depth.height(); ++y) {
      for (int x = 0; x < frame.depth.width(); ++x) {
        EXPECT_EQ(frame.depth(x, y), blank ? 0 : 1000 + frame.index) << "frame " << frame.index;
        EXPECT_EQ(frame.rgb(x, y), blank ? Rgb8{} : MemoryRecording::kColour) << "frame " << frame.index;
      }
    }
  }
  EXPECT_EQ(indices, (std::vector<std::int64_t>{0, 1, 2, 3, 3, 4, 5, 6, 7, 8, 9}));
}

TEST(FaultInjection, ADuplicatedFrameArrivesTwiceAndTheGuardRefusesTheSecond) {
  auto reader = withIncreasingTimes(faulty(6, "frame-duplicate@3"));
  EXPECT_EQ(reader->frameCount(), 7u);
  RgbdFrame frame;
  std::vector<std::int64_t> indices;
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(reader->nextFrame(frame));
    indices.push_back(frame.index);
  }
  ASSERT_TRUE(reader->nextFrame(frame));
  EXPECT_EQ(frame.index, 3);
  expectErrorNaming([&] { reader->nextFrame(frame); }, {"frame 3 at t=5.100000 s", "time does not increase"});
  ASSERT_TRUE(reader->nextFrame(frame));  // moved past the refused one
  EXPECT_EQ(frame.index, 4);
  EXPECT_EQ(frame.depth(0, 0), 1004);
}

TEST(FaultInjection, TimeGoingBackwardsMovesOneFrameAndTheGuardRefusesIt) {
  auto reader = withIncreasingTimes(faulty(6, "time-backwards@2"));
  RgbdFrame frame;
  ASSERT_TRUE(reader->nextFrame(frame));
  ASSERT_TRUE(reader->nextFrame(frame));
  expectErrorNaming([&] { reader->nextFrame(frame); }, {"frame 2", "time does not increase"});
  ASSERT_TRUE(reader->nextFrame(frame));
  EXPECT_EQ(frame.t_ns, MemoryRecording::timeOf(3));
}

TEST(FaultInjection, AClockJumpShiftsEveryLaterFrameAndImuSample) {
  for (const double jump_s : {+1.0, -1.0}) {
    const auto reader = faulty(8, jump_s > 0 ? "clock-jump@4:+1" : "clock-jump@4:-1");
    const std::int64_t jump_ns = secondsToNs(jump_s);
    const std::vector<Delivered> delivered = readAll(*reader);
    ASSERT_EQ(delivered.size(), 8u);
    for (const Delivered& frame : delivered) {
      const std::int64_t recorded = MemoryRecording::timeOf(static_cast<std::size_t>(frame.index));
      EXPECT_EQ(frame.t_ns, recorded + (frame.index >= 4 ? jump_ns : 0)) << "frame " << frame.index;
    }
    const MemoryRecording original(8);
    const std::int64_t moment_ns = (MemoryRecording::timeOf(3) + MemoryRecording::timeOf(4)) / 2;
    ASSERT_EQ(reader->imu().size(), original.imu().size());
    for (std::size_t i = 0; i < original.imu().size(); ++i) {
      const std::int64_t recorded = original.imu()[i].t_ns;
      EXPECT_EQ(reader->imu()[i].t_ns, recorded + (recorded >= moment_ns ? jump_ns : 0));
    }
  }
}

TEST(FaultInjection, AStallHoldsTheFrameBackForItsDuration) {
  const auto reader = faulty(3, "stall@1:0.2");
  RgbdFrame frame;
  ASSERT_TRUE(reader->nextFrame(frame));
  const auto before = std::chrono::steady_clock::now();
  ASSERT_TRUE(reader->nextFrame(frame));
  EXPECT_GE(std::chrono::steady_clock::now() - before, std::chrono::milliseconds(200));
  EXPECT_EQ(frame.index, 1);
}

TEST(FaultInjection, ImuFaultsBreakTheStreamWhereThePlanSays) {
  const MemoryRecording original(10);
  const std::span<const ImuSample> recorded = original.imu();
  const std::int64_t moment_ns = (MemoryRecording::timeOf(4) + MemoryRecording::timeOf(5)) / 2;

  const auto gap = faulty(10, "imu-gap@5:0.05");
  const std::int64_t gap_end_ns = moment_ns + kNsPerSecond / 20;
  EXPECT_EQ(gap->imu().size(), recorded.size() - 10);  // 50 ms at 200 Hz
  for (const ImuSample& sample : gap->imu()) EXPECT_TRUE(sample.t_ns < moment_ns || sample.t_ns >= gap_end_ns);

  const auto count = [](std::span<const ImuSample> stream, auto broken) {
    int found = 0;
    for (std::size_t i = 1; i < stream.size(); ++i) found += broken(stream[i - 1], stream[i]) ? 1 : 0;
    return found;
  };
  const auto duplicate = faulty(10, "imu-duplicate@5");
  EXPECT_EQ(duplicate->imu().size(), recorded.size() + 1);
  EXPECT_EQ(count(duplicate->imu(), [](const ImuSample& a, const ImuSample& b) { return a.t_ns == b.t_ns; }), 1);

  const auto reordered = faulty(10, "imu-reorder@5");
  EXPECT_EQ(reordered->imu().size(), recorded.size());
  EXPECT_EQ(count(reordered->imu(), [](const ImuSample& a, const ImuSample& b) { return a.t_ns > b.t_ns; }), 1);

  for (const char* plan : {"imu-nan@5", "imu-inf@5"}) {
    const auto nonfinite = faulty(10, plan);
    int broken = 0;
    for (const ImuSample& sample : nonfinite->imu()) {
      if (!sample.accel_mps2.allFinite() || !sample.gyro_rad_s.allFinite()) {
        ++broken;
        EXPECT_GE(sample.t_ns, moment_ns) << plan;
        EXPECT_LT(sample.t_ns, moment_ns + kImuPeriodNs) << plan;
      }
    }
    EXPECT_EQ(broken, 1) << plan;
  }
}

TEST(FaultInjection, RefusesFaultsItCannotPlace) {
  expectErrorNaming([] { faulty(10, "stall@10"); }, {"memory recording", "'stall@10:2'", "frame 10", "has 10 frames"});
  expectErrorNaming(
      [] { withFaults(std::make_unique<MemoryRecording>(10, false), parseFaultPlan("imu-gap@3", "--inject")); },
      {"memory recording", "lists no frame times"});
  // Frame faults need no listed times.
  EXPECT_EQ(withFaults(std::make_unique<MemoryRecording>(10, false), parseFaultPlan("frame-drop@3", "--inject"))
                ->frameCount(),
            9u);
}

TEST(FaultInjection, TheGuardPassesAnIncreasingStreamUntouched) {
  const MemoryRecording original(5);
  auto reader = withIncreasingTimes(std::make_unique<MemoryRecording>(5));
  EXPECT_EQ(readAll(*reader).size(), 5u);
  ASSERT_EQ(reader->imu().size(), original.imu().size());
  EXPECT_TRUE(reader->skippedImuRows().empty());
}

TEST(FaultInjection, TheGuardLeavesOutImuSamplesOutOfOrderOrNotFiniteNamingEach) {
  const MemoryRecording original(10);
  const auto guarded = [](const std::string& plan) { return withIncreasingTimes(faulty(10, plan)); };
  // One sample out each: the repeat, the earlier of the swapped pair, the one with NaN or ∞.
  for (const char* plan : {"imu-duplicate@5", "imu-reorder@5", "imu-nan@5", "imu-inf@5"}) {
    const auto reader = guarded(plan);
    const std::span<const ImuSample> kept = reader->imu();
    EXPECT_EQ(kept.size(), original.imu().size() - (std::string(plan) == "imu-duplicate@5" ? 0 : 1)) << plan;
    for (std::size_t i = 1; i < kept.size(); ++i) ASSERT_LT(kept[i - 1].t_ns, kept[i].t_ns) << plan;
    for (const ImuSample& sample : kept) ASSERT_TRUE(sample.gyro_rad_s.allFinite() && sample.accel_mps2.allFinite());
    ASSERT_EQ(reader->skippedImuRows().size(), 1u) << plan;
    const std::string& reason = reader->skippedImuRows().front();
    const bool not_finite = std::string(plan).find("imu-nan") == 0 || std::string(plan).find("imu-inf") == 0;
    EXPECT_NE(reason.find(not_finite ? "not finite" : "time does not increase"), std::string::npos) << reason;
  }
  // The clock going back a second: every sample of that second is out of order.
  const MemoryRecording longer(40);
  const auto jumped = withIncreasingTimes(faulty(40, "clock-jump@5:-1"));
  EXPECT_EQ(jumped->skippedImuRows().size(), 200u);  // 1 s at 200 Hz
  EXPECT_EQ(jumped->imu().size(), longer.imu().size() - 200);
}

}  // namespace
}  // namespace vifusion::datasets
