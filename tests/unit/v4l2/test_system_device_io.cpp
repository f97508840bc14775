// The real syscall side of the seam, on files every Linux machine has (no camera needed).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <pthread.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <thread>

#include "vifusion/core/time.hpp"
#include "vifusion/test/expect_error.hpp"
#include "vifusion/v4l2/device_error.hpp"
#include "vifusion/v4l2/device_io.hpp"
#include "vifusion/v4l2/v4l2_stream.hpp"

namespace vifusion::v4l2 {
namespace {

/// What this platform answers to VIDIOC_QUERYCAP on /dev/null, asked directly: ENOTTY from Linux, ENOSYS
/// under qemu-user (it refuses ioctls it cannot translate). The seam must pass exactly that through.
int queryCapErrnoOfDevNull() {
  const int fd = ::open("/dev/null", O_RDWR | O_CLOEXEC);
  v4l2_capability capability{};
  const int result = ::ioctl(fd, VIDIOC_QUERYCAP, &capability);
  const int error_number = result < 0 ? errno : 0;
  ::close(fd);
  return error_number;
}

TEST(SystemDeviceIo, PassesCallsAndErrnoThrough) {
  SystemDeviceIo io;
  const int fd = io.open("/dev/null", O_RDWR);
  ASSERT_GE(fd, 0);
  v4l2_capability capability{};
  const int expected_errno = queryCapErrnoOfDevNull();
  ASSERT_TRUE(expected_errno == ENOTTY || expected_errno == ENOSYS) << errnoText(expected_errno);
  EXPECT_EQ(io.ioctl(fd, VIDIOC_QUERYCAP, &capability), -1);
  EXPECT_EQ(errno, expected_errno);
  EXPECT_EQ(io.close(fd), 0);
  EXPECT_EQ(io.open("/dev/vifusion-no-such-node", O_RDWR), -1);
  EXPECT_EQ(errno, ENOENT);

  const int zero = io.open("/dev/zero", O_RDONLY);
  ASSERT_GE(zero, 0);
  void* mapping = io.mmap(nullptr, 4096, PROT_READ, MAP_PRIVATE, zero, 0);
  ASSERT_NE(mapping, MAP_FAILED);
  EXPECT_EQ(static_cast<const unsigned char*>(mapping)[4095], 0);
  EXPECT_EQ(io.munmap(mapping, 4096), 0);
  EXPECT_EQ(io.close(zero), 0);
}

void ignoreSignal(int) {}

TEST(SystemDeviceIo, PollWaitsOutItsTimeoutThroughSignals) {
  // A signal handler installed without SA_RESTART makes poll(2) fail with EINTR; the seam must wait on.
  struct sigaction action {};
  action.sa_handler = ignoreSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  struct sigaction previous {};
  ASSERT_EQ(sigaction(SIGUSR1, &action, &previous), 0);

  int pipe_fds[2];
  ASSERT_EQ(pipe(pipe_fds), 0);
  SystemDeviceIo io;
  const pthread_t poller = pthread_self();
  std::atomic<bool> done{false};
  std::thread interrupter([&] {
    for (int i = 0; i < 5 && !done; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      pthread_kill(poller, SIGUSR1);
    }
  });
  pollfd descriptor{pipe_fds[0], POLLIN, 0};
  const std::int64_t start_ns = monotonicNowNs();
  const int ready = io.poll(&descriptor, 1, 120);
  const std::int64_t waited_ns = monotonicNowNs() - start_ns;
  done = true;
  interrupter.join();
  EXPECT_EQ(ready, 0);
  EXPECT_GE(waited_ns, 120 * kNsPerMillisecond);

  ASSERT_EQ(write(pipe_fds[1], "x", 1), 1);
  EXPECT_EQ(io.poll(&descriptor, 1, 1000), 1);
  EXPECT_EQ(descriptor.revents, POLLIN);
  close(pipe_fds[0]);
  close(pipe_fds[1]);
  sigaction(SIGUSR1, &previous, nullptr);
}

TEST(SystemDeviceIo, StreamOnANonV4l2FileFailsNamingNodeAndErrno) {
  SystemDeviceIo io;
  V4l2StreamOptions options;
  options.label = "depth";
  options.node_path = "/dev/null";
  V4l2Stream stream(io, options);
  try {
    stream.start();
    FAIL() << "started on /dev/null";
  } catch (const DeviceError& error) {
    const int expected_errno = queryCapErrnoOfDevNull();
    EXPECT_EQ(error.errorNumber(), expected_errno);
    EXPECT_FALSE(error.deviceGone());
    EXPECT_EQ(std::string(error.what()),
              "depth /dev/null: VIDIOC_QUERYCAP failed (not a V4L2 device?): " + errnoText(expected_errno));
  }
  EXPECT_EQ(stream.fd(), -1);  // closed again
  options.node_path = "/dev/vifusion-no-such-node";
  V4l2Stream missing(io, options);
  vifusion::test::expectError([&] { missing.start(); }, "depth /dev/vifusion-no-such-node: cannot open: ENOENT");
}

}  // namespace
}  // namespace vifusion::v4l2
