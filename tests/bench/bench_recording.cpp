// Recording while mapping (issue 18's acceptance: "Recording at 640×480 depth + colour at 30 Hz with IMU at
// 200 Hz keeps up on 2 cores while vifusiond maps; a benchmark reports MB/s, CPU time and dropped frames; none
// dropped"). In one process, as in vifusiond with `record: true` (record_while_mapping.py runs vifusiond itself):
//   - the SLAM thread runs slam::Slam (default SlamOptions, rgbd mode, as bench_rgbd_slam) on lavapipe over the
//     first --frames frames of sim:living_room_0 at --sizes (default 640x480), forwards then backwards so
//     the camera path stays continuous, as fast as it goes: lavapipe's workers load both cores;
//   - a producer thread plays the camera in real time: every 1/30 s a frame of the same sequence (depth and
//     colour at the size, stamped with the monotonic clock), every 1/200 s an IMU sample, and with each frame
//     a clock mapping (as `vifusion record` pushes), into a recording::Recorder with default options (chunks
//     flushed on the writer's time budget, write + fdatasync per chunk);
//   - the recorder's thread serialises and writes the MCAP file under --out_dir.
// The recording runs --seconds of wall time once SLAM has processed its first frames; then the recorder is
// stopped (summary written) and the file's summary is read back and its message counts compared.
//
//   bench_recording [--seconds=10] [--out_dir=DIR] [--keep=0] [--slam=1] [--frames=90] [--sizes=640x480]
//                   [--data_dir=DIR] [--vifusion=PATH] --benchmark_out=rec.json --benchmark_out_format=json
//
// Counters (one iteration = one recording):
//   seconds                wall time recorded [s]
//   mb_per_s               file bytes / seconds [MB/s, 10⁶ bytes]
//   recorder_cpu_ms_per_s  the recorder thread's CPU time per second recorded [ms/s] (1000 = one core)
//   process_cpu_ms_per_s   the whole process's CPU time per second (SLAM, lavapipe, producer, recorder) [ms/s]
//   machine_busy_ms_per_s, machine_iowait_ms_per_s, machine_steal_ms_per_s   all cores, from /proc/stat
//                          [ms/s, 2000 = both cores]: the kernel's writeback and other processes included
//   frames_pushed, frames_written, frames_dropped; imu_pushed, imu_written, imu_dropped
//   frames_in_file, imu_in_file   messages on the depth/colour (each) and IMU topics in the file's summary
//   fdatasync              1: SyncPolicy::kFdatasyncPerChunk (the default)
//   producer_late_ms       the producer's worst delay behind the camera's schedule [ms] (a starved producer
//                          would push fewer frames than the recorder could take)
//   stop_ms                recorder.stop(): the last drain, the summary and the close [ms]
//   slam_fps, slam_frames, slam_lost   SLAM frames per second during the recording, their count, lost ones
//   failed                 1 when the recording failed (the error is printed)

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "bench_options.hpp"
#include "bench_sequence.hpp"
#include "single_entry_main.hpp"
#include "timing.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/recording/recorder.hpp"
#include "vifusion/recording/topics.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion::bench {
namespace {

constexpr double kCameraRateHz = 30.0;  // the ZR300's depth + colour rate
constexpr double kImuRateHz = 200.0;    // its IMU rate
constexpr double kBytesPerMb = 1e6;
/// SLAM frames processed before the recording starts: the first starts the map, the next ones compile
/// nothing new but settle the map's size, so the load is steady while recording.
constexpr int kSlamWarmUpFrames = 3;
constexpr std::int64_t kWarmUpPollUs = 1000;
/// ClockRecord::state of a valid mapping (clock::ClockMapperState's order).
constexpr std::uint8_t kClockValid = 2;

struct RecordingFlags {
  double seconds = 10.0;                               ///< wall time recorded [s]
  std::string out_dir = VIFUSION_BENCH_RECORDING_DIR;  ///< where the recording is written
  bool keep = false;                                   ///< keep the file (≈ 46 MB per second at 640×480)
  bool slam = true;                                    ///< map meanwhile (0: the recorder alone)
};

RecordingFlags& flags() {
  static RecordingFlags instance;
  return instance;
}

/// Takes this program's own flags out of argv; bench_options' and Google Benchmark's stay.
void parseRecordingFlags(int& argc, char** argv) {
  constexpr double kMaxSeconds = 3600.0;
  RecordingFlags& f = flags();
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    std::string value;
    if (takeFlag(argv[i], "--seconds", value)) {
      char* end = nullptr;
      f.seconds = std::strtod(value.c_str(), &end);
      if (*end != '\0' || !(f.seconds > 0.0 && f.seconds <= kMaxSeconds)) {
        throw Error("--seconds: expected (0, 3600], got '" + value + "'");
      }
    } else if (takeFlag(argv[i], "--out_dir", value)) {
      f.out_dir = value;
    } else if (takeFlag(argv[i], "--keep", value)) {
      f.keep = parseBoolFlag("--keep", value);
    } else if (takeFlag(argv[i], "--slam", value)) {
      f.slam = parseBoolFlag("--slam", value);
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
}

/// The SLAM thread: frames 0, 1, …, n−1, n−2, …, 1, 0, 1, … (a continuous camera path), restamped on a 30 Hz
/// clock of its own, until `stop`.
class MappingLoad {
 public:
  MappingLoad(const Sequence& sequence, const std::atomic<bool>& stop) : sequence_(sequence), stop_(stop) {
    thread_ = std::thread([this] { run(); });
  }
  ~MappingLoad() { join(); }
  MappingLoad(const MappingLoad&) = delete;
  MappingLoad& operator=(const MappingLoad&) = delete;

  int frames() const { return frames_.load(); }
  int lost() const { return lost_.load(); }
  void join() {
    if (thread_.joinable()) thread_.join();
  }
  /// What stopped the thread early, if anything (read after join()).
  const std::string& error() const { return error_; }

 private:
  void run() {
    try {
      slam::Slam pipeline(context(), sequence_.calibration, slam::SlamOptions{});
      const std::int64_t period_ns = secondsToNs(1.0 / kCameraRateHz);
      RgbdFrame frame;
      for (std::int64_t j = 0; !stop_.load(); ++j) {
        frame = sequence_.frames[pingPongFrame(sequence_.frames.size(), j)];
        frame.t_ns = j * period_ns;
        frame.index = j;
        lost_ += pipeline.process(frame).lost() ? 1 : 0;
        ++frames_;
      }
    } catch (const std::exception& e) {
      error_ = e.what();
      frames_ = -1;
    }
  }

  const Sequence& sequence_;
  const std::atomic<bool>& stop_;
  std::atomic<int> frames_{0};
  std::atomic<int> lost_{0};
  std::string error_;
  std::thread thread_;
};

struct ProducerResult {
  std::uint64_t frames = 0;
  std::uint64_t imu = 0;
  double worst_late_ms = 0.0;
};

/// Plays the camera in real time for `seconds`: frames at 30 Hz, IMU at 200 Hz, a clock mapping per frame.
ProducerResult produce(recording::Recorder& recorder, const Sequence& sequence, double seconds) {
  using Clock = std::chrono::steady_clock;
  const auto frame_period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / kCameraRateHz));
  const auto imu_period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / kImuRateHz));
  const auto start = Clock::now();
  const auto end = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  ProducerResult result;
  RgbdFrame frame = sequence.frames.front();
  ImuSample sample;
  sample.accel_mps2 = -sequence.calibration.g_W;
  while (true) {
    const auto frame_due = start + static_cast<Clock::rep>(result.frames) * frame_period;
    const auto imu_due = start + static_cast<Clock::rep>(result.imu) * imu_period;
    const auto due = std::min(frame_due, imu_due);
    if (due >= end) break;
    std::this_thread::sleep_until(due);
    result.worst_late_ms = std::max(result.worst_late_ms, msSince(due));
    if (imu_due <= frame_due) {
      sample.t_ns = monotonicNowNs();
      recorder.pushImu(sample);
      ++result.imu;
    } else {
      frame = sequence.frames[result.frames % sequence.frames.size()];
      frame.t_ns = monotonicNowNs();
      frame.index = static_cast<std::int64_t>(result.frames);
      recording::ClockRecord clock;
      clock.t_ns = frame.t_ns;
      clock.state = kClockValid;
      clock.ref_host_ns = frame.t_ns;
      clock.ref_device_ns = frame.t_ns;
      recorder.pushClock(clock);
      recorder.pushFrame(frame);
      ++result.frames;
    }
  }
  return result;
}

