#include "vifusion/daemon/serve.hpp"

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <thread>

#include "vifusion/config/command_line.hpp"
#include "vifusion/core/imu_feed.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/daemon/frame_reader.hpp"
#include "vifusion/daemon/frame_source.hpp"
#include "vifusion/daemon/map_saver.hpp"
#include "vifusion/daemon/publisher.hpp"
#include "vifusion/daemon/recording_session.hpp"
#include "vifusion/daemon/slam_worker.hpp"
#include "vifusion/daemon/sync_line_source.hpp"
#include "vifusion/datasets/fault_injection.hpp"
#include "vifusion/dds/reader.hpp"
#include "vifusion/map/surfel.hpp"
#include "vifusion/service/log.hpp"
#include "vifusion/service/signal_fd.hpp"
#include "vifusion/service/systemd_notifier.hpp"

namespace vifusion::daemon {
namespace {

using service::LogLevel;
using service::logLine;

/// Shortest interval between two warnings about kernel-stamped frames [ns].
constexpr std::int64_t kKernelStampLogPeriodNs = 5 * kNsPerSecond;
/// Start-up steps may take this long each before systemd's TimeoutStartSec counts again [µs].
constexpr std::uint64_t kStartupStepUsec = 60'000'000;

const char* trackingText(const SharedState& state, bool ready) {
  if (!ready) return "initialising";
  if (state.relocalising.load()) return "relocalising into the loaded map";
  return state.lost_frames.load() > 0 ? "tracking (with lost frames)" : "tracking";
}

/// Loads config.map_file into `pipeline` (relocalising from the first frame). @returns false when the service
/// must not start: the file is missing or refused and map_file_required is true.
bool loadMapFile(const config::DaemonConfig& config, slam::Slam& pipeline) {
  std::string problem;
  std::error_code error;
  if (!std::filesystem::exists(config.map_file, error)) {
    problem = "no such file";
  } else {
    try {
      const slam::MapLoadReport loaded = pipeline.loadMap(config.map_file);
      logLine(LogLevel::Info,
              "map file %s loaded: %u surfels, %d keyframes, %s mode, %llu bytes in %.0f ms; relocalising (no pose "
              "published until the camera is located in it)",
              config.map_file.c_str(), loaded.surfels, loaded.keyframes, loaded.mode.c_str(),
              static_cast<unsigned long long>(loaded.bytes), loaded.elapsed_ms);
      return true;
    } catch (const std::exception& refused) {
      problem = refused.what();
    }
  }
  if (config.map_file_required) {
    logLine(LogLevel::Error,
            "map_file %s cannot be loaded: %s (map_file_required is true; set it false to start with an empty map)",
            config.map_file.c_str(), problem.c_str());
    return false;
  }
  if (problem != "no such file") {
    // The saves of this run would replace it: keep what was saved.
    const std::string kept = config.map_file + ".refused";
    std::filesystem::rename(config.map_file, kept, error);
    logLine(LogLevel::Warning, "map_file %s refused: %s; %s", config.map_file.c_str(), problem.c_str(),
            error ? ("it could not be moved aside (" + error.message() + ")").c_str() : ("kept as " + kept).c_str());
  }
  logLine(LogLevel::Warning, "map_file %s: starting with an empty map (map_file_required is false); it is saved there",
          config.map_file.c_str());
  return true;
}

/// Takes the rt/vifusion/map_save_request samples that arrived: the newest id goes to the SLAM thread, which
/// answers it in the status (map_save_request_done) once the save ends. Without a map file it is answered now.
void takeMapSaveRequests(dds::Reader<dds::msg::MapSaveRequest>& requests, const config::DaemonConfig& config,
                         SharedState& state) {
  requests.take([&](const dds::msg::MapSaveRequest& request) {
    if (request.request_id == 0) {
      logLine(LogLevel::Warning, "map save request with id 0 ignored: ids start at 1");
      return;
    }
    if (config.map_file.empty() || !config.mapping) {
      logLine(LogLevel::Warning, "map save request %llu: not saved, %s",
              static_cast<unsigned long long>(request.request_id),
              config.map_file.empty() ? "no map_file is configured" : "localisation only never changes the map");
      state.map_save_request_done = request.request_id;
      return;
    }
    logLine(LogLevel::Info, "map save request %llu: saving to %s after the current frame",
            static_cast<unsigned long long>(request.request_id), config.map_file.c_str());
    state.map_save_requested = std::max(state.map_save_requested.load(), request.request_id);
  });
}

}  // namespace

#ifdef VIFUSION_WITH_ZR300
int serve(const config::DaemonConfig& config) { return serve(config, nullptr); }

int serve(const config::DaemonConfig& config, std::unique_ptr<zr300::Zr300Backend> backend) {
#else
int serve(const config::DaemonConfig& config) {
#endif
  const service::SignalFd signals({SIGTERM, SIGINT, SIGHUP});
  const service::SystemdNotifier notifier;
  notifier.extendTimeout(kStartupStepUsec);
  notifier.status("opening the source");

  // The sync line first: it is checked in a moment, the source may take minutes (a sim: preset is generated).
  std::unique_ptr<gpio_sync::SyncLine> sync_line;
  if (!config.sync.chip.empty()) {
    try {
      sync_line = openSyncLine(config.sync);
    } catch (const std::exception& error) {
      logLine(LogLevel::Error, "sync line: %s", error.what());
      return config::kExitSource;
    }
    logLine(LogLevel::Info, "sync line: %s, %s edges", sync_line->lineName().c_str(), config.sync.edges.c_str());
  }

  slam::SlamOptions slam_options;
  slam_options.mode = slam::slamModeFromName(config.mode);  // validate() admitted only the valid names
  static_assert(config::kDefaultMapCapacity == map::kDefaultMapCapacity, "one default map capacity");
  slam_options.map.capacity = static_cast<std::uint32_t>(config.map_capacity);  // validate() bounded it
  slam_options.mapping = config.mapping;
  const bool inertial = slam_options.mode != slam::SlamMode::kRgbd;
  datasets::FaultPlan faults;  // config `inject`, parsed once: a typo is a configuration error
  try {
    faults = datasets::parseFaultPlan(config.inject, "inject");
  } catch (const std::exception& error) {
    logLine(LogLevel::Error, "%s", error.what());
    return config::kExitConfig;
  }
  OpenedSource opened;
  try {
#ifdef VIFUSION_WITH_ZR300
    opened = openSource(config, inertial, faults, std::move(backend));
#else
    opened = openSource(config, inertial, faults);
#endif
  } catch (const std::exception& error) {
    logLine(LogLevel::Error, "cannot open source '%s': %s", config.source.c_str(), error.what());
    return config::kExitSource;
  }
  const std::unique_ptr<datasets::DatasetReader>& source = opened.reader;
  logLine(LogLevel::Info, "source: %s", source->describe().c_str());
  // IMU rows the reader left out: each hole is a gap to the estimator (frames across it track RGB-D only).
  for (const std::string& reason : source->skippedImuRows()) {
    logLine(LogLevel::Warning, "IMU row unreadable, left out: %s", reason.c_str());
  }
  // The inertial modes need the source's IMU stream; without it, say so now rather than run RGB-D only.
  if (inertial && (source->live() ? opened.live_imu == nullptr : source->imu().empty())) {
    logLine(LogLevel::Error,
            "source '%s' has no IMU data, and mode '%s' needs it: use mode rgbd, or a source with IMU samples "
            "(dataset:DIR with imu.csv, sim:NAME)",
            config.source.c_str(), config.mode.c_str());
    return config::kExitSource;
  }
  if (inertial && !source->live()) {
    logLine(LogLevel::Info, "mode %s: %zu IMU samples", config.mode.c_str(), source->imu().size());
  }
  // Borrows the reader's stream: `source` outlives the SLAM thread, joined below.
  RecordedImuFeed recorded_imu(source->imu());
  ImuFeed* imu_feed = opened.live_imu != nullptr ? opened.live_imu : &recorded_imu;

  notifier.extendTimeout(kStartupStepUsec);
  notifier.status("building the GPU pipeline");
  std::unique_ptr<gpu::GpuContext> context;
  std::unique_ptr<slam::Slam> pipeline;
  try {
    gpu::GpuOptions gpu_options;
    gpu_options.device = config.device;
    context = gpu::GpuContext::create(gpu_options.withEnvironment());
    pipeline = std::make_unique<slam::Slam>(*context, source->calibration(), slam_options);
  } catch (const std::exception& error) {
    logLine(LogLevel::Error, "GPU pipeline: %s", error.what());
    return config::kExitGpu;
  }
  logLine(LogLevel::Info, "GPU: %s, arena %llu bytes (fixed from here on)", context->features().device_name.c_str(),
          static_cast<unsigned long long>(pipeline->arenaBytes()));
  if (!config.map_file.empty()) {
    notifier.status("loading the map file");
    if (!loadMapFile(config, *pipeline)) return config::kExitMap;
  }

  // Every camera ring slot sized for the calibration's images now: the reader never allocates.
  const PinholeCamera& camera = source->calibration().camera;
  FrameSlot prototype;
  prototype.frame.depth.resize(camera.width, camera.height);
  prototype.frame.rgb.resize(camera.width, camera.height);
  constexpr std::size_t kOutputRing = 64;
  SharedState state(static_cast<std::size_t>(config.frame_ring), prototype, kOutputRing);
  state.imu_samples_unreadable = source->skippedImuRows().size();

  std::unique_ptr<dds::Participant> participant;
  std::unique_ptr<Publisher> publisher;
  std::unique_ptr<dds::Reader<dds::msg::MapSaveRequest>> map_save_requests;
  try {
    participant = std::make_unique<dds::Participant>(
        dds::ParticipantOptions{config.dds.domain, config.dds.config, config.dds.partition});
    publisher = std::make_unique<Publisher>(*participant, config, slam_options.map.confidence_threshold,
                                            source->calibration().T_S_C, state);
    map_save_requests =
        std::make_unique<dds::Reader<dds::msg::MapSaveRequest>>(*participant, dds::topics::kMapSaveRequest);
  } catch (const std::exception& error) {
    logLine(LogLevel::Error, "DDS: %s", error.what());
    return config::kExitDds;
  }
  logLine(LogLevel::Info, "%s", participant->confinement().description.c_str());

  std::unique_ptr<recording::Recorder> recorder;
  try {
    recorder = openRecording(config, *source);
  } catch (const std::exception& error) {
    logLine(LogLevel::Error, "cannot record: %s", error.what());
    return config::kExitOutput;
  }
  bool recording_failure_reported = false;

  SlamWorkerOptions worker_options;
  worker_options.out_dir = config.out;
  worker_options.max_frames = static_cast<std::uint64_t>(config.max_frames);
  worker_options.map_period_ns = secondsToNs(config.map_publish_period_s);
  worker_options.expected_frames = source->live() ? kLiveTrajectoryReserveFrames : source->frameCount();
  worker_options.imu = inertial ? imu_feed : nullptr;
  worker_options.recorder = inertial ? recorder.get() : nullptr;
  worker_options.take_newest = config.realtime;
  std::unique_ptr<MapSaver> map_saver;
  if (!config.map_file.empty() && config.mapping) {  // localisation only never changes the map: no saves
    map_saver =
        std::make_unique<MapSaver>(config.map_file, slam_options.map.capacity, worker_options.expected_frames, state);
  }
  worker_options.map_saver = map_saver.get();
  worker_options.map_save_period_ns = secondsToNs(config.map_save_period_s);
  worker_options.mode = slam_options.mode;
  worker_options.calibration = &source->calibration();
  worker_options.gpu = context.get();
  worker_options.lose_device_at_frame = faults.deviceLostFrame();
  SlamWorker worker(*pipeline, slam_options.map, worker_options, state);

  notifier.status("waiting for the first frame");
  std::thread reader_thread([&] { runFrameReader(*source, config.realtime, state, recorder.get()); });
  std::thread slam_thread([&] { worker.run(); });
  std::thread publisher_thread([&] { publisher->run(); });

  bool ready = false;
  std::uint64_t petted_frames = 0;
  std::int64_t next_pet_ns = monotonicNowNs() + notifier.watchdogPeriodNs();
  std::int64_t next_status_ns = 0;
  std::int64_t next_extend_ns = monotonicNowNs();
  bool stopping = false;
  bool camera_present = true;
  std::int64_t camera_absent_since_ns = 0;
  std::uint64_t kernel_stamped_logged = 0;
  std::int64_t next_kernel_stamp_log_ns = 0;
  while (!state.slam_done) {
    const int signal = signals.wait(100);
    if (signal == SIGTERM || signal == SIGINT) {
      logLine(LogLevel::Info, "%s: finishing the current frame, writing trajectory.txt and map.ply%s",
              signal == SIGTERM ? "SIGTERM" : "SIGINT",
              config.map_file.empty() || !config.mapping ? "" : " and saving the map file");
      state.stop = true;
    } else if (signal == SIGHUP) {
      service::reopenLog();
      logLine(LogLevel::Info, "SIGHUP: log file reopened");
    }
    if (state.stop && !stopping) {
      stopping = true;
      notifier.stopping();
      if (opened.request_stop) opened.request_stop();  // a live source may be waiting for its camera
    }
    const std::int64_t now_ns = monotonicNowNs();
    takeMapSaveRequests(*map_save_requests, config, state);
    if (sync_line) reportSyncLine(*sync_line, state, recorder.get());
    if (recorder) reportRecording(*recorder, recording_failure_reported);
    if (opened.report) {
      opened.report(state);
      if (state.source_present.load() != camera_present) {
        camera_present = state.source_present.load();
        camera_absent_since_ns = now_ns;
        if (camera_present) {
          logLine(LogLevel::Info, "camera back: re-opened (%llu times so far), tracking resumes",
                  static_cast<unsigned long long>(state.source_reopens.load()));
        } else {
          logLine(LogLevel::Error, "camera gone (the map is kept; waiting for it to come back): %s",
                  opened.problem().c_str());
        }
        next_status_ns = 0;
      }
      // Frames without the motion module's event take the kernel's time, on another reference than the IMU's:
      // warn, at most once per kKernelStampLogPeriodNs.
      const std::uint64_t kernel_stamped = state.kernel_timestamp_frames.load();
      if (inertial && kernel_stamped > kernel_stamped_logged && now_ns >= next_kernel_stamp_log_ns) {
        logLine(LogLevel::Warning,
                "%llu frames so far stamped by the kernel: the motion module sent no event for them (clock mapping "
                "warming up after a start or re-open, or events lost)",
                static_cast<unsigned long long>(kernel_stamped));
        kernel_stamped_logged = kernel_stamped;
        next_kernel_stamp_log_ns = now_ns + kKernelStampLogPeriodNs;
      }
    }
    const std::uint64_t frames = state.frames_processed.load();
    if (!ready && frames > 0) {
      ready = true;
      notifier.ready();
      logLine(LogLevel::Info, "first frame processed: ready");
    }
    if (!ready && now_ns >= next_extend_ns) {  // the first frame may need the shaders JIT-compiled
      notifier.extendTimeout(kStartupStepUsec);
      next_extend_ns = now_ns + 10 * kNsPerSecond;
    }
    // Pet only on progress, or while the live camera is known to be unplugged (then no frame can come, and
    // the service is doing what it should: waiting for it); a stalled source or a hung GPU lets it fire.
    if (notifier.watchdogPeriodNs() > 0 && now_ns >= next_pet_ns) {
      if (frames != petted_frames || !camera_present) notifier.watchdog();
      petted_frames = frames;
      next_pet_ns = now_ns + notifier.watchdogPeriodNs();
    }
    if (now_ns >= next_status_ns && !camera_present) {
      char text[200];
      std::snprintf(text, sizeof(text), "camera absent for %.0f s (unplugged): map kept, %llu frames so far",
                    nsToSeconds(now_ns - camera_absent_since_ns), static_cast<unsigned long long>(frames));
      notifier.status(text);
      next_status_ns = now_ns + kNsPerSecond;
    }
    if (now_ns >= next_status_ns) {
      char text[256];
      const int length = std::snprintf(text, sizeof(text), "%s: %llu frames, %llu lost, camera ring overruns %llu",
                                       trackingText(state, ready), static_cast<unsigned long long>(frames),
                                       static_cast<unsigned long long>(state.lost_frames.load()),
                                       static_cast<unsigned long long>(state.frames.overruns()));
      if (inertial && length > 0 && static_cast<std::size_t>(length) < sizeof(text)) {
        std::snprintf(text + length, sizeof(text) - static_cast<std::size_t>(length),
                      ", %s: %llu IMU-carried, %llu frames without IMU", config.mode.c_str(),
                      static_cast<unsigned long long>(state.imu_carried_frames.load()),
                      static_cast<unsigned long long>(state.imu_issue_frames.load()));
      }
      if (recorder) appendRecordingStatus(*recorder, text, sizeof(text));
      notifier.status(text);
      next_status_ns = now_ns + kNsPerSecond;
    }
  }
  // The SLAM thread ended (stop, end of source, max_frames or failure): let the others finish.
  state.stop = true;
  if (opened.request_stop) opened.request_stop();
  reader_thread.join();
  slam_thread.join();
  publisher_thread.join();
  if (recorder) closeRecording(*recorder);
  const int code = state.exit_code.load();
  logLine(code == 0 ? LogLevel::Info : LogLevel::Error,
          "exiting with code %d after %llu frames (%llu lost); GPU arena %llu bytes", code,
          static_cast<unsigned long long>(state.frames_processed.load()),
          static_cast<unsigned long long>(state.lost_frames.load()),
          static_cast<unsigned long long>(pipeline->arenaBytes()));
  return code;
}

}  // namespace vifusion::daemon
