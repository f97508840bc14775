#include "synccheck_command.hpp"

#include <cstdio>
#include <filesystem>
#include <span>
#include <utility>
#include <vector>

#include "run_source.hpp"
#include "sync_line_spec.hpp"
#include "vifusion/config/daemon_config.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/recording/recording_reader.hpp"
#include "vifusion/synccheck/analyse.hpp"
#include "vifusion/synccheck/motion_clock_residuals.hpp"
#include "vifusion/synccheck/sync_report.hpp"

#ifdef VIFUSION_WITH_ZR300
#include "vifusion/zr300/zr300_backend.hpp"
#include "vifusion/zr300/zr300_source.hpp"
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

/// Motion-module transfers kept between two frames while checking live: ≈5 s at ≈100 transfers/s.
constexpr std::size_t kRawTransferRing = 512;

/// Transfers as received (bytes and arrival), collected to derive the clock mapper's residuals.
struct CollectedTransfers {
  std::vector<std::int64_t> host_receive_ns;
  std::vector<std::vector<std::uint8_t>> bytes;

  void add(std::int64_t t_ns, std::span<const std::uint8_t> data) {
    host_receive_ns.push_back(t_ns);
    bytes.emplace_back(data.begin(), data.end());
  }
  std::vector<synccheck::ClockResidualSample> residuals() const {
    std::vector<synccheck::MotionTransferBytes> transfers;
    for (std::size_t i = 0; i < bytes.size(); ++i) transfers.push_back({host_receive_ns[i], bytes[i]});
    return synccheck::motionClockResiduals(transfers);
  }
};

/// A recording's times: frames, edges, IMU and the motion module's transfers, as recorded.
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
  // The packets of one transfer are consecutive and share its index: put the transfers back together.
  CollectedTransfers transfers;
  const auto packets = reader.motionPackets();
  for (std::size_t i = 0; i < packets.size();) {
    std::vector<std::uint8_t> bytes;
    std::size_t j = i;
    for (; j < packets.size() && packets[j].transfer_index == packets[i].transfer_index &&
           packets[j].host_receive_ns == packets[i].host_receive_ns;
         ++j) {
      bytes.insert(bytes.end(), packets[j].bytes.begin(), packets[j].bytes.end());
    }
    transfers.add(packets[i].host_receive_ns, bytes);
    i = j;
  }
  input.clock_residuals = transfers.residuals();
  return input;
}

/// The live camera's and sync line's times over `duration_s`; false when they cannot be opened (printed).
bool fromLive(const SyncCheckCommandOptions& options, std::unique_ptr<zr300::Zr300Backend> backend,
              std::unique_ptr<gpio_sync::GpioLineIo> line_io, synccheck::SyncInput& input) {
  RunSource source;
  if (!openRunSource({options.source, options.calibration, "", true, kRawTransferRing, {}, false}, kCommand,
                     std::move(backend), source))
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
  CollectedTransfers transfers;
  while (!interrupted() && source.reader->nextFrame(frame)) {
#ifdef VIFUSION_WITH_ZR300
    if (SpscRing<usb_imu::RawTransfer>* raw = source.camera != nullptr ? source.camera->rawTransferRing() : nullptr) {
      while (const usb_imu::RawTransfer* transfer = raw->front()) {
        transfers.add(transfer->host_receive_ns, std::span<const std::uint8_t>(transfer->bytes.data(), transfer->size));
        raw->pop();
      }
    }
#endif
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
  input.clock_residuals = transfers.residuals();
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
