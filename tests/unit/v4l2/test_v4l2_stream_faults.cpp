// V4l2Stream when things go wrong: lost frames (three ways), corrupt buffers, unusable timestamps, unplug.
#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <string>
#include <vector>

#include "scripted_zr300.hpp"
#include "vifusion/test/expect_error.hpp"
#include "vifusion/v4l2/device_error.hpp"
#include "vifusion/v4l2/ds_metadata.hpp"
#include "vifusion/v4l2/v4l2_stream.hpp"

namespace vifusion::v4l2::test {
namespace {

using v4l2_scripted::ManualClock;
using v4l2_scripted::ScriptedV4l2Device;

constexpr std::int64_t kExposureNs = 10'000'000;
constexpr std::int64_t kWaitNs = 100'000'000;

V4l2StreamOptions depthOptions() {
  V4l2StreamOptions options;
  options.label = "depth";
  options.node_path = kDepthPath;
  options.fourcc = kFourccZ16;
  options.width_px = kDepthWidthPx;
  options.height_px = kDepthHeightPx;
  options.buffer_count = 4;
  options.timing.exposure_ns = kExposureNs;
  return options;
}

/// A depth script whose frame k can be altered by `alter` after the normal content is written.
v4l2_scripted::ScriptedNodeConfig alteredDepth(
    std::function<void(std::int64_t, ScriptedFrame&, std::uint32_t&)> alter) {
  return depthNodeConfig([alter](const ScriptedFrameRequest& request, ScriptedFrame& frame) {
    std::uint32_t counter = kFirstDinghyCounter + static_cast<std::uint32_t>(request.frame_index);
    frame.t_stamp_ns = scriptedStampNs(request.arrival_ns);
    alter(request.frame_index, frame, counter);
    fillDepth(request.frame_index, counter, request.payload, request.format.bytesperline);
  });
}

class V4l2StreamFaultTest : public ::testing::Test {
 protected:
  /// Calls next() until `frames` frames came; returns every outcome in order (frames released at once).
  std::vector<NextStatus> collect(V4l2Stream& stream, int frames) {
    std::vector<NextStatus> outcomes;
    int got = 0;
    while (got < frames && outcomes.size() < 1000) {
      NextResult result = stream.next(kWaitNs);
      outcomes.push_back(result.status);
      if (result.status == NextStatus::kFrame) {
        ++got;
        sequences.push_back(result.frame.view().sequence);
        ProblemText problem;
        if (const auto dinghy =
                readDinghy(result.frame.view().bytes, result.frame.view().bytes_per_line, kDepthHeightPx, problem)) {
          stream.noteEmbeddedFrameCounter(dinghy->frame_counter);
        }
      } else if (result.status != NextStatus::kTimeout) {
        problems.emplace_back(stream.lastProblem());
        if (result.status == NextStatus::kUnplugged) break;
      }
    }
    return outcomes;
  }

  void expectCleanDevice() {
    EXPECT_EQ(device_.openFdCount(), 0);
    EXPECT_EQ(device_.liveMappingCount(), 0);
    EXPECT_EQ(device_.ruleViolations(), 0) << device_.lastViolation();
  }

