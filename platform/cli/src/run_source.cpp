#include "run_source.hpp"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "sim_command.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/datasets/recalibrated_reader.hpp"
#include "vifusion/recording/open_recorded.hpp"
#ifdef VIFUSION_WITH_ZR300
#include "vifusion/discovery/source_spec.hpp"
#include "vifusion/zr300/open_zr300.hpp"
#endif

namespace vifusion::cli {
namespace {

/// A `sim:NAME` source is generated once into <out>/sim_NAME and reused by later runs.
std::string datasetSpec(const SourceRequest& request) {
  if (request.spec.rfind("sim:", 0) != 0) return request.spec;
  const std::string preset = request.spec.substr(4);
  const std::filesystem::path dir = std::filesystem::path(request.out) / ("sim_" + preset);
  if (!std::filesystem::exists(dir / "rgb.txt")) {
    std::filesystem::remove_all(dir);  // an interrupted earlier generation
    SimOptions sim;
    sim.preset = preset;
    sim.out = dir.string();
    sim.quiet = true;
    runSim(sim);
  }
  return "dataset:" + dir.string();
}

/// Set by SIGINT/SIGTERM during a live run: the run ends after the current frame and writes its outputs.
std::atomic<bool> g_interrupted{false};
#ifdef VIFUSION_WITH_ZR300
/// The live camera, whose waiting nextFrame() the handler ends (requestStop() only stores a flag).
std::atomic<zr300::Zr300Source*> g_live_camera{nullptr};
#endif
extern "C" void onInterrupt(int) {
  g_interrupted.store(true);
#ifdef VIFUSION_WITH_ZR300
  if (zr300::Zr300Source* camera = g_live_camera.load()) camera->requestStop();
#endif
}

}  // namespace

bool openRunSource(const SourceRequest& request, const char* command, std::unique_ptr<zr300::Zr300Backend> backend,
                   RunSource& source) {
#ifdef VIFUSION_WITH_ZR300
  if (const std::optional<discovery::Zr300SourceSpec> spec = discovery::parseZr300SourceSpec(request.spec)) {
    if (!request.faults.empty()) throw Error("--inject: faults are replayed into recordings, not the live camera");
    zr300::Zr300Options live;
    live.imu = request.inertial;  // rgbd mode leaves the motion module alone: frames take their kernel times
    live.motion.raw_transfer_ring_capacity = request.raw_transfers;
    std::unique_ptr<zr300::Zr300Source> camera;
    try {
      camera = zr300::openZr300(*spec, request.calibration, live, std::move(backend));
    } catch (const std::exception& error) {
      std::fprintf(stderr, "%s: cannot open source '%s': %s\n", command, request.spec.c_str(), error.what());
      return false;
    }
    source.imu = camera->imuFeed();
    source.camera = camera.get();
    source.reader = std::move(camera);
    return true;
  }
#else
  (void)backend;
  if (request.spec.rfind("zr300", 0) == 0) {
    std::fprintf(stderr,
                 "%s: cannot open source '%s': this build has no live drivers "
                 "(configured with VIFUSION_WITH_LIVE_DRIVERS=OFF)\n",
                 command, request.spec.c_str());
    return false;
  }
#endif
  source.reader = recording::openRecorded(datasetSpec(request));
  if (!request.calibration.empty()) {
    source.reader = datasets::withCalibrationFile(std::move(source.reader), request.calibration);
  }
  if (!request.faults.empty()) source.reader = datasets::withFaults(std::move(source.reader), request.faults);
  // A frame or IMU sample whose time does not increase is passed over and counted like an unreadable one.
  if (request.time_order_guard) source.reader = datasets::withIncreasingTimes(std::move(source.reader));
  if (!source.reader->imu().empty()) {
    source.recorded_imu = std::make_unique<RecordedImuFeed>(source.reader->imu());
    source.imu = source.recorded_imu.get();
  }
  return true;
}

void watchInterrupts(RunSource& source) {
#ifdef VIFUSION_WITH_ZR300
  g_live_camera.store(source.camera);
#else
  (void)source;
#endif
  g_interrupted.store(false);
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
}

bool interrupted() { return g_interrupted.load(); }

void forgetSource() {
#ifdef VIFUSION_WITH_ZR300
  g_live_camera.store(nullptr);
#endif
}

}  // namespace vifusion::cli
