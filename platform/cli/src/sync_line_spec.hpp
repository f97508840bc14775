#pragma once
// `--gpio CHIP:LINE` of `vifusion record` and `vifusion synccheck`: the sync line (the camera's strobe or an
// external trigger) through drivers/gpio_sync, started and stamping edges on its own thread.

#include <memory>
#include <string>

#include "vifusion/gpio_sync/gpio_line_io.hpp"
#include "vifusion/gpio_sync/sync_line.hpp"

namespace vifusion::cli {

/// Opens and starts the line `spec` ("gpiochip0:17", or "/dev/gpiochip0:17") for `edges` ("rising",
/// "falling", "both"), through `io` when given (a scripted line in tests), else through libgpiod.
/// @throws vifusion::Error naming the spec and what is wrong (a missing chip, a line out of range or held by
/// another driver, a build without libgpiod and no `io`).
std::unique_ptr<gpio_sync::SyncLine> openSyncLineSpec(const std::string& spec, const std::string& edges,
                                                      std::unique_ptr<gpio_sync::GpioLineIo> io = nullptr);

}  // namespace vifusion::cli
