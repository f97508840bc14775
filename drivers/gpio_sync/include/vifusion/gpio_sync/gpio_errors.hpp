#pragma once
// The messages a failed line request gives, one place for their wording (LibgpiodLineIo throws them; they
// are pure functions so they are tested, and build, without libgpiod or a chip). Each names the chip as the
// user configured it, then the line, then what is wrong and what to do.

#include <string>
#include <string_view>

#include "vifusion/gpio_sync/edge_detection.hpp"

namespace vifusion::gpio_sync {

/// The device node a chip setting names: "/dev/" + a name, or an absolute path as is.
std::string chipPath(std::string_view chip);

/// Opening the chip failed with `error_number` (errno), e.g.
/// "gpiochip7: no such GPIO chip (/dev/gpiochip7: No such file or directory; `gpiodetect` lists the chips)".
std::string describeChipOpenFailure(std::string_view chip, int error_number);

/// "gpiochip0 line 40: out of range, the chip has 32 lines (offsets 0 to 31)".
std::string describeLineOutOfRange(std::string_view chip, unsigned line_offset, unsigned line_count);

/// Requesting edge events failed with `error_number`; `holder` is the consumer that holds the line when
/// known (empty otherwise), e.g. "gpiochip0 line 5: cannot request rising edge events: the line is busy,
/// held by \"gpio-keys\" (Device or resource busy)".
std::string describeRequestFailure(std::string_view chip, unsigned line_offset, EdgeDetection edges, int error_number,
                                   std::string_view holder);

}  // namespace vifusion::gpio_sync
