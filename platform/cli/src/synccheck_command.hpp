#pragma once
// `vifusion synccheck`: the hardware-in-the-loop timestamp-sync test. Collects the camera frames' times
// (the stamp SLAM uses, the kernel's, the motion module's event), the sync line's edges and the IMU's
// sample times — live from the camera and --gpio line for --duration seconds, from a recording (rec:FILE),
// or from the clock model of --simulate — and reports offsets, jitter, drift, drops and IMU gaps
// (platform/synccheck): one JSON object on stdout, a PNG of the offsets over time with --plot, and the exit
// code 0 when every check passes, 1 when one fails (2 bad options, 3 no camera or sync line).

#include <cstdint>
#include <memory>
#include <string>

#include "vifusion/gpio_sync/gpio_line_io.hpp"
#include "vifusion/synccheck/clock_model.hpp"
#include "vifusion/synccheck/sync_check_options.hpp"

namespace vifusion::zr300 {
class Zr300Backend;
}

namespace vifusion::cli {

struct SyncCheckCommandOptions {
  std::string source = "zr300";  ///< zr300[:SERIAL] or rec:FILE.mcap
  std::string calibration;       ///< zr300: the rig's calibration.yaml
  std::string gpio;              ///< live: CHIP:LINE of the sync line
  std::string edges = "rising";  ///< the edge of each strobe pulse: rising or falling
  double duration_s = 60.0;      ///< live: how long to collect [s]
  bool simulate = false;         ///< analyse the clock model instead of a source
  synccheck::ClockModel model;   ///< --simulate: offset, drift, jitter, drops
  std::uint64_t seed = 1;        ///< --simulate: the noise's seed
  synccheck::SyncCheckOptions check;
  std::string plot;  ///< PNG of the offsets over time; empty: none
};

/// `backend` reaches the camera (null: the real devices); `line_io`, when given, is the --gpio line instead
/// of the chip libgpiod opens (a scripted line in tests; the spec's chip and line are still what it opens).
int runSyncCheck(const SyncCheckCommandOptions& options, std::unique_ptr<zr300::Zr300Backend> backend,
                 std::unique_ptr<gpio_sync::GpioLineIo> line_io = nullptr);
/// The same on the real devices.
int runSyncCheck(const SyncCheckCommandOptions& options);

}  // namespace vifusion::cli
