#include "sim_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "dataset_writer.hpp"
#include "progress_bar.hpp"
#include "recording_sequence_writer.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/datasets/kalibr.hpp"
#include "vifusion/eval/trajectory_io.hpp"
#include "vifusion/scene/living_room.hpp"
#include "vifusion/scene/renderer.hpp"
#include "vifusion/scene/row_pool.hpp"
#include "vifusion/scene/sensor_noise.hpp"
#include "vifusion/scene/sensor_resolution.hpp"
#include "vifusion/sim/imu_simulator.hpp"
#include "vifusion/sim/presets.hpp"
#include "vifusion/sim/trajectory_fit.hpp"

namespace vifusion::cli {
namespace {

/// `--out` with this extension writes a recording instead of a dataset directory.
constexpr const char* kRecordingExtension = ".mcap";

constexpr int64_t kFramePeriodNs = 33'333'333;  // 30 Hz, as ICL-NUIM

/// Camera → IMU of a ZR300-like rig: a few centimetres of lever arm and a slight misalignment, so
/// that estimators cannot get away with ignoring the extrinsic.
SE3d defaultT_S_C() { return SE3d(expSO3(Eigen::Vector3d(0.01, -0.02, 0.005)), Eigen::Vector3d(0.045, -0.008, 0.004)); }

std::filesystem::path dataDirectory(const SimOptions& options) {
  if (!options.data_dir.empty()) return options.data_dir;
  if (const char* env = std::getenv("VIFUSION_DATA_DIR"); env != nullptr && env[0] != '\0') return env;
  return VIFUSION_DEFAULT_DATA_DIR;
}

/// The camera path as stamped T_W_C poses.
std::vector<sim::StampedPose> cameraPath(const SimOptions& options) {
  std::vector<sim::StampedPose> poses;
  if (!options.preset.empty() && !options.trajectory.empty()) throw Error("give --preset or --trajectory, not both");
  if (options.preset.rfind("living_room_", 0) == 0) {
    const std::string index = options.preset.substr(12);
    if (index.size() != 1 || index[0] < '0' || index[0] > '3') {
      throw Error("unknown preset '" + options.preset + "' (living_room_0..3)");
    }
    const auto file = dataDirectory(options) / "icl-nuim-trajectories" / ("livingRoom" + index + ".tum.txt");
    for (const eval::StampedPose& pose : eval::readTum(file)) poses.push_back({pose.t_ns, pose.T_world_body});
  } else if (!options.preset.empty()) {
    poses = sim::presetCameraPoses(options.preset);
  } else if (!options.trajectory.empty()) {
    for (const eval::StampedPose& pose : eval::readTum(options.trajectory))
      poses.push_back({pose.t_ns, pose.T_world_body});
  } else {
    throw Error("give --preset NAME or --trajectory FILE");
  }
  return poses;
}

/// The writer for `--out`: a recording for FILE.mcap, a dataset directory otherwise.
std::unique_ptr<SequenceWriter> openSequenceWriter(const SimOptions& options) {
  const std::filesystem::path out = options.out;
  if (out.extension() == kRecordingExtension) {
    return std::make_unique<RecordingSequenceWriter>(
        out, options.preset.empty() ? "sim:trajectory " + options.trajectory : "sim:" + options.preset);
  }
  return std::make_unique<DatasetWriter>(out);
}

nlohmann::json residualsJson(const sim::FitResiduals& r) {
  return {{"poses", r.count},
          {"rms_position_mm", r.rms_position_mm},
          {"max_position_mm", r.max_position_mm},
          {"rms_rotation_deg", r.rms_rotation_deg},
          {"max_rotation_deg", r.max_rotation_deg}};
}

/// The ground truth must be the path that was asked for: a fit beyond sim::FitTolerance at its own samples is
/// refused, naming the worst of them.
void requireFitFollowsPath(const sim::TrajectoryFit& fit, const std::vector<sim::StampedPose>& path, int stride) {
  const sim::FitTolerance tolerance;
  if (sim::withinTolerance(fit.at_samples, tolerance)) return;
  const sim::FitResiduals& r = fit.at_samples;
  const bool rotation = r.max_rotation_deg > tolerance.max_rotation_deg;
  const int64_t t_ns = rotation ? r.max_rotation_t_ns : r.max_position_t_ns;
  const auto pose = std::find_if(path.begin(), path.end(), [&](const sim::StampedPose& p) { return p.t_ns == t_ns; });
  std::ostringstream message;
  message << std::fixed << std::setprecision(6) << "the ground-truth spline through one pose in " << stride
          << " cannot follow the path: it misses pose " << (pose - path.begin()) << " (t = " << nsToSeconds(t_ns)
          << " s) by " << std::setprecision(3) << (rotation ? r.max_rotation_deg : r.max_position_mm)
          << (rotation ? "°" : " mm") << ", beyond the "
          << (rotation ? tolerance.max_rotation_deg : tolerance.max_position_mm) << (rotation ? "°" : " mm")
          << " tolerance (worst: " << r.max_position_mm << " mm, " << r.max_rotation_deg << "°); ";
  if (stride > 1) {
    message << "the path moves too fast for that stride: fit more densely with --fit-stride N (N < " << stride << ")";
  } else {
    message << "even through every pose: the path jumps between its poses; smooth or resample it first";
  }
  throw Error(message.str());
}

}  // namespace

int runSim(const SimOptions& options) {
  if (options.out.empty()) throw Error("--out DIR is required");
  if (!(options.cover_start_s >= 0.0) || !(options.cover_s >= 0.0) || !std::isfinite(options.cover_start_s) ||
      !std::isfinite(options.cover_s)) {
    throw Error("--cover START SECONDS: both must be finite and ≥ 0 s");
  }
  if (options.up != "y" && options.up != "z") throw Error("--up must be 'y' or 'z', got '" + options.up + "'");
  if (options.width % 2 != 0 || options.width < 16 || options.height < 16) {
    throw Error("--width must be even and both sizes at least 16 px");
  }
  const auto start = std::chrono::steady_clock::now();

  // Ground truth: the IMU-body spline through every 10th camera pose.
  const std::vector<sim::StampedPose> path = cameraPath(options);
  const bool synthetic_preset = !options.preset.empty() && options.preset.rfind("living_room_", 0) != 0;
  const sim::PresetTraits traits = synthetic_preset ? sim::presetTraits(options.preset) : sim::PresetTraits{};
  sim::TrajectoryFitOptions fit_options;
  fit_options.subsample = options.fit_stride > 0 ? options.fit_stride : traits.fit_subsample;
  const sim::TrajectoryFit fit = sim::fitTrajectory(path, defaultT_S_C(), fit_options);
  requireFitFollowsPath(fit, path, fit_options.subsample);

  RigCalibration calibration;
  const double scale = options.width / 640.0;
  calibration.camera = PinholeCamera::create(options.width, options.height, 481.2 * scale, 480.0 * scale,
                                             0.5 * options.width - 0.5, 0.5 * options.height - 0.5);
  calibration.depth_scale_m = 1.0 / 5000.0;
  calibration.T_S_C = fit.T_S_C;
  calibration.imu = ImuNoiseParams::preset(options.imu);
  calibration.g_W = options.up == "z" ? Eigen::Vector3d(0, 0, -calibration.imu.gravity_mps2)
                                      : Eigen::Vector3d(0, -calibration.imu.gravity_mps2, 0);

  int64_t t_end_ns = fit.last_pose_ns;
  if (options.duration_s > 0.0) t_end_ns = std::min(t_end_ns, fit.first_pose_ns + secondsToNs(options.duration_s));

  sim::ImuSimOptions imu_options;
  imu_options.noise = calibration.imu;
  imu_options.g_W_mps2 = calibration.g_W;
  imu_options.seed = options.seed;
  imu_options.add_noise = options.noise;
  imu_options.add_biases = options.biases;
  imu_options.t_end_ns = t_end_ns;
  const sim::ImuSimResult imu = sim::simulateImu(fit.spline_W_S, imu_options);

  const std::unique_ptr<SequenceWriter> output = openSequenceWriter(options);
  SequenceWriter& writer = *output;
  writer.writeCalibration(calibration);
  writer.writeImu(imu.samples);
  writer.writeGroundTruthStates(imu.states);

  // Images at 30 Hz along the spline; stamps on whole microseconds so TUM text files hold them exactly.
  const int blur_samples =
      options.motion_blur_samples >= 0 ? options.motion_blur_samples : (traits.motion_blur ? 5 : 0);
  constexpr int64_t kExposureNs = 10'000'000;  // sub-frame renders span 10 ms around the frame time
  scene::LivingRoom room;
  scene::RowPool pool;
  scene::RenderOptions render_options;
  render_options.depth_scale = 1.0 / calibration.depth_scale_m;
  scene::Renderer renderer(room, pool, render_options);
  scene::SensorNoiseOptions noise_options;
  noise_options.seed = options.seed;
  noise_options.intensity_sigma = options.imu == "zr300" ? 1.0 : 4.0;  // Table I image intensity noise
  noise_options.depth_scale = render_options.depth_scale;
  scene::SensorNoise noise(noise_options, pool);

  const PinholeCamera& camera = calibration.camera;
  Image<Rgb8> rgb(camera.width, camera.height);
  Image<uint16_t> depth(camera.width, camera.height);
  // Noisy depth comes from the sensor's native resolution (sensor_resolution.hpp), colour from `camera`.
  const int subsampling = scene::sensorSubsampling(camera);
  const PinholeCamera sensor_camera = scene::sensorCamera(camera, subsampling);
  Image<float> sensor_depth_m;
  if (subsampling > 1) sensor_depth_m.resize(sensor_camera.width, sensor_camera.height);
  Image<float> depth_m(camera.width, camera.height);
  std::vector<SE3d> sub_frame_poses(std::max(blur_samples, 1));
  const int64_t frames = (t_end_ns - fit.first_pose_ns) / kFramePeriodNs + 1;
  ProgressBar progress("rendering", frames);
  const auto render_start = std::chrono::steady_clock::now();
  const int64_t cover_start_ns = fit.first_pose_ns + secondsToNs(options.cover_start_s);
  const int64_t cover_end_ns = cover_start_ns + secondsToNs(options.cover_s);
  int64_t covered_frames = 0;
  for (int64_t k = 0; k < frames; ++k) {
    const int64_t t_ns = (fit.first_pose_ns + k * kFramePeriodNs) / 1000 * 1000;
    const bool covered = t_ns >= cover_start_ns && t_ns < cover_end_ns;
    for (std::size_t i = 0; i < sub_frame_poses.size(); ++i) {
      const int64_t offset_ns =
          sub_frame_poses.size() == 1
              ? 0
              : static_cast<int64_t>((static_cast<double>(i) / (sub_frame_poses.size() - 1) - 0.5) * kExposureNs);
      const int64_t t_sample = std::clamp(t_ns + offset_ns, fit.spline_W_S.startTimeNs(), fit.spline_W_S.endTimeNs());
      sub_frame_poses[i] = fit.cameraPose(t_sample);
    }
    if (covered) {
      std::fill_n(rgb.data(), rgb.pixelCount(), Rgb8{});
      std::fill_n(depth.data(), depth.pixelCount(), std::uint16_t{0});
      ++covered_frames;
    } else if (options.noise && subsampling > 1) {
      // Depth only at the native resolution: colour there would be rendered and thrown away.
      renderer.renderBlurred(sub_frame_poses, sensor_camera, ImageView<Rgb8>{}, sensor_depth_m.view());
      noise.addDepthNoise(sensor_depth_m.view(), depth.view(), static_cast<uint64_t>(k), subsampling);
      renderer.renderBlurred(sub_frame_poses, camera, rgb.view(), depth_m.view());
      noise.addIntensityNoise(rgb.view(), static_cast<uint64_t>(k));
    } else if (options.noise) {
      renderer.renderBlurred(sub_frame_poses, camera, rgb.view(), depth_m.view());
      noise.addDepthNoise(depth_m.view(), depth.view(), static_cast<uint64_t>(k));
      noise.addIntensityNoise(rgb.view(), static_cast<uint64_t>(k));
    } else {
      renderer.renderBlurred(sub_frame_poses, camera, rgb.view(), depth.view());
    }
    writer.writeFrame(t_ns, rgb.view(), depth.view(), fit.cameraPose(t_ns));
    progress.update(k + 1);
  }
  writer.finish();
  const double render_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - render_start).count();
  const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  nlohmann::json summary = {
      {"out", options.out},
      {"frames", frames},
      {"imu_samples", imu.samples.size()},
      {"duration_s", nsToSeconds(t_end_ns - fit.first_pose_ns)},
      {"fit_stride", fit_options.subsample},
      {"fit_at_samples", residualsJson(fit.at_samples)},
      {"fit_at_all_poses", residualsJson(fit.at_all_poses)},
      {"gyro_clipped_samples", imu.gyro_clipped_samples},
      {"accel_clipped_samples", imu.accel_clipped_samples},
      {"motion_blur_samples", blur_samples},
      {"covered_frames", covered_frames},
      // The simulated camera's truth, which calibration.yaml leaves to be measured.
      {"sensor",
       {{"inverse_depth_bias_per_m", options.noise ? scene::kSimulatedInverseDepthBias_per_m : 0.0},
        {"intensity_sigma", options.noise ? noise_options.intensity_sigma : 0.0}}},
      {"render_frames_per_s", static_cast<double>(frames) / render_s},
      {"wall_time_s", total_s}};
  if (!options.quiet) std::printf("%s\n", summary.dump().c_str());
  return 0;
}

}  // namespace vifusion::cli
