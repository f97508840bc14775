#include "record_command.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>
#include <utility>

#include "run_source.hpp"
#include "sync_line_spec.hpp"
#include "vifusion/config/daemon_config.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/mcap/recover_mcap.hpp"
#include "vifusion/recording/recorder.hpp"
#ifdef VIFUSION_WITH_ZR300
#include "vifusion/zr300/zr300_source.hpp"
#endif

#ifdef VIFUSION_WITH_ZR300
#include "vifusion/zr300/zr300_backend.hpp"
#endif

namespace vifusion::cli {
namespace {

constexpr std::int64_t kWaitStepNs = kNsPerMillisecond;
/// Motion-module transfers kept between two frames for the recorder: ≈5 s of the module's ≈100 transfers/s.
constexpr std::size_t kRawTransferRing = 512;
/// Nominal camera rate of a recorded source, for the recording info (its frames keep their own times) [Hz].
constexpr double kRecordedFrameRateHz = 30.0;

int recover(const RecordOptions& options) {
  const std::filesystem::path in = options.recover;
  std::filesystem::path out = options.out;
  if (out.empty()) out = in.parent_path() / (in.stem().string() + ".recovered.mcap");
  if (std::filesystem::exists(out)) throw Error(out.string() + ": already exists; choose another --out");
  const mcap::RecoveryResult result = mcap::recoverMcap(in.string(), out.string());
  std::printf("%s\n", nlohmann::json({{"recovered", out.string()},
                                      {"messages", result.messages},
                                      {"chunks", result.chunks_written},
                                      {"attachments", result.attachments},
                                      {"input_complete", result.input_complete},
                                      {"note", result.note}})
                          .dump()
                          .c_str());
  return config::kExitOk;
}

void sleepUntilNs(std::int64_t until_ns) {
  for (std::int64_t now = monotonicNowNs(); now < until_ns && !interrupted(); now = monotonicNowNs()) {
    std::this_thread::sleep_for(std::chrono::nanoseconds(std::min(until_ns - now, 20 * kNsPerMillisecond)));
  }
}

}  // namespace

int runRecord(const RecordOptions& options, std::unique_ptr<zr300::Zr300Backend> backend,
              std::unique_ptr<gpio_sync::GpioLineIo> line_io) {
  if (!options.recover.empty()) return recover(options);
  if (options.out.empty()) throw Error("--out FILE.mcap is required");
  if (std::filesystem::exists(options.out)) throw Error(options.out + ": already exists; choose another --out");
  if (options.mode != "rgbd" && options.mode != "rgbdi" && options.mode != "gyro") {
    throw Error("--mode '" + options.mode + "' is not one of: rgbd, rgbdi, gyro");
  }
  if (!(options.duration_s >= 0.0)) throw Error("--duration must be >= 0 s");
  const bool inertial = options.mode != "rgbd";
  const std::filesystem::path out_dir = std::filesystem::absolute(options.out).parent_path();
  RunSource source;
  if (!openRunSource({options.source, options.calibration, out_dir.string(), inertial, kRawTransferRing, {}, false},
                     "vifusion record", std::move(backend), source)) {
    return config::kExitSource;
  }
  datasets::DatasetReader& reader = *source.reader;
  std::unique_ptr<gpio_sync::SyncLine> sync_line;
  if (!options.gpio.empty()) {
    try {
      sync_line = openSyncLineSpec(options.gpio, options.edges, std::move(line_io));
    } catch (const std::exception& error) {
      std::fprintf(stderr, "vifusion record: %s\n", error.what());
      return config::kExitSource;
    }
  }

  recording::RecordingHeader header;
  header.source = options.source;
  header.mode = options.mode;
  header.calibration = reader.calibration();
  header.frame_rate_hz = kRecordedFrameRateHz;
  header.imu_rate_hz = source.imu != nullptr ? reader.calibration().imu.rate_hz : 0.0;
  header.t_ns = monotonicNowNs();
  recording::Recorder recorder(options.out, header, options.recorder);
  watchInterrupts(source);

  const std::int64_t duration_ns = secondsToNs(options.duration_s);
  const std::int64_t start_ns = monotonicNowNs();
  std::int64_t first_t_ns = 0, last_imu_t_ns = INT64_MIN;
  std::uint64_t frames = 0;
  RgbdFrame frame;
  gpio_sync::SyncEdge edge;
  while (!interrupted() && reader.nextFrame(frame)) {
    if (frames == 0) first_t_ns = frame.t_ns;
    if (duration_ns > 0 && frame.t_ns - first_t_ns > duration_ns) break;
    if (options.realtime && !reader.live()) sleepUntilNs(start_ns + (frame.t_ns - first_t_ns));
    if (source.imu != nullptr) {
      // Through the first sample after the frame (in IMU time), the one that covers it: what a live feed hands
      // the frame; a recorded source's feed hands the whole stream, a live one windows that overlap.
      const std::int64_t t_imu_ns = frame.t_ns + header.calibration.time_shift_cam_imu_ns;
      for (const ImuSample& sample : source.imu->samplesThrough(frame.t_ns)) {
        if (sample.t_ns <= last_imu_t_ns) continue;
        recorder.pushImu(sample);
        last_imu_t_ns = sample.t_ns;
        if (sample.t_ns > t_imu_ns) break;
      }
    }
    if (sync_line) {
      while (sync_line->edgeRing().tryPop(edge)) recorder.pushSyncEdge(edge.t_ns, edge.rising, edge.sequence);
    }
#ifdef VIFUSION_WITH_ZR300
    if (source.camera != nullptr) {
      const zr300::Zr300Stats stats = source.camera->stats();
      // The mapping as the module reports it: its offset at the newest sample, about this frame's time.
      recording::ClockRecord clock;
      clock.t_ns = frame.t_ns;
      clock.state = static_cast<std::uint8_t>(stats.motion.clock_state);
      clock.ref_host_ns = frame.t_ns;
      clock.ref_device_ns = frame.t_ns - stats.motion.clock_offset_ns;
      clock.skew = stats.motion.clock_skew_ppm * 1e-6;
      recorder.pushClock(clock);
      if (SpscRing<usb_imu::RawTransfer>* raw = source.camera->rawTransferRing()) {
        while (const usb_imu::RawTransfer* transfer = raw->front()) {
          recorder.pushMotionTransfer(transfer->host_receive_ns, transfer->index,
                                      std::span<const std::uint8_t>(transfer->bytes.data(), transfer->size));
          raw->pop();
        }
      }
    }
#endif
    // A recorded source waits for the recorder (nothing lost); a camera does not wait (losses are counted).
    while (!reader.live() && recorder.frameRingFull() && !recorder.stats().failed) {
      std::this_thread::sleep_for(std::chrono::nanoseconds(kWaitStepNs));
    }
    recorder.pushFrame(frame);
    ++frames;
    if (recorder.stats().failed) break;
  }
  forgetSource();
  if (sync_line) {
    sync_line->stop();
    while (sync_line->edgeRing().tryPop(edge)) recorder.pushSyncEdge(edge.t_ns, edge.rising, edge.sequence);
  }
  const bool ok = recorder.stop();
  const recording::RecorderStats stats = recorder.stats();
  const double wall_s = nsToSeconds(monotonicNowNs() - start_ns);
  std::printf("%s\n", nlohmann::json({{"out", options.out},
                                      {"source", options.source},
                                      {"frames", stats.written.frames},
                                      {"imu_samples", stats.written.imu_samples},
                                      {"sync_edges", stats.written.sync_edges},
                                      {"frames_dropped", stats.frames_dropped},
                                      {"imu_dropped", stats.imu_dropped},
                                      {"motion_packets", stats.written.motion_packets},
                                      {"bytes", stats.bytes_written},
                                      {"wall_s", wall_s},
                                      {"mb_per_s", wall_s > 0 ? stats.bytes_written / wall_s / 1e6 : 0.0},
                                      {"error", stats.error}})
                          .dump()
                          .c_str());
  if (!ok) {
    std::fprintf(stderr, "vifusion record: the recording failed: %s (what was written before is readable)\n",
                 stats.error.c_str());
    return config::kExitOutput;
  }
  return config::kExitOk;
}

int runRecord(const RecordOptions& options) { return runRecord(options, nullptr); }

}  // namespace vifusion::cli
