#include "scripted_replay.hpp"

#include <memory>
#include <vector>

#include "dataset_writer.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/datasets/kalibr.hpp"

namespace vifusion::live_test {
namespace {

/// IMU before the recording's first sample: the clock mapping's 2 s warm-up and the gravity window.
constexpr std::int64_t kImuLeadNs = 2'500'000'000;
constexpr std::int64_t kImuPeriodNs = 5'000'000;

}  // namespace

Replay prepareReplay(const std::filesystem::path& recording, const std::filesystem::path& work) {
  const auto reader = datasets::openDataset("dataset:" + recording.string());
  const RigCalibration& calibration = reader->calibration();
  Replay replay;
  CameraScript& script = replay.script;
  script.preset = {calibration.camera.width, calibration.camera.height, 30};
  script.depth_units_um = 200;
  if (calibration.depth_scale_m != script.depth_units_um / 1e6) {
    throw Error(recording.string() + ": depth_scale_m is not the camera's 200 um unit");
  }

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
  // The simulator renders depth in the colour camera's pixels: the scripted ZR300's depth camera is the
  // colour camera itself (an identity registration, which preprocessing skips).
  RigCalibration rig = calibration;
  rig.depth_camera = DepthCameraCalibration{calibration.camera, SE3d()};
  datasets::writeCalibrationYaml(replay.files / "calibration.yaml", rig);
  return replay;
}

}  // namespace vifusion::live_test
