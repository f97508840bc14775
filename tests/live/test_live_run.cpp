// `vifusion run --source zr300` end to end (issue 17's acceptance): a scripted camera plays a recording —
// depth, colour and IMU as the ZR300 would deliver them — into the same runPipeline() the program runs, and the
// run's trajectory must match the run on that data replayed from files: same frames, same times to 1 µs, same
// poses, and the same estimator states (velocity, biases, gravity and their variances: they integrate every IMU
// sample, so they agree only if the same samples arrived with the same times). The recording is 30 s of the
// synthetic living room (320×240, IMU at 200 Hz) from this folder's fixture; what the camera cannot carry exactly
// (colour through YUYV, IMU readings in whole counts, times to whole µs) is applied to both sides first, and the
// file side is written as a dataset directory (DatasetWriter).

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "run_command.hpp"
#include "scripted_replay.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::live_test {
namespace {

struct Pose {
  double t_s = 0.0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector4d q = Eigen::Vector4d::Zero();
};

std::vector<Pose> readTum(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::vector<Pose> poses;
  std::string line;
  while (std::getline(file, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    Pose pose;
    fields >> pose.t_s >> pose.p.x() >> pose.p.y() >> pose.p.z() >> pose.q.x() >> pose.q.y() >> pose.q.z() >>
        pose.q.w();
    poses.push_back(pose);
  }
  return poses;
}

/// states.csv rows: the stamp [ns] and every estimator column after it.
std::vector<std::vector<double>> readStates(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(file, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<double> row;
    std::istringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) row.push_back(std::stod(field));
    rows.push_back(std::move(row));
  }
  return rows;
}

TEST(LiveRun, ScriptedCameraRunMatchesTheFilesRun) {
  const std::filesystem::path work = std::filesystem::path(VIFUSION_LIVE_RUN_DIR);
  std::filesystem::create_directories(work);
  // VIFUSION_LIVE_RUN_RECORDING replays another recording (a longer one, by hand; tests/bench/README.md).
  const char* recording = std::getenv("VIFUSION_LIVE_RUN_RECORDING");
  Replay replay = prepareReplay(recording != nullptr ? recording : VIFUSION_RECORDING_DIR, work);
  ASSERT_GT(replay.frames, 30u);

  cli::RunOptions files;
  files.source = "dataset:" + replay.files.string();
  files.mode = "rgbdi";
  files.out = (work / "run_files").string();
  ASSERT_EQ(cli::runPipeline(files), 0);

  cli::RunOptions live = files;
  live.source = "zr300";
  live.calibration = (replay.files / "calibration.yaml").string();
  live.out = (work / "run_zr300").string();
  live.max_frames = static_cast<int>(replay.frames);
  ASSERT_EQ(cli::runPipeline(live, std::make_unique<ScriptedCamera>(std::move(replay.script))), 0);

  const std::vector<Pose> from_files = readTum(std::filesystem::path(files.out) / "trajectory.txt");
  const std::vector<Pose> from_camera = readTum(std::filesystem::path(live.out) / "trajectory.txt");
  ASSERT_EQ(from_files.size(), replay.frames);
  ASSERT_EQ(from_camera.size(), from_files.size());
  double worst_dt_s = 0.0, worst_dp_m = 0.0, worst_dq = 0.0;
  for (std::size_t i = 0; i < from_files.size(); ++i) {
    worst_dt_s = std::max(worst_dt_s, std::abs(from_camera[i].t_s - from_files[i].t_s));
    worst_dp_m = std::max(worst_dp_m, (from_camera[i].p - from_files[i].p).norm());
    worst_dq = std::max(
        worst_dq, std::min((from_camera[i].q - from_files[i].q).norm(), (from_camera[i].q + from_files[i].q).norm()));
  }
  std::printf("%zu frames: worst time difference %.3g s, position %.3g m, quaternion %.3g\n", from_files.size(),
              worst_dt_s, worst_dp_m, worst_dq);
  EXPECT_LE(worst_dt_s, 1e-6);
  EXPECT_LE(worst_dp_m, 1e-6);
  EXPECT_LE(worst_dq, 1e-6);

  const auto states_files = readStates(std::filesystem::path(files.out) / "states.csv");
  const auto states_camera = readStates(std::filesystem::path(live.out) / "states.csv");
  ASSERT_EQ(states_files.size(), replay.frames);
  ASSERT_EQ(states_camera.size(), states_files.size());
  double worst_stamp_ns = 0.0, worst_state = 0.0;
  for (std::size_t i = 0; i < states_files.size(); ++i) {
    ASSERT_EQ(states_camera[i].size(), states_files[i].size()) << "states.csv row " << i;
    worst_stamp_ns = std::max(worst_stamp_ns, std::abs(states_camera[i][0] - states_files[i][0]));
    for (std::size_t k = 1; k < states_files[i].size(); ++k) {
      worst_state = std::max(worst_state, std::abs(states_camera[i][k] - states_files[i][k]));
    }
  }
  std::printf("states: worst stamp difference %.3g ns, worst value difference %.3g\n", worst_stamp_ns, worst_state);
  EXPECT_LE(worst_stamp_ns, 1000.0);
  EXPECT_LE(worst_state, 1e-6);
}

}  // namespace
}  // namespace vifusion::live_test
