// The real LibgpiodLineIo on this machine, which has no GPIO chip: the error paths a person meets when the
// configuration names the wrong chip, through libgpiod itself.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <memory>

#include "vifusion/core/time.hpp"
#include "vifusion/gpio_sync/libgpiod_line_io.hpp"
#include "vifusion/gpio_sync/sync_line.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::gpio_sync {
namespace {

bool exists(const char* path) {
  struct stat info {};
  return ::stat(path, &info) == 0;
}

TEST(LibgpiodLineIo, AMissingChipIsNamedWithItsPath) {
  if (exists("/dev/gpiochip7")) GTEST_SKIP() << "this machine has a /dev/gpiochip7";
  LibgpiodLineIo io;
  test::expectError([&] { io.open("gpiochip7", 0, EdgeDetection::kRising); },
                    "gpiochip7: no such GPIO chip (/dev/gpiochip7: No such file or directory");
  test::expectError([&] { io.open("/dev/gpio-no-such-strobe", 4, EdgeDetection::kBoth); },
                    "/dev/gpio-no-such-strobe: no such GPIO chip (/dev/gpio-no-such-strobe: No such file");
}

TEST(LibgpiodLineIo, ANodeThatIsNotAGpioChipIsRefused) {
  LibgpiodLineIo io;
  test::expectError([&] { io.open("/dev/null", 0, EdgeDetection::kRising); },
                    "/dev/null: not a GPIO chip (/dev/null: Inappropriate ioctl for device)");
  test::expectError([&] { io.open("/dev", 0, EdgeDetection::kRising); },
                    "/dev: not a GPIO chip (/dev: Is a directory)");
}

TEST(LibgpiodLineIo, WaitingOrReadingWithoutALineFailsWithoutCrashing) {
  LibgpiodLineIo io;
  EXPECT_EQ(io.waitEvent(1), LineStatus::kError);
  EXPECT_STREQ(io.errorText(), "Bad file descriptor");
  std::array<LineEvent, kMaxEventsPerRead> events{};
  std::size_t count = 7;
  EXPECT_EQ(io.readEvents(events, count), LineStatus::kError);
  EXPECT_EQ(count, 0u);
  io.close();
  io.close();  // twice is safe
}

TEST(LibgpiodLineIo, NowIsTheMonotonicClock) {
  LibgpiodLineIo io;
  const std::int64_t before_ns = monotonicNowNs();
  const std::int64_t now_ns = io.nowNs();
  EXPECT_GE(now_ns, before_ns);
  EXPECT_LT(now_ns - before_ns, kNsPerSecond);
}

TEST(LibgpiodLineIo, SyncLineStartNamesTheMissingChipAndStaysClosed) {
  if (exists("/dev/gpiochip7")) GTEST_SKIP() << "this machine has a /dev/gpiochip7";
  SyncLineOptions options;
  options.chip = "gpiochip7";
  options.line_offset = 12;
  SyncLine line(std::make_unique<LibgpiodLineIo>(), options);
  test::expectError([&] { line.start(); }, "gpiochip7: no such GPIO chip");
  EXPECT_EQ(line.state(), SyncLineState::kClosed);
}

}  // namespace
}  // namespace vifusion::gpio_sync