/// The machine's CPU time by kind, all cores, from /proc/stat [ms]: the kernel's writeback and the disk's
/// interrupts run outside this process, and a VM's host may take time (steal).
struct MachineCpu {
  double busy_ms = 0.0;    ///< user, nice, system, irq, softirq, steal
  double iowait_ms = 0.0;  ///< idle with I/O outstanding
  double steal_ms = 0.0;   ///< taken by the hypervisor
};

MachineCpu machineCpu() {
  std::ifstream stat("/proc/stat");
  std::string cpu;
  double user = 0, nice = 0, system = 0, idle = 0, iowait = 0, irq = 0, softirq = 0, steal = 0;
  stat >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq >> steal;
  const double ms_per_tick = 1000.0 / static_cast<double>(sysconf(_SC_CLK_TCK));
  return {(user + nice + system + irq + softirq + steal) * ms_per_tick, iowait * ms_per_tick, steal * ms_per_tick};
}

/// Messages on `topic` in the file's summary (or scan).
std::uint64_t messagesOn(const mcap::McapReader& reader, std::string_view topic) {
  std::uint64_t count = 0;
  for (const mcap::ChannelInfo& channel : reader.channels()) {
    if (channel.topic != topic) continue;
    const auto& counts = reader.statistics().channel_message_counts;
    const auto it = counts.find(channel.id);
    if (it != counts.end()) count += it->second;
  }
  return count;
}

