// The scripted device's own rules, driven with raw calls: the test double must refuse what a kernel refuses,
// or the V4l2Stream tests built on it would prove nothing.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <sys/mman.h>

#include <cerrno>
#include <string>

#include "scripted_zr300.hpp"

namespace vifusion::v4l2::test {
namespace {

using v4l2_scripted::ManualClock;
using v4l2_scripted::ScriptedV4l2Device;

constexpr std::int64_t kT0 = ManualClock::kDefaultStartNs;
constexpr std::int64_t kFirstArrivalNs = kT0 + kFirstArrivalDelayNs;

v4l2_buffer mmapBuffer(std::uint32_t index) {
  v4l2_buffer buffer{};
  buffer.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buffer.memory = V4L2_MEMORY_MMAP;
  buffer.index = index;
  return buffer;
}

class ScriptedDeviceTest : public ::testing::Test {
 protected:
  ScriptedDeviceTest() { device_.addNode(depthNodeConfig()); }

  /// Opens the depth node, allocates and maps `count` buffers; returns the fd.
  int openWithBuffers(std::uint32_t count, int flags = O_RDWR | O_NONBLOCK) {
    const int fd = device_.open(kDepthPath, flags);
    EXPECT_GE(fd, ScriptedV4l2Device::kFirstFd);
    v4l2_requestbuffers request{};
    request.count = count;
    request.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    request.memory = V4L2_MEMORY_MMAP;
    EXPECT_EQ(device_.ioctl(fd, VIDIOC_REQBUFS, &request), 0);
    EXPECT_EQ(request.count, count);
    for (std::uint32_t i = 0; i < count; ++i) {
      v4l2_buffer buffer = mmapBuffer(i);
      EXPECT_EQ(device_.ioctl(fd, VIDIOC_QUERYBUF, &buffer), 0);
      mappings_[i] = device_.mmap(nullptr, buffer.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, buffer.m.offset);
      lengths_[i] = buffer.length;
      EXPECT_NE(mappings_[i], MAP_FAILED);
    }
    return fd;
  }

  int queue(int fd, std::uint32_t index) {
    v4l2_buffer buffer = mmapBuffer(index);
    return device_.ioctl(fd, VIDIOC_QBUF, &buffer);
  }

  int streamOn(int fd) {
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    return device_.ioctl(fd, VIDIOC_STREAMON, &type);
  }

