// Seeds of the text parsers: calibration files, every dataset layout's lists, the services' configuration.

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include "seed_writer.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/imu_noise.hpp"
#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/datasets/ground_truth_states.hpp"
#include "vifusion/datasets/kalibr.hpp"
#include "vifusion/eval/state_csv.hpp"

namespace vifusion::fuzz::seeds {
namespace {

std::string fileText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot read");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// A written file's text, through a scratch file beside the seeds.
template <typename Write>
std::string writtenText(const std::filesystem::path& root, Write&& write) {
  const std::filesystem::path scratch = root / "scratch.tmp";
  write(scratch);
  std::string text = fileText(scratch);
  std::filesystem::remove(scratch);
  return text;
}

/// The 7-Scenes Kinect as its folder describes it: the colour camera only.
RigCalibration kinectCalibration() {
  RigCalibration calibration;
  calibration.camera = PinholeCamera::create(640, 480, 585.0, 585.0, 320.0, 240.0);
  calibration.depth_scale_m = 0.001;
  return calibration;
}

/// A ZR300-class rig with every optional part: a separate depth camera, a depth bias, a measured noise
/// model, the camera-IMU transform and time shift, the real-world IMU noise.
RigCalibration zr300Calibration() {
  RigCalibration calibration;
  calibration.camera = PinholeCamera::create(640, 480, 617.5, 618.25, 321.75, 238.5);
  DepthCameraCalibration depth;
  depth.camera = PinholeCamera::create(628, 468, 585.0, 585.0, 314.0, 234.0);
  depth.T_C_D = SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY())), {0.025, 0.0, 0.004});
  calibration.depth_camera = depth;
  calibration.depth_scale_m = 0.001;
  calibration.inverse_depth_bias_per_m = 1.4e-3;
  CameraNoiseModel noise;
  noise.depth = {0.09, 43.875, 0.001, 0.5, 1.2, 3.0};
  noise.intensity = {1.8, 0.4, 0.9, 2.0};
  calibration.noise = noise;
  calibration.T_S_C =
      SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2.0, Eigen::Vector3d::UnitZ())), {0.1, 0.2, 0.3});
  calibration.time_shift_cam_imu_ns = -4'123'457;
  calibration.imu = ImuNoiseParams::zr300();
  return calibration;
}

/// Kalibr's two files for `calibration`, in the layout Kalibr writes them.
std::string kalibrCamchain(const RigCalibration& calibration) {
  const Eigen::Matrix4d T_C_S = calibration.T_S_C.inverse().matrix();
  std::ostringstream out;
  out.precision(17);
  out << "cam0:\n  T_cam_imu:\n";
  for (int r = 0; r < 4; ++r) {
    out << "  - [" << T_C_S(r, 0) << ", " << T_C_S(r, 1) << ", " << T_C_S(r, 2) << ", " << T_C_S(r, 3) << "]\n";
  }
  const PinholeCamera& camera = calibration.camera;
  out << "  cam_overlaps: []\n  camera_model: pinhole\n  distortion_coeffs: [0.0, 0.0, 0.0, 0.0]\n"
      << "  distortion_model: radtan\n  intrinsics: [" << camera.fx << ", " << camera.fy << ", " << camera.cx << ", "
      << camera.cy << "]\n  resolution: [" << camera.width << ", " << camera.height << "]\n"
      << "  rostopic: /camera/color/image_raw\n  timeshift_cam_imu: " << calibration.time_shift_cam_imu_ns * 1e-9
      << "\n";
  return out.str();
}

std::string kalibrImu(const ImuNoiseParams& imu) {
  std::ostringstream out;
  out.precision(17);
  out << "#Accelerometers\naccelerometer_noise_density: " << imu.accel_noise_density
      << "\naccelerometer_random_walk: " << imu.accel_random_walk
      << "\n#Gyroscopes\ngyroscope_noise_density: " << imu.gyro_noise_density
      << "\ngyroscope_random_walk: " << imu.gyro_random_walk << "\nrostopic: /imu0\nupdate_rate: " << imu.rate_hz
      << "\n";
  return out.str();
}

std::vector<GroundTruthState> sampleStates() {
  std::vector<GroundTruthState> states(4);
  for (std::size_t i = 0; i < states.size(); ++i) {
    const double t = 0.005 * static_cast<double>(i);
    states[i].t_ns = static_cast<std::int64_t>(i) * 5'000'000;
    states[i].p_W_S = {1.37 + 0.1 * t, 1.52, -1.45 + 0.2 * t};
    states[i].q_W_S = Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * t, Eigen::Vector3d(0.0, 0.6, 0.8)));
    states[i].v_W_S = {0.1, 0.0, 0.2};
    states[i].b_g = {1e-3, -2e-3, 5e-4};
    states[i].b_a = {0.02, -0.01, 0.03};
  }
  return states;
}

}  // namespace

