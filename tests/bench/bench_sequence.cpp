#include "bench_sequence.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <span>

#include "vifusion/core/error.hpp"
#include "vifusion/datasets/dataset_reader.hpp"

extern char** environ;

namespace vifusion::bench {
namespace {

/// Runs `vifusion sim` with its stdout sent to stderr (stdout may carry the benchmark's JSON).
void runSim(const Size& size, int frames, const std::filesystem::path& out) {
  // `sim` renders floor((duration − first stamp) / period) + 1 frames: half a period of margin.
  char duration[32];
  std::snprintf(duration, sizeof(duration), "%.6f", (frames - 0.5) / kFrameRateHz);
  std::vector<std::string> args = {options().vifusion,
                                   "sim",
                                   "--preset",
                                   kPreset,
                                   "--width",
                                   std::to_string(size.width),
                                   "--height",
                                   std::to_string(size.height),
                                   "--duration",
                                   duration,
                                   "--out",
                                   out.string()};
  if (!options().noise) args.push_back("--no-noise");
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  std::fprintf(stderr, "bench_rgbd_slam: generating %d frames of sim:%s at %s into %s\n", frames, kPreset,
               size.name().c_str(), out.c_str());
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, STDERR_FILENO, STDOUT_FILENO);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0)
    throw Error(options().vifusion + ": cannot be started (" + std::strerror(spawned) + "); give --vifusion=PATH");
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw Error("vifusion sim failed for " + out.string());
  }
}

/// The dataset directory of `size` holding at least `frames` frames, generated if missing or short.
std::filesystem::path datasetFor(const Size& size, int frames) {
  const std::filesystem::path dir = std::filesystem::path(options().data_dir) /
                                    (std::string(kPreset) + "_" + size.name() + (options().noise ? "" : "_no_noise"));
  if (std::filesystem::exists(dir / "rgb.txt")) {
    if (datasets::openDataset("dataset:" + dir.string())->frameCount() >= static_cast<std::size_t>(frames)) return dir;
  }
  // Written beside and renamed: an interrupted generation never looks complete.
  const std::filesystem::path partial = dir.string() + ".partial";
  std::filesystem::remove_all(partial);
  std::filesystem::create_directories(partial.parent_path());
  runSim(size, frames, partial);
  std::filesystem::remove_all(dir);
  std::filesystem::rename(partial, dir);
  return dir;
}

}  // namespace

const Sequence& sequenceFor(const Size& size) {
  static std::map<std::string, std::unique_ptr<Sequence>> cache;
  auto& slot = cache[size.name()];
  if (slot) return *slot;
  const int frames = options().frames;
  const auto reader = datasets::openDataset("dataset:" + datasetFor(size, frames).string());
  auto sequence = std::make_unique<Sequence>();
  sequence->calibration = reader->calibration();
  sequence->describe = reader->describe();
  sequence->frames.resize(static_cast<std::size_t>(frames));
  for (RgbdFrame& frame : sequence->frames) {
    if (!reader->nextFrame(frame)) throw Error("the dataset ran out of frames: " + reader->describe());
  }
  const std::span<const datasets::StampedPose> truth = reader->groundTruth();
  for (const RgbdFrame& frame : sequence->frames) {
    const auto it = std::lower_bound(truth.begin(), truth.end(), frame.t_ns,
                                     [](const datasets::StampedPose& pose, int64_t t_ns) { return pose.t_ns < t_ns; });
    if (it == truth.end() || it->t_ns != frame.t_ns)
      throw Error("no ground-truth pose at a frame's stamp: " + reader->describe());
    sequence->ground_truth.push_back({it->t_ns, it->T_world_body});
  }
  const std::span<const ImuSample> imu = reader->imu();
  sequence->imu.assign(imu.begin(), imu.end());
  slot = std::move(sequence);
  return *slot;
}

void writeTrajectory(const std::string& name, const std::vector<eval::StampedPose>& trajectory) {
  if (options().trajectory_dir.empty()) return;
  std::filesystem::create_directories(options().trajectory_dir);
  eval::writeTum(std::filesystem::path(options().trajectory_dir) / (name + ".txt"), trajectory);
}

}  // namespace vifusion::bench