  ManualClock clock_;
  ScriptedV4l2Device device_{clock_};
  void* mappings_[8] = {};
  std::uint32_t lengths_[8] = {};
};

TEST_F(ScriptedDeviceTest, QbufOfABufferTheClientDoesNotHoldIsRefused) {
  const int fd = openWithBuffers(2);
  ASSERT_EQ(queue(fd, 0), 0);
  EXPECT_EQ(queue(fd, 0), -1);
  EXPECT_EQ(errno, EINVAL);
  EXPECT_EQ(device_.ruleViolations(), 1);
  EXPECT_EQ(device_.lastViolation(), "/dev/video1 QBUF(0): the buffer is queued already, not held by the client");

  ASSERT_EQ(streamOn(fd), 0);
  clock_.advanceTo(kFirstArrivalNs);  // frame 0 completes into buffer 0
  EXPECT_EQ(queue(fd, 0), -1);
  EXPECT_EQ(device_.lastViolation(), "/dev/video1 QBUF(0): the buffer is done, not dequeued, not held by the client");
  EXPECT_EQ(queue(fd, 7), -1);
  EXPECT_EQ(device_.lastViolation(), "/dev/video1 QBUF(7): only 2 buffers exist");
  EXPECT_EQ(device_.ruleViolations(), 3);

  v4l2_buffer buffer = mmapBuffer(0);
  ASSERT_EQ(device_.ioctl(fd, VIDIOC_DQBUF, &buffer), 0);
  EXPECT_EQ(buffer.index, 0u);
  EXPECT_EQ(queue(fd, 0), 0);  // now it is the client's to give back
  EXPECT_EQ(device_.ruleViolations(), 3);
}

TEST_F(ScriptedDeviceTest, CallsOutOfOrderAreRefusedAndCounted) {
  const int fd = device_.open(kDepthPath, O_RDWR | O_NONBLOCK);
  EXPECT_EQ(streamOn(fd), -1);  // no buffers
  EXPECT_EQ(errno, EINVAL);
  v4l2_buffer buffer = mmapBuffer(0);
  EXPECT_EQ(device_.ioctl(fd, VIDIOC_DQBUF, &buffer), -1);
  EXPECT_EQ(errno, EINVAL);
  EXPECT_EQ(device_.lastViolation(), "/dev/video1 DQBUF while not streaming");
  v4l2_requestbuffers userptr{};
  userptr.count = 2;
  userptr.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  userptr.memory = V4L2_MEMORY_USERPTR;
  EXPECT_EQ(device_.ioctl(fd, VIDIOC_REQBUFS, &userptr), -1);
  EXPECT_EQ(device_.lastViolation(), "/dev/video1 REQBUFS: type 1 memory 2, only VIDEO_CAPTURE and MMAP");
  EXPECT_EQ(device_.close(fd), 0);
  EXPECT_EQ(device_.ruleViolations(), 3);

  const int owner = openWithBuffers(2);
  v4l2_format format{};
  format.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  EXPECT_EQ(device_.ioctl(owner, VIDIOC_S_FMT, &format), -1);
  EXPECT_EQ(errno, EBUSY);
  v4l2_requestbuffers again{};
  again.count = 0;
  again.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  again.memory = V4L2_MEMORY_MMAP;
  EXPECT_EQ(device_.ioctl(owner, VIDIOC_REQBUFS, &again), -1);  // still mapped
  EXPECT_EQ(device_.lastViolation(), "/dev/video1 REQBUFS(0) while 2 buffers are still mapped");
  EXPECT_EQ(device_.mmap(nullptr, 4096, PROT_READ, MAP_SHARED, owner, 12345), MAP_FAILED);
  EXPECT_EQ(device_.mmap(nullptr, lengths_[0], PROT_READ, MAP_PRIVATE, owner, 0), MAP_FAILED);
  const int other = device_.open(kDepthPath, O_RDWR);
  again.count = 2;
  EXPECT_EQ(device_.ioctl(other, VIDIOC_REQBUFS, &again), -1);
  EXPECT_EQ(errno, EBUSY);
  EXPECT_EQ(device_.close(123), -1);
  EXPECT_EQ(errno, EBADF);
  EXPECT_EQ(device_.ruleViolations(), 9);

  // A correct teardown is accepted.
  EXPECT_EQ(device_.munmap(mappings_[0], lengths_[0]), 0);
  EXPECT_EQ(device_.munmap(mappings_[1], lengths_[1]), 0);
  again.count = 0;
  EXPECT_EQ(device_.ioctl(owner, VIDIOC_REQBUFS, &again), 0);
  EXPECT_EQ(device_.close(owner), 0);
  EXPECT_EQ(device_.close(other), 0);
  EXPECT_EQ(device_.ruleViolations(), 9);
  EXPECT_EQ(device_.openFdCount(), 0);
  EXPECT_EQ(device_.liveMappingCount(), 0);
}

TEST_F(ScriptedDeviceTest, NonBlockingDqbufAndPollFollowTheManualClock) {
  const int fd = openWithBuffers(2);
  ASSERT_EQ(queue(fd, 0), 0);
  ASSERT_EQ(queue(fd, 1), 0);
  ASSERT_EQ(streamOn(fd), 0);
  v4l2_buffer buffer = mmapBuffer(0);
  EXPECT_EQ(device_.ioctl(fd, VIDIOC_DQBUF, &buffer), -1);
  EXPECT_EQ(errno, EAGAIN);

  pollfd descriptor{fd, POLLIN, 0};
  EXPECT_EQ(device_.poll(&descriptor, 1, 4), 0);  // frame 0 completes at +10 ms
  EXPECT_EQ(clock_.nowNs(), kT0 + 4'000'000);
  EXPECT_EQ(device_.poll(&descriptor, 1, 100), 1);
  EXPECT_EQ(descriptor.revents, POLLIN);
  EXPECT_EQ(clock_.nowNs(), kFirstArrivalNs);  // woken at the arrival, not at the timeout

  ASSERT_EQ(device_.ioctl(fd, VIDIOC_DQBUF, &buffer), 0);
  EXPECT_EQ(buffer.sequence, 0u);
  const std::int64_t stamp_us = (kFirstArrivalNs - kStampBeforeArrivalNs) / 1000;
  EXPECT_EQ(buffer.timestamp.tv_sec, stamp_us / 1'000'000);
  EXPECT_EQ(buffer.timestamp.tv_usec, stamp_us % 1'000'000);
  EXPECT_EQ(buffer.flags & (V4L2_BUF_FLAG_TIMESTAMP_MASK | V4L2_BUF_FLAG_TSTAMP_SRC_MASK),
            V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_SOE);
  EXPECT_EQ(buffer.bytesused, 628u * 2u * 469u);
  EXPECT_EQ(device_.ruleViolations(), 0);
}

TEST_F(ScriptedDeviceTest, FramesWithoutAQueuedBufferAreDroppedAndSkipTheirSequence) {
  const int fd = openWithBuffers(2);
  ASSERT_EQ(queue(fd, 0), 0);
  ASSERT_EQ(queue(fd, 1), 0);
  ASSERT_EQ(streamOn(fd), 0);
  clock_.advanceTo(kFirstArrivalNs + 4 * kPeriodNs);  // frames 0 … 4 arrive; only two buffers
  v4l2_buffer buffer = mmapBuffer(0);
  ASSERT_EQ(device_.ioctl(fd, VIDIOC_DQBUF, &buffer), 0);
  EXPECT_EQ(buffer.sequence, 0u);
  ASSERT_EQ(device_.ioctl(fd, VIDIOC_DQBUF, &buffer), 0);
  EXPECT_EQ(buffer.sequence, 1u);
  const auto stats = device_.nodeStats(kDepthPath);
  EXPECT_EQ(stats.arrivals, 5);
  EXPECT_EQ(stats.filled, 2);
  EXPECT_EQ(stats.dropped_no_buffer, 3);
  ASSERT_EQ(queue(fd, 0), 0);
  clock_.advanceTo(kFirstArrivalNs + 5 * kPeriodNs);
  ASSERT_EQ(device_.ioctl(fd, VIDIOC_DQBUF, &buffer), 0);
  EXPECT_EQ(buffer.sequence, 5u);
}

TEST_F(ScriptedDeviceTest, BlockingDqbufMovesTheClockInsteadOfSleeping) {
  const int fd = openWithBuffers(2, O_RDWR);
  ASSERT_EQ(queue(fd, 0), 0);
  ASSERT_EQ(streamOn(fd), 0);
  v4l2_buffer buffer = mmapBuffer(0);
  ASSERT_EQ(device_.ioctl(fd, VIDIOC_DQBUF, &buffer), 0);
  EXPECT_EQ(clock_.nowNs(), kFirstArrivalNs);
  // Nothing queued and nothing scheduled for it: a blocking DQBUF would hang; the device says so instead.
  v4l2_scripted::ScriptedNodeConfig finite = colourNodeConfig();
  finite.schedule.frame_count = 0;
  device_.addNode(finite);
  const int colour = device_.open(kColourPath, O_RDWR);
  v4l2_requestbuffers request{};
  request.count = 1;
  request.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  request.memory = V4L2_MEMORY_MMAP;
  ASSERT_EQ(device_.ioctl(colour, VIDIOC_REQBUFS, &request), 0);
  ASSERT_EQ(queue(colour, 0), 0);
  ASSERT_EQ(streamOn(colour), 0);
  ASSERT_EQ(device_.ioctl(fd, VIDIOC_STREAMOFF, &request.type), 0);  // the depth node's arrivals stop too
  EXPECT_EQ(device_.ioctl(colour, VIDIOC_DQBUF, &buffer), -1);
  EXPECT_EQ(errno, EDEADLK);
}

TEST_F(ScriptedDeviceTest, UnplugFailsEverythingButCloseAndMunmapUntilTheReplug) {
  const int fd = openWithBuffers(2);
  ASSERT_EQ(queue(fd, 0), 0);
  ASSERT_EQ(streamOn(fd), 0);
  device_.unplug();
  v4l2_buffer buffer = mmapBuffer(1);
  EXPECT_EQ(device_.ioctl(fd, VIDIOC_QBUF, &buffer), -1);
  EXPECT_EQ(errno, ENODEV);
  pollfd descriptor{fd, POLLIN, 0};
  EXPECT_EQ(device_.poll(&descriptor, 1, 1000), 1);
  EXPECT_EQ(descriptor.revents, POLLERR | POLLHUP);
  EXPECT_EQ(device_.mmap(nullptr, lengths_[0], PROT_READ, MAP_SHARED, fd, 0), MAP_FAILED);
  EXPECT_EQ(errno, ENODEV);
  EXPECT_EQ(device_.open(kDepthPath, O_RDWR), -1);
  EXPECT_EQ(errno, ENOENT);
  EXPECT_EQ(device_.munmap(mappings_[0], lengths_[0]), 0);
  EXPECT_EQ(device_.munmap(mappings_[1], lengths_[1]), 0);
  EXPECT_EQ(device_.close(fd), 0);
  EXPECT_EQ(device_.ruleViolations(), 0);

  device_.replug();
  const int again = device_.open(kDepthPath, O_RDWR | O_NONBLOCK);
  ASSERT_GE(again, 0);
  const auto stats = device_.nodeStats(kDepthPath);
  EXPECT_FALSE(stats.streaming);
  EXPECT_EQ(stats.buffers, 0);
  EXPECT_EQ(stats.arrivals, 0);
  EXPECT_EQ(device_.close(again), 0);
}

TEST_F(ScriptedDeviceTest, AScheduledUnplugHappensBetweenTheFramesAroundIt) {
  const int fd = openWithBuffers(4);
  for (std::uint32_t i = 0; i < 4; ++i) ASSERT_EQ(queue(fd, i), 0);
  ASSERT_EQ(streamOn(fd), 0);
  device_.scheduleUnplug(kFirstArrivalNs + 2 * kPeriodNs + kPeriodNs / 2);
  pollfd descriptor{fd, POLLIN, 0};
  int frames = 0;
  while (device_.poll(&descriptor, 1, 1000) == 1 && descriptor.revents == POLLIN) {
    v4l2_buffer buffer = mmapBuffer(0);
    ASSERT_EQ(device_.ioctl(fd, VIDIOC_DQBUF, &buffer), 0);
    EXPECT_EQ(buffer.sequence, static_cast<std::uint32_t>(frames));
    ++frames;
  }
  EXPECT_EQ(frames, 3);
  EXPECT_EQ(descriptor.revents, POLLERR | POLLHUP);
  EXPECT_EQ(clock_.nowNs(), kFirstArrivalNs + 2 * kPeriodNs + kPeriodNs / 2);
  EXPECT_FALSE(device_.plugged());
}

TEST_F(ScriptedDeviceTest, FormatAndRateFallBackLikeUvcvideo) {
  device_.addNode(colourNodeConfig());
  const int fd = device_.open(kColourPath, O_RDWR);
  v4l2_format format{};
  format.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  format.fmt.pix.pixelformat = kFourccZ16;  // not offered: falls back to the default format
  format.fmt.pix.width = 330;
  format.fmt.pix.height = 250;
  ASSERT_EQ(device_.ioctl(fd, VIDIOC_S_FMT, &format), 0);
  EXPECT_EQ(format.fmt.pix.pixelformat, kFourccYuyv);
  EXPECT_EQ(format.fmt.pix.width, 320u);  // nearest offered size
  EXPECT_EQ(format.fmt.pix.height, 240u);
  EXPECT_EQ(format.fmt.pix.bytesperline, 640u);
  EXPECT_EQ(format.fmt.pix.sizeimage, 640u * 240u);
  v4l2_streamparm parameters{};
  parameters.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  parameters.parm.capture.timeperframe = {1, 50};
  ASSERT_EQ(device_.ioctl(fd, VIDIOC_S_PARM, &parameters), 0);
  EXPECT_EQ(parameters.parm.capture.timeperframe.denominator, 60u);
  EXPECT_EQ(parameters.parm.capture.capability, static_cast<std::uint32_t>(V4L2_CAP_TIMEPERFRAME));
  EXPECT_EQ(device_.ruleViolations(), 0);
}

}  // namespace
}  // namespace vifusion::v4l2::test
