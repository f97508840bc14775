// V4l2Stream against the scripted device: the call sequence, bytes and timestamps exactly as scripted,
// refusals with their messages, buffer ownership, and no allocation while streaming.
#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "scripted_zr300.hpp"
#include "vifusion/test/counting_allocations.hpp"
#include "vifusion/test/expect_error.hpp"
#include "vifusion/v4l2/ds_metadata.hpp"
#include "vifusion/v4l2/v4l2_stream.hpp"
#include "vifusion/v4l2/yuyv.hpp"
#include "vifusion/v4l2/z16.hpp"

namespace vifusion::v4l2::test {
namespace {

using v4l2_scripted::ManualClock;
using v4l2_scripted::ScriptedV4l2Device;
using vifusion::test::expectError;

constexpr std::int64_t kExposureNs = 10'000'000;
constexpr std::int64_t kWaitNs = 100'000'000;

V4l2StreamOptions depthOptions() {
  V4l2StreamOptions options;
  options.label = "depth";
  options.node_path = kDepthPath;
  options.fourcc = kFourccZ16;
  options.width_px = kDepthWidthPx;
  options.height_px = kDepthHeightPx;
  options.fps = 30;
  options.buffer_count = 4;
  options.timing.exposure_ns = kExposureNs;
  return options;
}

V4l2StreamOptions colourOptions() {
  V4l2StreamOptions options;
  options.label = "colour";
  options.node_path = kColourPath;
  options.fourcc = kFourccYuyv;
  options.width_px = kColourWidthPx;
  options.height_px = kColourHeightPx;
  options.fps = 30;
  options.buffer_count = 4;
  options.timing.exposure_ns = kExposureNs;
  return options;
}

/// Forwards to another DeviceIo and writes down which calls were made, in order.
class RecordingIo final : public DeviceIo {
 public:
  explicit RecordingIo(DeviceIo& inner) : inner_(inner) {}
  std::vector<std::string> calls;

  int open(const char* path, int flags) override {
    calls.emplace_back("open");
    return inner_.open(path, flags);
  }
  int close(int fd) override {
    calls.emplace_back("close");
    return inner_.close(fd);
  }
  int ioctl(int fd, unsigned long request, void* argument) override {
    calls.emplace_back(requestName(request, argument));
    return inner_.ioctl(fd, request, argument);
  }
  void* mmap(void* address, std::size_t length, int protection, int flags, int fd, off_t offset) override {
    calls.emplace_back("mmap");
    return inner_.mmap(address, length, protection, flags, fd, offset);
  }
  int munmap(void* address, std::size_t length) override {
    calls.emplace_back("munmap");
    return inner_.munmap(address, length);
  }
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override {
    calls.emplace_back("poll");
    return inner_.poll(fds, count, timeout_ms);
  }

 private:
  static std::string requestName(unsigned long request, void* argument) {
    switch (request) {
      case VIDIOC_QUERYCAP:
        return "QUERYCAP";
      case VIDIOC_S_FMT:
        return "S_FMT";
      case VIDIOC_S_PARM:
        return "S_PARM";
      case VIDIOC_REQBUFS:
        return "REQBUFS(" + std::to_string(static_cast<v4l2_requestbuffers*>(argument)->count) + ")";
      case VIDIOC_QUERYBUF:
        return "QUERYBUF(" + std::to_string(static_cast<v4l2_buffer*>(argument)->index) + ")";
      case VIDIOC_QBUF:
        return "QBUF(" + std::to_string(static_cast<v4l2_buffer*>(argument)->index) + ")";
      case VIDIOC_DQBUF:
        return "DQBUF";
      case VIDIOC_STREAMON:
        return "STREAMON";
      case VIDIOC_STREAMOFF:
        return "STREAMOFF";
      default:
        return "ioctl?";
    }
  }
  DeviceIo& inner_;
};

class V4l2StreamTest : public ::testing::Test {
 protected:
  void expectCleanDevice() {
    EXPECT_EQ(device_.openFdCount(), 0);
    EXPECT_EQ(device_.liveMappingCount(), 0);
    EXPECT_EQ(device_.ruleViolations(), 0) << device_.lastViolation();
  }