void recordWhileMapping(benchmark::State& state, Size size) {
  const RecordingFlags& f = flags();
  const Sequence& sequence = sequenceFor(size);
  std::filesystem::create_directories(f.out_dir);
  const std::filesystem::path path = std::filesystem::path(f.out_dir) / ("recording_" + size.name() + ".mcap");
  for (auto _ : state) {
    std::filesystem::remove(path);
    std::atomic<bool> stop_mapping{false};
    std::unique_ptr<MappingLoad> mapping;
    if (f.slam) {
      mapping = std::make_unique<MappingLoad>(sequence, stop_mapping);
      while (mapping->frames() >= 0 && mapping->frames() < kSlamWarmUpFrames) {
        std::this_thread::sleep_for(std::chrono::microseconds(kWarmUpPollUs));
      }
    }
    recording::RecordingHeader header;
    header.source = std::string("sim:") + kPreset;
    header.mode = "rgbd";
    header.calibration = sequence.calibration;
    header.frame_rate_hz = kCameraRateHz;
    header.imu_rate_hz = kImuRateHz;
    header.t_ns = monotonicNowNs();
    const recording::RecorderOptions recorder_options;
    recording::Recorder recorder(path, header, recorder_options);

    const int slam_before = mapping ? mapping->frames() : 0;
    const double cpu_before_ms = processCpuMs();
    const MachineCpu machine_before = machineCpu();
    const auto start = std::chrono::steady_clock::now();
    const ProducerResult produced = produce(recorder, sequence, f.seconds);
    const double seconds = msSince(start) / 1e3;
    const double process_cpu_ms = processCpuMs() - cpu_before_ms;
    const MachineCpu machine_after = machineCpu();
    const int slam_frames = mapping ? mapping->frames() - slam_before : 0;
    const recording::RecorderStats running = recorder.stats();
    const auto stop_start = std::chrono::steady_clock::now();
    recorder.stop();
    const double stop_ms = msSince(stop_start);
    stop_mapping.store(true);
    int slam_lost = 0;
    if (mapping) {
      mapping->join();
      slam_lost = mapping->lost();
      if (!mapping->error().empty())
        std::fprintf(stderr, "bench_recording: SLAM stopped: %s\n", mapping->error().c_str());
    }
    const recording::RecorderStats stats = recorder.stats();
    if (stats.failed) std::fprintf(stderr, "bench_recording: the recording failed: %s\n", stats.error.c_str());

    const mcap::McapReader reader(path.string());
    auto& c = state.counters;
    c["seconds"] = seconds;
    c["mb_per_s"] = static_cast<double>(stats.bytes_written) / kBytesPerMb / seconds;
    c["recorder_cpu_ms_per_s"] = static_cast<double>(running.thread_cpu_ns) * 1e-6 / seconds;
    c["process_cpu_ms_per_s"] = process_cpu_ms / seconds;
    c["machine_busy_ms_per_s"] = (machine_after.busy_ms - machine_before.busy_ms) / seconds;
    c["machine_iowait_ms_per_s"] = (machine_after.iowait_ms - machine_before.iowait_ms) / seconds;
    c["machine_steal_ms_per_s"] = (machine_after.steal_ms - machine_before.steal_ms) / seconds;
    c["frames_pushed"] = static_cast<double>(produced.frames);
    c["frames_written"] = static_cast<double>(stats.written.frames);
    c["frames_dropped"] = static_cast<double>(stats.frames_dropped);
    c["imu_pushed"] = static_cast<double>(produced.imu);
    c["imu_written"] = static_cast<double>(stats.written.imu_samples);
    c["imu_dropped"] = static_cast<double>(stats.imu_dropped);
    c["frames_in_file"] = static_cast<double>(
        std::min(messagesOn(reader, recording::kTopicDepth), messagesOn(reader, recording::kTopicColour)));
    c["imu_in_file"] = static_cast<double>(messagesOn(reader, recording::kTopicImu));
    c["summary_used"] = reader.summaryUsed() ? 1.0 : 0.0;
    c["fdatasync"] = recorder_options.mcap.sync == mcap::SyncPolicy::kFdatasyncPerChunk ? 1.0 : 0.0;
    c["producer_late_ms"] = produced.worst_late_ms;
    c["stop_ms"] = stop_ms;
    c["slam_frames"] = slam_frames;
    c["slam_fps"] = slam_frames / seconds;
    c["slam_lost"] = slam_lost;
    c["failed"] = stats.failed ? 1.0 : 0.0;
    state.SetLabel(size.name() + (f.slam ? " while mapping on " + context().features().device_name : " alone"));
    if (!f.keep) std::filesystem::remove(path);
  }
}

}  // namespace
}  // namespace vifusion::bench

int main(int argc, char** argv) {
  vifusion::bench::options().sizes = {{640, 480}};  // the size; --sizes overrides
  vifusion::bench::SingleEntry entry;
  entry.program = "bench_recording";
  entry.family = "recording";
  entry.parse_own_flags = vifusion::bench::parseRecordingFlags;
  entry.run = vifusion::bench::recordWhileMapping;
  return vifusion::bench::runSingleEntry(argc, argv, entry);
}