  ManualClock clock_;
  ScriptedV4l2Device device_{clock_};
  std::vector<std::uint32_t> sequences;
  std::vector<std::string> problems;
};

TEST_F(V4l2StreamFaultTest, LossesOnUsbAndInTheCameraAreCountedFromSequenceAndEmbeddedCounter) {
  // k = 5 never reaches the host (both counters skip it); from k = 12 the camera's counter jumps by 2 more
  // (frames the camera dropped itself: the V4L2 sequence cannot see those).
  device_.addNode(alteredDepth([](std::int64_t k, ScriptedFrame& frame, std::uint32_t& counter) {
    frame.lost = k == 5;
    if (k >= 12) counter += 2;
  }));
  V4l2Stream stream(device_, depthOptions());
  stream.start();
  collect(stream, 20);
  EXPECT_EQ(sequences[4], 4u);
  EXPECT_EQ(sequences[5], 6u);
  const V4l2StreamStats stats = stream.stats();
  EXPECT_EQ(stats.frames, 20);
  EXPECT_EQ(stats.sequence_gap_frames, 1);
  EXPECT_EQ(stats.embedded_gap_frames, 3);
  EXPECT_EQ(stats.embedded_counter_regressions, 0);
  stream.stop();
  expectCleanDevice();
}

TEST_F(V4l2StreamFaultTest, FramesTheDriverHadNoBufferForShowAsSequenceGaps) {
  device_.addNode(depthNodeConfig());
  V4l2Stream stream(device_, depthOptions());
  stream.start();
  clock_.advanceTo(arrivalNs(9));  // frames 0 … 9 arrive while nobody dequeues: 4 buffers, 6 frames dropped
  collect(stream, 5);
  EXPECT_EQ(sequences, (std::vector<std::uint32_t>{0, 1, 2, 3, 10}));
  EXPECT_EQ(stream.stats().sequence_gap_frames, 6);
  EXPECT_EQ(stream.stats().embedded_gap_frames, 6);
  EXPECT_EQ(device_.nodeStats(kDepthPath).dropped_no_buffer, 6);
}

TEST_F(V4l2StreamFaultTest, ErrorFlaggedAndShortBuffersAreRejectedCountedAndRequeued) {
  const std::uint32_t size_image = 1256u * 469u;
  device_.addNode(alteredDepth([size_image](std::int64_t k, ScriptedFrame& frame, std::uint32_t&) {
    frame.error = k == 3;
    if (k == 6) frame.bytes_used = size_image - 64;
  }));
  V4l2Stream stream(device_, depthOptions());
  stream.start();
  const auto outcomes = collect(stream, 10);
  EXPECT_EQ(outcomes.size(), 12u);
  EXPECT_EQ(outcomes[3], NextStatus::kRejected);
  EXPECT_EQ(outcomes[6], NextStatus::kRejected);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_NE(problems[0].find("depth: buffer 3 (sequence 3) flagged V4L2_BUF_FLAG_ERROR"), std::string::npos)
      << problems[0];
  EXPECT_NE(problems[1].find("sequence 6) bytesused 589000, expected 589064"), std::string::npos) << problems[1];
  const V4l2StreamStats stats = stream.stats();
  EXPECT_EQ(stats.error_flagged_buffers, 1);
  EXPECT_EQ(stats.short_buffers, 1);
  EXPECT_EQ(stats.frames, 10);
  EXPECT_EQ(stats.sequence_gap_frames, 0);  // rejected buffers still count as received
  EXPECT_EQ(device_.ruleViolations(), 0) << device_.lastViolation();
}

TEST_F(V4l2StreamFaultTest, UnusableTimestampsAreRefusedNamingTheReason) {
  device_.addNode(alteredDepth([](std::int64_t k, ScriptedFrame& frame, std::uint32_t&) {
    if (k == 2) frame.timestamp_flags = V4L2_BUF_FLAG_TIMESTAMP_COPY | V4L2_BUF_FLAG_TSTAMP_SRC_SOE;
    if (k == 4) frame.t_stamp_ns = scriptedStampNs(arrivalNs(3)) - 1000;  // before frame 3's stamp
  }));
  V4l2Stream stream(device_, depthOptions());
  stream.start();
  const auto outcomes = collect(stream, 6);
  EXPECT_EQ(outcomes[2], NextStatus::kRejected);
  EXPECT_EQ(outcomes[4], NextStatus::kRejected);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0],
            "depth: buffer 2 (sequence 2): buffer flags 0x00014001: timestamp clock is COPY (copied from an output "
            "buffer), not CLOCK_MONOTONIC");
  EXPECT_NE(problems[1].find("depth: buffer 0 (sequence 4): buffer timestamp"), std::string::npos) << problems[1];
  EXPECT_NE(problems[1].find("back by 1000 ns"), std::string::npos) << problems[1];
  EXPECT_EQ(stream.stats().refused_timestamps, 2);
}