  ManualClock clock_;
  ScriptedV4l2Device device_{clock_};
};

TEST_F(V4l2StreamTest, StartStreamStopMakesTheV4l2CallsInOrderAndDeliversTheScriptExactly) {
  device_.addNode(depthNodeConfig());
  RecordingIo io(device_);
  {
    V4l2Stream stream(io, depthOptions());
    stream.start();
    const std::vector<std::string> start_calls = {"open",        "QUERYCAP",    "S_FMT",       "S_PARM",  "REQBUFS(4)",
                                                  "QUERYBUF(0)", "mmap",        "QUERYBUF(1)", "mmap",    "QUERYBUF(2)",
                                                  "mmap",        "QUERYBUF(3)", "mmap",        "QBUF(0)", "QBUF(1)",
                                                  "QBUF(2)",     "QBUF(3)",     "STREAMON"};
    EXPECT_EQ(io.calls, start_calls);
    EXPECT_EQ(stream.format().fourcc, kFourccZ16);
    EXPECT_EQ(stream.format().bytes_per_line, 1256u);
    EXPECT_EQ(stream.format().size_image, 1256u * 469u);
    EXPECT_EQ(stream.format().buffer_count, 4);
    EXPECT_TRUE(stream.streaming());

    std::vector<std::uint8_t> expected(1256u * 469u);
    Image<std::uint16_t> depth(kDepthWidthPx, kDepthHeightPx - 1);
    constexpr int kFrames = 30;
    for (int i = 0; i < kFrames; ++i) {
      io.calls.clear();
      NextResult result = stream.next(kWaitNs);
      ASSERT_EQ(result.status, NextStatus::kFrame) << nextStatusName(result.status) << ": " << stream.lastProblem();
      // Each frame is waited for: nothing ready → poll to its arrival → dequeue.
      EXPECT_EQ(io.calls, (std::vector<std::string>{"DQBUF", "poll", "DQBUF"}));
      const FrameView& view = result.frame.view();
      const std::int64_t k = i;  // started before frame 0 arrived
      EXPECT_EQ(view.sequence, static_cast<std::uint32_t>(i));
      EXPECT_EQ(view.t_stamp_ns, scriptedStampNs(arrivalNs(k)));
      EXPECT_EQ(view.t_mid_exposure_ns, scriptedStampNs(arrivalNs(k)) + kExposureNs / 2);
      EXPECT_EQ(view.bytes_per_line, 1256u);
      ASSERT_EQ(view.bytes.size(), expected.size());
      std::fill(expected.begin(), expected.end(), 0);
      fillDepth(k, kFirstDinghyCounter + static_cast<std::uint32_t>(k), expected, 1256);
      EXPECT_EQ(std::memcmp(view.bytes.data(), expected.data(), expected.size()), 0) << "frame " << k;

      ProblemText problem;
      const auto dinghy = readDinghy(view.bytes, view.bytes_per_line, kDepthHeightPx, problem);
      ASSERT_TRUE(dinghy.has_value());
      EXPECT_TRUE(checkDinghy(*dinghy, DinghyNode::kDepth, problem)) << problem.view();
      EXPECT_EQ(dinghy->frame_counter, kFirstDinghyCounter + static_cast<std::uint32_t>(k));
      ASSERT_TRUE(z16ToDepth(view.bytes, view.bytes_per_line, depth.view(), problem)) << problem.view();
      EXPECT_EQ(depth(0, 0), depthValue(k, 0, 0));
      EXPECT_EQ(depth(627, 467), depthValue(k, 627, 467));
      EXPECT_EQ(depth(300, 200), depthValue(k, 300, 200));

      io.calls.clear();
      result.frame.release();
      EXPECT_EQ(io.calls, (std::vector<std::string>{"QBUF(" + std::to_string(view.buffer_index) + ")"}));
    }
    const V4l2StreamStats stats = stream.stats();
    EXPECT_EQ(stats.frames, kFrames);
    EXPECT_EQ(stats.sequence_gap_frames, 0);
    EXPECT_EQ(stats.error_flagged_buffers + stats.short_buffers + stats.refused_timestamps + stats.errors, 0);

    io.calls.clear();
    stream.stop();
    EXPECT_EQ(io.calls,
              (std::vector<std::string>{"STREAMOFF", "munmap", "munmap", "munmap", "munmap", "REQBUFS(0)", "close"}));
    EXPECT_FALSE(stream.streaming());
    io.calls.clear();
  }
  EXPECT_TRUE(io.calls.empty());  // the destructor after stop() has nothing left to do
  expectCleanDevice();
}

TEST_F(V4l2StreamTest, ColourFramesCarryTheirFrameNumberAndConvertToRgb) {
  device_.addNode(colourNodeConfig());
  V4l2Stream stream(device_, colourOptions());
  clock_.advanceTo(arrivalNs(6) + 1);  // start late: the first frame served is k = 7, with sequence 0
  stream.start();
  Image<Rgb8> rgb(kColourWidthPx, kColourHeightPx);
  for (int i = 0; i < 5; ++i) {
    NextResult result = stream.next(kWaitNs);
    ASSERT_EQ(result.status, NextStatus::kFrame) << stream.lastProblem();
    const FrameView& view = result.frame.view();
    const std::int64_t k = 7 + i;
    EXPECT_EQ(view.sequence, static_cast<std::uint32_t>(i));
    EXPECT_EQ(view.t_stamp_ns, scriptedStampNs(arrivalNs(k)));
    ProblemText problem;
    EXPECT_EQ(readColourFrameNumber(view.bytes, view.bytes_per_line, kColourWidthPx, kColourHeightPx, problem),
              static_cast<std::uint32_t>(k));
    ASSERT_TRUE(yuyvToRgb(view.bytes, view.bytes_per_line, rgb.view(), problem)) << problem.view();
    // Pixel pair 0 of row 0: bytes Y0 Cb Y1 Cr = colourByte(k, 0 … 3).
    EXPECT_EQ(rgb(0, 0), bt601LimitedToRgb(colourByte(k, 0), colourByte(k, 1), colourByte(k, 3)));
    EXPECT_EQ(rgb(1, 0), bt601LimitedToRgb(colourByte(k, 2), colourByte(k, 1), colourByte(k, 3)));
  }
  stream.stop();
  expectCleanDevice();
}

TEST_F(V4l2StreamTest, AFormatTheDriverChangesIsRefusedNamingRequestAndGrant) {
  device_.addNode(colourNodeConfig());
  V4l2StreamOptions z16_on_colour = depthOptions();
  z16_on_colour.node_path = kColourPath;
  V4l2Stream unpatched(device_, z16_on_colour);
  expectError([&] { unpatched.start(); },
              "depth /dev/video2: requested 'Z16 ' 628x469, driver granted 'YUYV' 640x480 (uvcvideo lacks the "
              "RealSense pixel-format patch for 'Z16 ')");
  EXPECT_EQ(unpatched.fd(), -1);

  V4l2StreamOptions odd_size = colourOptions();
  odd_size.width_px = 800;
  odd_size.height_px = 600;
  V4l2Stream resized(device_, odd_size);
  expectError([&] { resized.start(); }, "colour /dev/video2: requested 'YUYV' 800x600, driver granted 'YUYV' 640x480");

  V4l2StreamOptions odd_rate = colourOptions();
  odd_rate.fps = 45;
  V4l2Stream retimed(device_, odd_rate);
  expectError([&] { retimed.start(); }, "colour /dev/video2: requested 1/45 s per frame, driver granted 1/30 s");
  expectCleanDevice();
}

TEST_F(V4l2StreamTest, ANodeWithoutCaptureOrStreamingIsRefusedNamingTheCapability) {
  auto metadata = depthNodeConfig();
  metadata.device_caps = V4L2_CAP_META_CAPTURE | V4L2_CAP_STREAMING;
  device_.addNode(metadata);
  V4l2Stream stream(device_, depthOptions());
  expectError([&] { stream.start(); },
              "depth /dev/video1 (driver 'uvcvideo', card 'RealSense ZR300 (scripted)'): missing capability "
              "VIDEO_CAPTURE (this is a metadata node, not the image node)");
  auto read_only = colourNodeConfig();
  read_only.device_caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_READWRITE;
  device_.addNode(read_only);
  V4l2Stream colour(device_, colourOptions());
  expectError([&] { colour.start(); }, "missing capability STREAMING");
  expectCleanDevice();
}

TEST_F(V4l2StreamTest, TooFewBuffersGrantedIsRefusedAndCleanedUp) {
  auto stingy = depthNodeConfig();
  stingy.max_buffers = 1;
  device_.addNode(stingy);
  V4l2Stream stream(device_, depthOptions());
  expectError([&] { stream.start(); },
              "depth /dev/video1: driver granted 1 MMAP buffers for 4 requested; need [2, 32]");
  expectCleanDevice();
}

TEST_F(V4l2StreamTest, BorrowedFramesAreGivenBackExactlyOnceWhateverTheCallerDoes) {
  device_.addNode(depthNodeConfig());
  V4l2Stream stream(device_, depthOptions());
  stream.start();
  std::mt19937 random(3);
  std::vector<BorrowedFrame> held;
  std::uint32_t next_sequence = 0;
  int delivered = 0;
  for (int step = 0; step < 400; ++step) {
    const unsigned action = random() % 6;
    if (held.size() < 3 && action < 3) {
      NextResult result = stream.next(kWaitNs);
      ASSERT_EQ(result.status, NextStatus::kFrame) << stream.lastProblem();
      EXPECT_EQ(result.frame.view().sequence, next_sequence++);
      held.push_back(std::move(result.frame));
      EXPECT_FALSE(result.frame);  // moved from: empty, its destructor gives nothing back
      ++delivered;
    } else if (!held.empty()) {
      const std::size_t pick = random() % held.size();
      switch (action) {
        case 3:  // explicit release, twice
          held[pick].release();
          held[pick].release();
          break;
        case 4: {  // move-assign an empty frame over it: releases the old one
          BorrowedFrame empty;
          held[pick] = std::move(empty);
          break;
        }
        default:  // destructor
          break;
      }
      held.erase(held.begin() + static_cast<std::ptrdiff_t>(pick));
    }
  }
  // Stop with frames still borrowed; giving them back afterwards must not touch the device.
  while (held.size() < 2) held.push_back(stream.next(kWaitNs).frame);
  stream.stop();
  held.clear();
  EXPECT_GT(delivered, 100);
  EXPECT_EQ(stream.stats().sequence_gap_frames, 0);
  expectCleanDevice();  // no QBUF of a buffer the stream did not hold, no call on a closed fd
}

TEST_F(V4l2StreamTest, HoldingEveryBufferIsReportedInsteadOfWaitingForever) {
  device_.addNode(depthNodeConfig());
  V4l2Stream stream(device_, depthOptions());
  stream.start();
  std::vector<BorrowedFrame> held;
  for (int i = 0; i < 4; ++i) {
    NextResult result = stream.next(kWaitNs);
    ASSERT_EQ(result.status, NextStatus::kFrame);
    held.push_back(std::move(result.frame));
  }
  const std::int64_t before_ns = clock_.nowNs();
  EXPECT_EQ(stream.next(kWaitNs).status, NextStatus::kError);
  EXPECT_EQ(stream.lastProblem(),
            "depth /dev/video1: all 4 buffers are held by the caller; release frames before asking for more");
  EXPECT_EQ(clock_.nowNs(), before_ns);  // it did not wait
  held.pop_back();
  EXPECT_EQ(stream.next(kWaitNs).status, NextStatus::kFrame);
  EXPECT_EQ(stream.stats().errors, 1);
}

TEST_F(V4l2StreamTest, StreamingDecodingAndReleasingAllocateNothingAfterStart) {
  // Frame 40 of each script is error-flagged, so the rejection path runs inside the measured loop too.
  device_.addNode(depthNodeConfig([](const ScriptedFrameRequest& request, ScriptedFrame& frame) {
    fillDepth(request.frame_index, kFirstDinghyCounter + static_cast<std::uint32_t>(request.frame_index),
              request.payload, request.format.bytesperline);
    frame.t_stamp_ns = scriptedStampNs(request.arrival_ns);
    frame.error = request.frame_index == 40;
  }));
  device_.addNode(colourNodeConfig());
  V4l2Stream depth_stream(device_, depthOptions());
  V4l2Stream colour_stream(device_, colourOptions());
  depth_stream.start();
  colour_stream.start();
  Image<std::uint16_t> depth(kDepthWidthPx, kDepthHeightPx - 1);
  Image<Rgb8> rgb(kColourWidthPx, kColourHeightPx);
  ProblemText problem;
  constexpr int kWarmUpFrames = 3;
  constexpr int kMeasuredFrames = 90;
  int statuses[5] = {};
  std::uint32_t last_counter = 0;
  std::uint32_t last_colour_number = 0;
  std::uint64_t allocations_before = 0;
  for (int i = 0; i < kWarmUpFrames + kMeasuredFrames; ++i) {
    if (i == kWarmUpFrames) allocations_before = vifusion::test::heapAllocationCount();
    {
      NextResult result = depth_stream.next(kWaitNs);
      ++statuses[static_cast<int>(result.status)];
      if (result.frame) {
        const FrameView& view = result.frame.view();
        if (const auto dinghy = readDinghy(view.bytes, view.bytes_per_line, kDepthHeightPx, problem)) {
          if (checkDinghy(*dinghy, DinghyNode::kDepth, problem)) {
            depth_stream.noteEmbeddedFrameCounter(dinghy->frame_counter);
            last_counter = dinghy->frame_counter;
          }
        }
        z16ToDepth(view.bytes, view.bytes_per_line, depth.view(), problem);
      }
    }
    NextResult colour = colour_stream.next(kWaitNs);
    ++statuses[static_cast<int>(colour.status)];
    if (colour.frame) {
      const FrameView& view = colour.frame.view();
      last_colour_number =
          readColourFrameNumber(view.bytes, view.bytes_per_line, kColourWidthPx, kColourHeightPx, problem).value_or(0);
      yuyvToRgb(view.bytes, view.bytes_per_line, rgb.view(), problem);
    }
    colour.frame.release();
    ++statuses[static_cast<int>(depth_stream.next(0).status)];  // nothing is ready right after a frame
  }
  const std::uint64_t allocations = vifusion::test::heapAllocationCount() - allocations_before;
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(statuses[static_cast<int>(NextStatus::kFrame)], 2 * (kWarmUpFrames + kMeasuredFrames) - 1);
  EXPECT_EQ(statuses[static_cast<int>(NextStatus::kRejected)], 1);
  EXPECT_EQ(statuses[static_cast<int>(NextStatus::kTimeout)], kWarmUpFrames + kMeasuredFrames);
  EXPECT_EQ(depth_stream.stats().error_flagged_buffers, 1);
  // Both streams end at frame k = 92 (frame 40 of depth was rejected in its turn, not replaced).
  EXPECT_EQ(last_counter, kFirstDinghyCounter + kWarmUpFrames + kMeasuredFrames - 1);
  EXPECT_EQ(last_colour_number, static_cast<std::uint32_t>(kWarmUpFrames + kMeasuredFrames - 1));
  EXPECT_EQ(depth_stream.stats().embedded_gap_frames, 1);  // the rejected frame's counter never came
  EXPECT_EQ(device_.ruleViolations(), 0) << device_.lastViolation();
}

}  // namespace
}  // namespace vifusion::v4l2::test
