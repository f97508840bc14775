#include "synccheck_command.hpp"

#include <cstdio>
#include <filesystem>
#include <utility>

#include "run_source.hpp"
#include "sync_line_spec.hpp"
#include "vifusion/config/daemon_config.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/recording/recording_reader.hpp"
#include "vifusion/synccheck/analyse.hpp"
#include "vifusion/synccheck/sync_report.hpp"

#ifdef VIFUSION_WITH_ZR300
#include "vifusion/zr300/zr300_backend.hpp"
#endif

namespace vifusion::cli {
namespace {

constexpr int kExitFailedCheck = 1;
constexpr const char* kCommand = "vifusion synccheck";

synccheck::CameraFrameTimes frameTimes(std::int64_t index, std::int64_t t_ns, const FrameTiming& timing) {
  return {index,
          timing.device_frame_number,
          t_ns,
          timing.kernel_mid_exposure_ns,
          timing.device_event_ns,
          timing.stamped_by_device_event};
}

/// A recording's times: frames, edges and IMU, as recorded.
synccheck::SyncInput fromRecording(const std::string& path) {
  const recording::RecordingReader reader(path);
  if (!reader.note().empty()) std::fprintf(stderr, "%s: %s\n", kCommand, reader.note().c_str());
  synccheck::SyncInput input;
  for (const auto& frame : reader.frameStamps())
    input.frames.push_back(frameTimes(frame.index, frame.t_ns, frame.timing));
  for (const recording::RecordedSyncEdge& edge : reader.syncEdges()) {
    input.edges.push_back({edge.t_ns, edge.rising, edge.sequence});
  }
  for (const ImuSample& sample : reader.imu()) input.imu_t_ns.push_back(sample.t_ns);
  return input;
}

/// The live camera's and sync line's times over `duration_s`; false when they cannot be opened (printed).
bool fromLive(const SyncCheckCommandOptions& options, std::unique_ptr<zr300::Zr300Backend> backend,
              std::unique_ptr<gpio_sync::GpioLineIo> line_io, synccheck::SyncInput& input) {
  RunSource source;
  if (!openRunSource({options.source, options.calibration, "", true}, kCommand, std::move(backend), source))
    return false;
  if (!source.reader->live())
    throw Error("source '" + options.source + "': synccheck takes zr300[:SERIAL] or rec:FILE");
  std::unique_ptr<gpio_sync::SyncLine> sync_line;
  if (!options.gpio.empty()) {
    try {
      sync_line = openSyncLineSpec(options.gpio, options.edges, std::move(line_io));
    } catch (const std::exception& error) {
      std::fprintf(stderr, "%s: %s\n", kCommand, error.what());
      return false;
    }
  }
  watchInterrupts(source);
  const std::int64_t duration_ns = secondsToNs(options.duration_s);
  std::int64_t first_t_ns = 0, last_imu_t_ns = INT64_MIN;
  RgbdFrame frame;
  gpio_sync::SyncEdge edge;
  while (!interrupted() && source.reader->nextFrame(frame)) {
    if (input.frames.empty()) first_t_ns = frame.t_ns;
    if (frame.t_ns - first_t_ns > duration_ns) break;
    input.frames.push_back(frameTimes(frame.index, frame.t_ns, frame.timing));
    if (source.imu != nullptr) {
      for (const ImuSample& sample : source.imu->samplesThrough(frame.t_ns)) {
        if (sample.t_ns <= last_imu_t_ns) continue;
        input.imu_t_ns.push_back(sample.t_ns);
        last_imu_t_ns = sample.t_ns;
      }
    }
    if (sync_line) {
      while (sync_line->edgeRing().tryPop(edge)) input.edges.push_back({edge.t_ns, edge.rising, edge.sequence});
    }
  }
  forgetSource();
  if (sync_line) {
    sync_line->stop();
    while (sync_line->edgeRing().tryPop(edge)) input.edges.push_back({edge.t_ns, edge.rising, edge.sequence});
  }
  return true;
}

}  // namespace

int runSyncCheck(const SyncCheckCommandOptions& options, std::unique_ptr<zr300::Zr300Backend> backend,
                 std::unique_ptr<gpio_sync::GpioLineIo> line_io) {
  options.check.validate();
  synccheck::SyncInput input;
  if (options.simulate) {
    options.model.validate();
    input = synccheck::simulate(options.model, options.seed);
  } else if (options.source.starts_with("rec:")) {
    input = fromRecording(options.source.substr(4));
  } else {
    if (!(options.duration_s > 0.0)) throw Error("--duration must be > 0 s");
    if (!fromLive(options, std::move(backend), std::move(line_io), input)) return config::kExitSource;
  }
  const synccheck::SyncReport report = synccheck::analyse(input, options.check);
  std::printf("%s\n", report.toJson().c_str());
  if (!options.plot.empty()) report.savePlot(options.plot);
  return report.passed ? config::kExitOk : kExitFailedCheck;
}

int runSyncCheck(const SyncCheckCommandOptions& options) { return runSyncCheck(options, nullptr); }

}  // namespace vifusion::cli
