#include <gtest/gtest.h>

#include <cerrno>

#include "vifusion/gpio_sync/gpio_errors.hpp"

namespace vifusion::gpio_sync {
namespace {

TEST(GpioErrors, ChipPathIsUnderDevForANameAndAsIsForAPath) {
  EXPECT_EQ(chipPath("gpiochip0"), "/dev/gpiochip0");
  EXPECT_EQ(chipPath("/dev/gpio-strobe"), "/dev/gpio-strobe");
}

TEST(GpioErrors, OpenFailuresNameTheChipAndWhatToDo) {
  EXPECT_EQ(describeChipOpenFailure("gpiochip7", ENOENT),
            "gpiochip7: no such GPIO chip (/dev/gpiochip7: No such file or directory; `gpiodetect` lists the "
            "chips)");
  EXPECT_EQ(describeChipOpenFailure("gpiochip0", EACCES),
            "gpiochip0: permission denied (/dev/gpiochip0: Permission denied; give the service user access to the "
            "chip through the udev rule and its group)");
  EXPECT_EQ(describeChipOpenFailure("/dev/null", ENOTTY),
            "/dev/null: not a GPIO chip (/dev/null: Inappropriate ioctl for device)");
  EXPECT_EQ(describeChipOpenFailure("gpiochip0", EIO),
            "gpiochip0: cannot open the GPIO chip (/dev/gpiochip0: Input/output error)");
}

TEST(GpioErrors, AnOutOfRangeLineNamesTheLineAndTheChipsLineCount) {
  EXPECT_EQ(describeLineOutOfRange("gpiochip0", 40, 32),
            "gpiochip0 line 40: out of range, the chip has 32 lines (offsets 0 to 31)");
  EXPECT_EQ(describeLineOutOfRange("gpiochip1", 1, 1),
            "gpiochip1 line 1: out of range, the chip has 1 line (offsets 0 to 0)");
  EXPECT_EQ(describeLineOutOfRange("gpiochip2", 0, 0), "gpiochip2 line 0: out of range, the chip has 0 lines");
}

TEST(GpioErrors, ABusyLineNamesItsHolder) {
  EXPECT_EQ(describeRequestFailure("gpiochip0", 5, EdgeDetection::kRising, EBUSY, "gpio-keys"),
            "gpiochip0 line 5: cannot request rising edge events: the line is busy, held by \"gpio-keys\" (Device "
            "or resource busy)");
  EXPECT_EQ(describeRequestFailure("gpiochip0", 5, EdgeDetection::kBoth, EBUSY, ""),
            "gpiochip0 line 5: cannot request both edge events: the line is busy (Device or resource busy)");
  EXPECT_EQ(describeRequestFailure("gpiochip0", 5, EdgeDetection::kFalling, EINVAL, ""),
            "gpiochip0 line 5: cannot request falling edge events: Invalid argument");
}

}  // namespace
}  // namespace vifusion::gpio_sync
