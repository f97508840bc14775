#pragma once
// `vifusion record`: records a source into a vifusion recording (recording/topics.hpp: MCAP with ROS 2
// messages) — the live camera with its IMU, its device clocks and, with --gpio, the sync line's edges, or any
// recorded source (a dataset, another recording, a sim:NAME sequence), as fast as it reads or, with
// --realtime, at its timestamps. Ends at --duration, at the source's end, or on Ctrl-C / SIGTERM, completing
// the file; a recording cut short anyway (SIGKILL, power loss) keeps everything up to its last chunk (at most
// 100 ms before the cut, recording/recorder.hpp), and `vifusion record --recover FILE` rewrites it complete.
//
// Exit codes: 0 recorded; 2 bad options or a bad recorded source; 3 the live camera or the sync line cannot be
// opened; 6 the recording failed (disk full, storage gone: the message names the file and why; what was
// written before stays readable).

#include <memory>
#include <string>

#include "vifusion/gpio_sync/gpio_line_io.hpp"
#include "vifusion/recording/recorder.hpp"

namespace vifusion::zr300 {
class Zr300Backend;
}

namespace vifusion::cli {

struct RecordOptions {
  std::string source = "zr300";  ///< a source spec of `vifusion run`
  std::string calibration;       ///< zr300: the rig's calibration.yaml
  std::string mode = "rgbdi";    ///< what the recording is for: rgbd records no IMU (the motion module stays closed)
  std::string out;               ///< the recording to create, FILE.mcap
  double duration_s = 0.0;       ///< > 0: stop after this much source time [s]
  bool realtime = false;         ///< recorded sources: deliver frames at their timestamps (live ones always do)
  std::string gpio;              ///< CHIP:LINE of the sync line to record; empty: none
  std::string edges = "rising";  ///< the sync line's edges: rising, falling or both
  std::string recover;           ///< a cut recording to rewrite complete (into --out, or FILE.recovered.mcap)
  recording::RecorderOptions recorder;  ///< ring sizes and MCAP settings (defaults; not on the command line)
};

/// `backend` reaches the camera (null: the real devices); `line_io`, when given, is the --gpio line instead
/// of the chip libgpiod opens (a scripted line in tests).
int runRecord(const RecordOptions& options, std::unique_ptr<zr300::Zr300Backend> backend,
              std::unique_ptr<gpio_sync::GpioLineIo> line_io = nullptr);
/// The same on the real devices.
int runRecord(const RecordOptions& options);

}  // namespace vifusion::cli
