#include "vifusion/daemon/recording_session.hpp"

#include <cstdio>
#include <cstring>
#include <ctime>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/service/log.hpp"

namespace vifusion::daemon {
namespace {

using service::LogLevel;
using service::logLine;

/// Recordings of one start: vifusiond-YYYYmmddTHHMMSSZ.mcap (UTC wall clock, so files sort by start).
std::filesystem::path recordingPath(const std::filesystem::path& directory) {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char name[64];
  std::strftime(name, sizeof(name), "vifusiond-%Y%m%dT%H%M%SZ.mcap", &utc);
  std::filesystem::path path = directory / name;
  for (int n = 1; std::filesystem::exists(path); ++n) {  // restarted within the same second
    path = directory / (std::string(name, std::strlen(name) - 5) + "-" + std::to_string(n) + ".mcap");
  }
  return path;
}

}  // namespace

std::unique_ptr<recording::Recorder> openRecording(const config::DaemonConfig& config,
                                                   const datasets::DatasetReader& source) {
  if (!config.record) return nullptr;
  const std::filesystem::path directory = config.record_dir.empty() ? std::filesystem::path(config.out) / "recordings"
                                                                    : std::filesystem::path(config.record_dir);
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (error) throw Error("record_dir '" + directory.string() + "': cannot be created: " + error.message());
  recording::RecordingHeader header;
  header.source = config.source;
  header.mode = config.mode;
  header.calibration = source.calibration();
  header.imu_rate_hz = config.mode == "rgbd" ? 0.0 : source.calibration().imu.rate_hz;
  header.t_ns = monotonicNowNs();
  auto recorder = std::make_unique<recording::Recorder>(recordingPath(directory), header);
  logLine(LogLevel::Info, "recording to %s", recorder->path().c_str());
  return recorder;
}

void reportRecording(const recording::Recorder& recorder, bool& reported) {
  if (reported) return;
  const recording::RecorderStats stats = recorder.stats();
  if (!stats.failed) return;
  reported = true;
  logLine(LogLevel::Error,
          "recording stopped, mapping goes on: %s (the %llu messages of its complete chunks stay "
          "readable)",
          stats.error.c_str(), static_cast<unsigned long long>(stats.messages_in_chunks));
}

void appendRecordingStatus(const recording::Recorder& recorder, char* text, std::size_t size) {
  const std::size_t length = std::strlen(text);
  if (length + 1 >= size) return;
  const recording::RecorderStats stats = recorder.stats();
  if (stats.failed) {
    std::snprintf(text + length, size - length, ", recording stopped (failed)");
    return;
  }
  std::snprintf(text + length, size - length, ", recording: %llu frames, %llu lost",
                static_cast<unsigned long long>(stats.written.frames),
                static_cast<unsigned long long>(stats.frames_dropped + stats.imu_dropped + stats.edges_dropped +
                                                stats.motion_dropped + stats.clocks_dropped));
}

void closeRecording(recording::Recorder& recorder) {
  const bool ok = recorder.stop();
  const recording::RecorderStats stats = recorder.stats();
  logLine(ok ? LogLevel::Info : LogLevel::Error,
          "recording %s: %llu frames, %llu IMU samples, %llu sync edges, %.1f MB; not recorded (full rings, or after a "
          "failure): %llu frames, "
          "%llu IMU samples; recorder thread CPU %.3f s%s%s",
          recorder.path().c_str(), static_cast<unsigned long long>(stats.written.frames),
          static_cast<unsigned long long>(stats.written.imu_samples),
          static_cast<unsigned long long>(stats.written.sync_edges), static_cast<double>(stats.bytes_written) / 1e6,
          static_cast<unsigned long long>(stats.frames_dropped), static_cast<unsigned long long>(stats.imu_dropped),
          nsToSeconds(stats.thread_cpu_ns), ok ? "" : "; failed: ", ok ? "" : stats.error.c_str());
}

}  // namespace vifusion::daemon