TEST_F(V4l2StreamFaultTest, EndOfFrameStampsMoveBackByReadoutAndHalfTheExposure) {
  device_.addNode(alteredDepth([](std::int64_t, ScriptedFrame& frame, std::uint32_t&) {
    frame.timestamp_flags = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_EOF;
  }));
  auto options = depthOptions();
  options.timing.readout_ns = 7'000'000;
  V4l2Stream stream(device_, options);
  stream.start();
  NextResult first = stream.next(kWaitNs);
  ASSERT_EQ(first.status, NextStatus::kFrame);
  EXPECT_EQ(first.frame.view().t_mid_exposure_ns, scriptedStampNs(arrivalNs(0)) - 7'000'000 - kExposureNs / 2);
  first.frame.release();
  stream.setExposureTiming({4'000'000, 7'000'000});  // auto-exposure shortened it
  NextResult second = stream.next(kWaitNs);
  ASSERT_EQ(second.status, NextStatus::kFrame);
  EXPECT_EQ(second.frame.view().t_mid_exposure_ns, scriptedStampNs(arrivalNs(1)) - 7'000'000 - 2'000'000);
}

TEST_F(V4l2StreamFaultTest, UnplugIsAnOutcomeStopIsCleanAndTheReplugStreamsAgain) {
  device_.addNode(depthNodeConfig());
  device_.scheduleUnplug(arrivalNs(4) + kPeriodNs / 2);
  V4l2Stream stream(device_, depthOptions());
  stream.start();
  const auto outcomes = collect(stream, 4);  // frames 0 … 3
  ASSERT_EQ(outcomes.size(), 4u);
  NextResult held = stream.next(kWaitNs);  // frame 4, kept across the unplug
  ASSERT_EQ(held.status, NextStatus::kFrame);

  NextResult gone = stream.next(kWaitNs);
  EXPECT_EQ(gone.status, NextStatus::kUnplugged);
  EXPECT_EQ(stream.lastProblem(),
            "depth /dev/video1: device gone (VIDIOC_DQBUF: ENODEV); stop() and wait for it to come back");
  EXPECT_TRUE(stream.unplugged());
  EXPECT_EQ(stream.next(kWaitNs).status, NextStatus::kUnplugged);  // stays so, without touching the device
  held.frame.release();                                            // nothing to give back to a dead device
  stream.stop();
  EXPECT_EQ(stream.stats().unplugs, 1);
  EXPECT_EQ(stream.stats().errors, 0);
  expectCleanDevice();

  // Before the camera is back, starting fails on open, naming the node.
  try {
    stream.start();
    FAIL() << "started without a device";
  } catch (const DeviceError& error) {
    EXPECT_EQ(error.errorNumber(), ENOENT);
    EXPECT_NE(std::string(error.what()).find("depth /dev/video1: cannot open: ENOENT"), std::string::npos);
  }
  expectCleanDevice();

  device_.replug();
  stream.start();
  NextResult again = stream.next(kWaitNs);
  ASSERT_EQ(again.status, NextStatus::kFrame) << stream.lastProblem();
  EXPECT_EQ(again.frame.view().sequence, 0u);  // a new device instance counts from 0
  again.frame.release();
  EXPECT_EQ(stream.stats().frames, 6);
  stream.stop();
  expectCleanDevice();
}

TEST_F(V4l2StreamFaultTest, AnUnplugSeenWhenGivingABufferBackAlsoEndsTheStream) {
  device_.addNode(depthNodeConfig());
  V4l2Stream stream(device_, depthOptions());
  stream.start();
  NextResult held = stream.next(kWaitNs);
  ASSERT_EQ(held.status, NextStatus::kFrame);
  device_.unplug();
  held.frame.release();  // QBUF fails with ENODEV
  EXPECT_TRUE(stream.unplugged());
  EXPECT_EQ(stream.next(kWaitNs).status, NextStatus::kUnplugged);
  EXPECT_NE(stream.lastProblem().find("VIDIOC_QBUF: ENODEV"), std::string_view::npos) << stream.lastProblem();
  stream.stop();
  expectCleanDevice();
}

}  // namespace
}  // namespace vifusion::v4l2::test
