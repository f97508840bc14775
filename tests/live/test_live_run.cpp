// `vifusion run --source zr300` end to end (issue 17's acceptance): a scripted camera plays a recording —
// depth, colour and IMU as the ZR300 would deliver them — into the same runPipeline() the program runs, and the
// run's trajectory must match the run on that data replayed from files: same frames, same times to 1 µs, same
// poses. The recording is the synthetic living room (2 s, 320×240, IMU at 200 Hz) from the integration fixture;
// what the camera cannot carry exactly (colour through YUYV, IMU readings in whole counts, times to whole µs) is
// applied to both sides first, and the file side is written as a dataset directory (DatasetWriter).

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dataset_writer.hpp"
#include "run_command.hpp"
#include "scripted_camera.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/datasets/kalibr.hpp"

namespace vifusion::live_test {
namespace {

/// The recording's times start at 0; the camera's clock is an uptime.
constexpr std::int64_t kUptimeNs = 1'000'000'000'000;
/// IMU before the recording's first sample: the clock mapping's 2 s warm-up and the gravity window.
constexpr std::int64_t kImuLeadNs = 2'500'000'000;
constexpr std::int64_t kImuPeriodNs = 5'000'000;

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

/// The recording as the camera plays it, and the same data written as a dataset directory.
struct Replay {
  CameraScript script;
  std::filesystem::path files;  ///< the dataset directory of what the camera delivers
  std::size_t frames = 0;
};

Replay prepare(const std::filesystem::path& recording, const std::filesystem::path& work) {
  const auto reader = datasets::openDataset("dataset:" + recording.string());
  const RigCalibration& calibration = reader->calibration();
  Replay replay;
  CameraScript& script = replay.script;
  script.preset = {calibration.camera.width, calibration.camera.height, 30};
  script.depth_units_um = 200;
  EXPECT_DOUBLE_EQ(calibration.depth_scale_m, 200 / 1e6) << "the recording's depth unit must be the camera's";

  // Frames: depth inside the DS4 padding, colour as YUYV decodes it, times on the uptime clock.
  auto depth = std::make_shared<std::vector<Image<std::uint16_t>>>();
  auto colour = std::make_shared<std::vector<Image<Rgb8>>>();
  RgbdFrame frame;
  while (reader->nextFrame(frame)) {
    script.frame_t_ns.push_back(kUptimeNs + frame.t_ns);
    depth->push_back(frame.depth);
    colour->push_back(frame.rgb);
  }
  replay.frames = depth->size();
  const int pad = zr300::kDepthPaddingPx;
  script.depth = [depth, pad](int k, ImageView<std::uint16_t> inner) {
    const Image<std::uint16_t>& full = (*depth)[static_cast<std::size_t>(k)];
    for (int y = 0; y < inner.height; ++y) {
      for (int x = 0; x < inner.width; ++x) inner(x, y) = full(x + pad, y + pad);
    }
  };
  script.colour = [colour](int k, ImageView<Rgb8> rgb) {
    const Image<Rgb8>& full = (*colour)[static_cast<std::size_t>(k)];
    for (int y = 0; y < rgb.height; ++y) {
      for (int x = 0; x < rgb.width; ++x) rgb(x, y) = full(x, y);
    }
  };
  // IMU in whole counts; before the recording, its first reading repeated (the camera held still).
  const std::span<const ImuSample> imu = reader->imu();
  for (std::int64_t t = imu.front().t_ns - kImuLeadNs; t < imu.front().t_ns; t += kImuPeriodNs) {
    RawImu raw = toRawImu(imu.front());
    raw.t_ns = kUptimeNs + t;
    script.imu.push_back(raw);
  }
  for (const ImuSample& sample : imu) {
    RawImu raw = toRawImu(sample);
    raw.t_ns += kUptimeNs;
    script.imu.push_back(raw);
  }

  // The same, as files.
  replay.files = work / "delivered";
  std::filesystem::remove_all(replay.files);
  cli::DatasetWriter writer(replay.files);
  Image<std::uint16_t> padded(script.preset.width_px, script.preset.height_px);
  Image<Rgb8> rgb(script.preset.width_px, script.preset.height_px), delivered(rgb.width(), rgb.height());
  const std::span<const datasets::StampedPose> truth = reader->groundTruth();
  for (std::size_t k = 0; k < replay.frames; ++k) {
    const int ki = static_cast<int>(k);
    padded = Image<std::uint16_t>(padded.width(), padded.height());
    script.depth(ki, ImageView<std::uint16_t>(padded.data() + pad * padded.width() + pad, padded.width() - 2 * pad,
                                              padded.height() - 2 * pad, padded.width()));
    script.colour(ki, rgb.view());
    expectedRgb(rgb.view(), kFirstFrameCounter + static_cast<std::uint32_t>(k), delivered.view());
    const SE3d T_W_C = k < truth.size() ? truth[k].T_world_body : SE3d();
    writer.writeFrame(script.frame_t_ns[k], delivered.view(), padded.view(), T_W_C);
  }
  std::vector<ImuSample> samples;
  for (const RawImu& raw : script.imu) samples.push_back(toImuSample(raw));
  writer.writeImu(samples);
  writer.finish();
  datasets::writeCalibrationYaml(replay.files / "calibration.yaml", calibration);
  return replay;
}

TEST(LiveRun, ScriptedCameraRunMatchesTheFilesRun) {
  const std::filesystem::path work = std::filesystem::path(VIFUSION_LIVE_RUN_DIR);
  std::filesystem::create_directories(work);
  Replay replay = prepare(VIFUSION_RECORDING_DIR, work);
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
}

}  // namespace
}  // namespace vifusion::live_test