void writeCalibrationSeeds(const std::filesystem::path& root) {
  enum : std::uint8_t { kFile, kText, kKalibr };  // fuzz_calibration_yaml.cpp's Reader
  SeedWriter seeds(root, "fuzz_calibration_yaml");
  const RigCalibration kinect = kinectCalibration(), zr300 = zr300Calibration();
  seeds.write("kinect_file.yaml", kFile, datasets::calibrationYamlText(kinect));
  seeds.write("zr300_file.yaml", kFile, datasets::calibrationYamlText(zr300));
  seeds.write("zr300_text.yaml", kText, datasets::calibrationYamlText(zr300));
  seeds.write("kalibr_pair", kKalibr, joinedWithNul({kalibrCamchain(zr300), kalibrImu(zr300.imu)}));
  seeds.write("kalibr_imu0", kKalibr,
              joinedWithNul({kalibrCamchain(zr300),
                             "imu0:\n  T_i_b: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], "
                             "[0, 0, 0, 1]]\n  accelerometer_noise_density: 0.08\n"
                             "  accelerometer_random_walk: 0.0004\n"
                             "  gyroscope_noise_density: 0.0012\n"
                             "  gyroscope_random_walk: 4.0e-06\n  update_rate: 200.0\n"}));
}

void writeDatasetListSeeds(const std::filesystem::path& root, const std::filesystem::path& data_dir) {
  // fuzz_dataset_lists.cpp's Choice
  enum : std::uint8_t { kTum, kIcl, kSevenScenes, kDataset, kEuroc, kStates, kTrajectory, kEstimated };
  SeedWriter seeds(root, "fuzz_dataset_lists");
  const std::string rgb = "# color images\n# timestamp filename\n1305031102.175304 rgb/1.png\n";
  const std::string depth = "# depth maps\n1305031102.160407 depth/1.png\n";
  const std::string tum_poses = firstLines(data_dir / "tum-fr1-xyz-eval/freiburg1_xyz-groundtruth.txt", 12);
  const std::string imu_csv = firstLines(data_dir / "euroc-v1-01-imu/imu0.csv", 24);
  const std::string seven_scenes = data_dir / "7scenes-50";
  seeds.write("tum", kTum,
              joinedWithNul({rgb, depth, tum_poses,
                             "# accelerometer data\n1305031102.17 -0.61 8.39 -4.04\n"
                             "1305031102.18 -0.60 8.41 -4.05\n"}));
  seeds.write("icl", kIcl,
              joinedWithNul({"0 depth/1.png 0 rgb/1.png\n1 depth/1.png 1 rgb/1.png\n",
                             firstLines(data_dir / "icl-nuim-trajectories/livingRoom0.tum.txt", 8)}));
  seeds.write("7scenes", kSevenScenes,
              joinedWithNul({firstLines(std::filesystem::path(seven_scenes) / "rgbd-frames/frame-000150.pose.txt", 4),
                             firstLines(std::filesystem::path(seven_scenes) / "camera-intrinsics.txt", 3)}));
  const std::string states_csv =
      writtenText(root, [&](const auto& path) { datasets::writeGroundTruthStates(path, sampleStates()); });
  seeds.write(
      "dataset", kDataset,
      joinedWithNul({datasets::calibrationYamlText(zr300Calibration()), rgb, depth, imu_csv, tum_poses, states_csv}));
  seeds.write("euroc", kEuroc, imu_csv);
  seeds.write("states", kStates, states_csv);
  seeds.write("trajectory", kTrajectory, firstLines(data_dir / "tum-fr1-xyz-eval/freiburg1_xyz-rgbdslam.txt", 16));
  std::vector<eval::StateRecord> records(3);
  for (std::size_t i = 0; i < records.size(); ++i) {
    records[i].t_ns = 1'000'000'000 + static_cast<std::int64_t>(i) * 33'333'333;
    records[i].variance.setConstant(1e-4 * static_cast<double>(i + 1));
  }
  seeds.write("estimated", kEstimated,
              writtenText(root, [&](const auto& path) { eval::writeEstimatedStates(path, records); }));
}

void writeDaemonConfigSeeds(const std::filesystem::path& root, const std::filesystem::path& source_dir) {
  SeedWriter seeds(root, "fuzz_daemon_config");
  seeds.write("shipped.yaml", std::nullopt, firstLines(source_dir / "systemd/vifusiond.yaml", 1000));
  seeds.write("minimal.yaml", std::nullopt, "source: \"7scenes:/data/office\"\nmode: rgbdi\ndds:\n  domain: 7\n");
}

}  // namespace vifusion::fuzz::seeds
