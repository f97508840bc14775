#include "vifusion/daemon/frame_source.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <vector>

#include "vifusion/core/error.hpp"
#include "vifusion/datasets/fault_injection.hpp"
#include "vifusion/datasets/looped_replay.hpp"
#include "vifusion/datasets/recalibrated_reader.hpp"
#include "vifusion/recording/open_recorded.hpp"
#include "vifusion/service/log.hpp"
#ifdef VIFUSION_WITH_ZR300
#include "vifusion/discovery/source_spec.hpp"
#include "vifusion/zr300/open_zr300.hpp"
#endif

extern char** environ;

namespace vifusion::daemon {
namespace {

std::filesystem::path siblingProgram(const char* name) {
  return std::filesystem::read_symlink("/proc/self/exe").parent_path() / name;
}

void generateSim(const std::string& preset, const std::filesystem::path& dir) {
  const std::filesystem::path program = siblingProgram("vifusion");
  service::logLine(service::LogLevel::Info, "generating sim:%s into %s with %s", preset.c_str(), dir.c_str(),
                   program.c_str());
  std::filesystem::remove_all(dir);  // an interrupted earlier generation
  std::vector<std::string> args = {program.string(), "sim", "--preset", preset, "--out", dir.string()};
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, program.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
    throw Error("source 'sim:" + preset + "': cannot start " + program.string());
  }
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw Error("source 'sim:" + preset + "': `vifusion sim --preset " + preset + "` failed");
  }
}

}  // namespace

#ifdef VIFUSION_WITH_ZR300
OpenedSource openSource(const config::DaemonConfig& config, bool inertial, const datasets::FaultPlan& faults) {
  return openSource(config, inertial, faults, nullptr);
}

OpenedSource openSource(const config::DaemonConfig& config, bool inertial, const datasets::FaultPlan& faults,
                        std::unique_ptr<zr300::Zr300Backend> backend) {
#else
OpenedSource openSource(const config::DaemonConfig& config, bool inertial, const datasets::FaultPlan& faults) {
#endif
  OpenedSource opened;
  const std::string& source = config.source;
#ifdef VIFUSION_WITH_ZR300
  if (const std::optional<discovery::Zr300SourceSpec> spec = discovery::parseZr300SourceSpec(source)) {
    zr300::Zr300Options options;
    options.imu = inertial;  // rgbd mode leaves the motion module alone: frames take their kernel times
    std::unique_ptr<zr300::Zr300Source> camera =
        zr300::openZr300(*spec, config.calibration, options, std::move(backend));
    zr300::Zr300Source* live = camera.get();
    opened.live_imu = live->imuFeed();
    opened.request_stop = [live] { live->requestStop(); };
    opened.report = [live](SharedState& state) {
      const zr300::Zr300Stats stats = live->stats();
      state.source_present = stats.camera_present;
      state.source_reopens = stats.reopens;
      state.clock_offset_ns = stats.motion.clock_offset_ns;
      state.clock_skew_ppm = stats.motion.clock_skew_ppm;
      state.imu_ring_fill = live->imuRingFill();
      state.imu_ring_capacity = live->imuRingCapacity();
      state.imu_ring_overruns = stats.motion.imu_overruns;
      state.kernel_timestamp_frames = stats.kernel_timestamps;
    };
    opened.problem = [live] { return live->lastProblem(); };
    opened.reader = std::move(camera);
    return opened;
  }
#else
  (void)inertial;
  if (source.starts_with("zr300")) {
    throw Error("this vifusiond was built without the live drivers (VIFUSION_WITH_LIVE_DRIVERS=OFF)");
  }
#endif
  std::string recorded = source;
  if (source.starts_with("sim:")) {
    const std::string preset = source.substr(4);
    const std::filesystem::path dir = std::filesystem::path(config.out) / ("sim_" + preset);
    if (!std::filesystem::exists(dir / "rgb.txt")) generateSim(preset, dir);
    recorded = "dataset:" + dir.string();
  }
  const datasets::RecordingOpener open = [calibration = config.calibration, recorded] {
    std::unique_ptr<datasets::DatasetReader> reader = recording::openRecorded(recorded);
    if (!calibration.empty()) {  // the rig's calibration in place of the recording's own
      reader = datasets::withCalibrationFile(std::move(reader), calibration);
    }
    return reader;
  };
  opened.reader =
      config.replay_loops > 1 ? datasets::loopedReplay(open, static_cast<std::size_t>(config.replay_loops)) : open();
  if (!faults.empty()) opened.reader = datasets::withFaults(std::move(opened.reader), faults);
  // A frame or IMU sample whose time does not increase is passed over and counted like an unreadable one.
  opened.reader = datasets::withIncreasingTimes(std::move(opened.reader));
  return opened;
}

}  // namespace vifusion::daemon
