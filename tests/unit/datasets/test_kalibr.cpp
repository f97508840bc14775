#include <gtest/gtest.h>

#include "fixtures.hpp"
#include "vifusion/datasets/kalibr.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion::datasets::test {
namespace {

// Non-symmetric on purpose: a 90° turn about z plus an offset, so reading T_cam_imu the wrong way
// round (as T_S_C) gives a visibly different transform.
constexpr const char* kCamchain = R"(cam0:
  T_cam_imu:
  - [0.0, -1.0, 0.0, 0.1]
  - [1.0, 0.0, 0.0, 0.2]
  - [0.0, 0.0, 1.0, 0.3]
  - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: []
  camera_model: pinhole
  distortion_coeffs: [0.0, 0.0, 0.0, 0.0]
  distortion_model: radtan
  intrinsics: [617.5, 618.25, 321.75, 238.5]
  resolution: [640, 480]
  rostopic: /camera/color/image_raw
  timeshift_cam_imu: -0.0041234567
)";

constexpr const char* kImuFlat = R"(#Accelerometers
accelerometer_noise_density: 1.86e-03   #Noise density (continuous-time)
accelerometer_random_walk:   4.33e-04   #Bias random walk
#Gyroscopes
gyroscope_noise_density:     1.87e-04
gyroscope_random_walk:       2.66e-05
rostopic:                    /imu0
update_rate:                 200.0
)";

TEST(Kalibr, ReadsCamchainAndImuWithTheExtrinsicInverted) {
  TempDir tmp;
  writeText(tmp / "camchain-imucam.yaml", kCamchain);
  writeText(tmp / "imu.yaml", kImuFlat);
  const RigCalibration calibration = readKalibr(tmp / "camchain-imucam.yaml", tmp / "imu.yaml");

  EXPECT_EQ(calibration.camera.width, 640);
  EXPECT_EQ(calibration.camera.height, 480);
  EXPECT_EQ(calibration.camera.fx, 617.5);
  EXPECT_EQ(calibration.camera.fy, 618.25);
  EXPECT_EQ(calibration.camera.cx, 321.75);
  EXPECT_EQ(calibration.camera.cy, 238.5);
  EXPECT_EQ(calibration.time_shift_cam_imu_ns, -4'123'457);

  // T_cam_imu = T_C_S, so the camera origin sits at T_S_C · 0 = −R_C_Sᵀ·t_C_S in S.
  EXPECT_MATRIX_NEAR(calibration.T_S_C.translation(), Eigen::Vector3d(-0.2, 0.1, -0.3), 1e-15);
  EXPECT_MATRIX_NEAR(calibration.T_S_C * Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-0.2, -0.9, -0.3), 1e-15);
  Eigen::Matrix4d T_cam_imu;
  T_cam_imu << 0, -1, 0, 0.1, 1, 0, 0, 0.2, 0, 0, 1, 0.3, 0, 0, 0, 1;
  EXPECT_MATRIX_NEAR(calibration.T_S_C.inverse().matrix(), T_cam_imu, 1e-15);

  EXPECT_EQ(calibration.imu.accel_noise_density, 1.86e-03);
  EXPECT_EQ(calibration.imu.accel_random_walk, 4.33e-04);
  EXPECT_EQ(calibration.imu.gyro_noise_density, 1.87e-04);
  EXPECT_EQ(calibration.imu.gyro_random_walk, 2.66e-05);
  EXPECT_EQ(calibration.imu.rate_hz, 200.0);
}

TEST(Kalibr, ReadsKalibrsNestedImuOutput) {
  TempDir tmp;
  writeText(tmp / "camchain-imucam.yaml", kCamchain);
  writeText(tmp / "imu-results.yaml", R"(imu0:
  T_i_b:
  - [1.0, 0.0, 0.0, 0.0]
  - [0.0, 1.0, 0.0, 0.0]
  - [0.0, 0.0, 1.0, 0.0]
  - [0.0, 0.0, 0.0, 1.0]
  accelerometer_noise_density: 0.01
  accelerometer_random_walk: 0.0002
  gyroscope_noise_density: 0.005
  gyroscope_random_walk: 4.0e-06
  model: calibrated
  rostopic: /imu0
  time_offset: 0.0
  update_rate: 250.0
)");
  const RigCalibration calibration = readKalibr(tmp / "camchain-imucam.yaml", tmp / "imu-results.yaml");
  EXPECT_EQ(calibration.imu.gyro_noise_density, 0.005);
  EXPECT_EQ(calibration.imu.rate_hz, 250.0);
}

TEST(Kalibr, CalibrationYamlRoundTrips) {
  TempDir tmp;
  RigCalibration original;
  original.camera = PinholeCamera::create(320, 240, 481.2, -480.0, 159.5, 119.5);
  original.depth_scale_m = 0.001;
  original.inverse_depth_bias_per_m = 1.4232849416453174e-3;
  original.T_S_C = SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, -1.0, 0.5).normalized())),
                        Eigen::Vector3d(0.015, -0.0042, 0.031));
  original.time_shift_cam_imu_ns = 2'345'678;
  original.imu = ImuNoiseParams::zr300();
  original.imu.rate_hz = 250.0;
  original.imu.gyro_saturation_rad_s = 8.7;
  original.g_W = Eigen::Vector3d(0.0, 0.0, -9.80665);
  original.depth_camera = DepthCameraCalibration{
      PinholeCamera::create(320, 240, 290.5, 291.25, 160.5, 118.75),
      SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.01, Eigen::Vector3d(0.3, 1.0, -0.2).normalized())),
           Eigen::Vector3d(0.0251, -0.0003, 0.0012))};
  writeCalibrationYaml(tmp / "calibration.yaml", original);
  const RigCalibration read = readCalibrationYaml(tmp / "calibration.yaml");

  EXPECT_EQ(read.camera.width, 320);
  EXPECT_EQ(read.camera.height, 240);
  EXPECT_EQ(read.camera.fx, 481.2);
  EXPECT_EQ(read.camera.fy, -480.0);
  EXPECT_EQ(read.camera.cx, 159.5);
  EXPECT_EQ(read.camera.cy, 119.5);
  EXPECT_EQ(read.depth_scale_m, 0.001);
  EXPECT_EQ(read.inverse_depth_bias_per_m, original.inverse_depth_bias_per_m);
  EXPECT_MATRIX_NEAR(read.T_S_C.matrix(), original.T_S_C.matrix(), 1e-15);
  EXPECT_EQ(read.time_shift_cam_imu_ns, 2'345'678);
  EXPECT_EQ(read.g_W, original.g_W);
  EXPECT_EQ(read.imu.gravity_mps2, 9.80665);
  EXPECT_EQ(read.imu.accel_noise_density, original.imu.accel_noise_density);
  EXPECT_EQ(read.imu.accel_random_walk, original.imu.accel_random_walk);
  EXPECT_EQ(read.imu.gyro_noise_density, original.imu.gyro_noise_density);
  EXPECT_EQ(read.imu.gyro_random_walk, original.imu.gyro_random_walk);
  EXPECT_EQ(read.imu.rate_hz, 250.0);
  EXPECT_EQ(read.imu.gyro_saturation_rad_s, 8.7);
  EXPECT_EQ(read.imu.accel_saturation_mps2, original.imu.accel_saturation_mps2);
  EXPECT_EQ(read.imu.gyro_bias_prior, original.imu.gyro_bias_prior);
  EXPECT_EQ(read.imu.accel_bias_prior, original.imu.accel_bias_prior);
  EXPECT_EQ(read.imu.static_accel_bias_mps2, original.imu.static_accel_bias_mps2);
  ASSERT_TRUE(read.depth_camera.has_value());
  EXPECT_EQ(read.depth_camera->camera.fx, 290.5);
  EXPECT_EQ(read.depth_camera->camera.cy, 118.75);
  EXPECT_MATRIX_NEAR(read.depth_camera->T_C_D.matrix(), original.depth_camera->T_C_D.matrix(), 1e-15);

  const std::string text = [&] {
    std::ifstream in(tmp / "calibration.yaml");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  // Its cam0 and cam1 blocks alone are a valid Kalibr camchain with the same extrinsics.
  writeText(tmp / "camchain-imucam.yaml", text.substr(0, text.find("imu0:")));
  writeText(tmp / "imu.yaml", kImuFlat);
  const RigCalibration as_kalibr = readKalibr(tmp / "camchain-imucam.yaml", tmp / "imu.yaml");
  EXPECT_MATRIX_NEAR(as_kalibr.T_S_C.matrix(), original.T_S_C.matrix(), 1e-15);
  ASSERT_TRUE(as_kalibr.depth_camera.has_value());
  EXPECT_MATRIX_NEAR(as_kalibr.depth_camera->T_C_D.matrix(), original.depth_camera->T_C_D.matrix(), 1e-15);
}

TEST(Kalibr, UnknownTopLevelKeyIsAnError) {
  TempDir tmp;
  writeCalibrationYaml(tmp / "calibration.yaml", RigCalibration{});
  std::ofstream(tmp / "calibration.yaml", std::ios::app) << "depth_scale: 0.001\n";
  expectError([&] { readCalibrationYaml(tmp / "calibration.yaml"); },
              "unknown key 'depth_scale' in the top level (expected one of: cam0, cam1, imu0, depth_scale_m");
}

TEST(Kalibr, InverseDepthBiasDefaultsToZeroAndAnImplausibleOneIsAnError) {
  TempDir tmp;
  writeText(tmp / "camchain-imucam.yaml", kCamchain);
  writeText(tmp / "imu.yaml", kImuFlat);
  RigCalibration calibration = readKalibr(tmp / "camchain-imucam.yaml", tmp / "imu.yaml");
  EXPECT_EQ(calibration.inverse_depth_bias_per_m, 0.0);

  calibration.inverse_depth_bias_per_m = -0.02;  // a stereo sensor reading far: allowed
  writeCalibrationYaml(tmp / "calibration.yaml", calibration);
  EXPECT_EQ(readCalibrationYaml(tmp / "calibration.yaml").inverse_depth_bias_per_m, -0.02);
  calibration.inverse_depth_bias_per_m = 1.5;  // no finite depth beyond 0.67 m: a typo
  writeCalibrationYaml(tmp / "calibration.yaml", calibration);
  expectError([&] { readCalibrationYaml(tmp / "calibration.yaml"); },
              "'inverse_depth_bias_per_m' (1/z_raw − 1/z) must be within ±0.1 1/m, got 1.5");
}

TEST(Kalibr, MeasuredNoiseRoundTripsAndIsOptional) {
  TempDir tmp;
  RigCalibration calibration;
  calibration.camera = PinholeCamera::create(320, 240, 240.6, 240.0, 159.5, 119.5);
  EXPECT_FALSE(readCalibrationYamlText(calibrationYamlText(calibration), "calibration.yaml").noise);
  calibration.noise = CameraNoiseModel{
      .depth = {.disparity_sigma_px = 0.047,
                .focal_baseline_px_m = 36.0,
                .quantisation_m = 0.011,
                .lateral_sigma_px = 0.57,
                .correlation_px = 0.86,
                .pixels_per_sample = 12.8,
                .inverse_depth_bias_sigma_per_m = 2.17e-4},
      .intensity = {.sigma = 2.86, .lateral_sigma_px = 0.4, .correlation_px = 0.69, .pixels_per_sample = 4.1}};
  writeCalibrationYaml(tmp / "calibration.yaml", calibration);
  const RigCalibration back = readCalibrationYaml(tmp / "calibration.yaml");
  ASSERT_TRUE(back.noise);
  EXPECT_EQ(back.noise->depth.disparity_sigma_px, 0.047);
  EXPECT_EQ(back.noise->depth.focal_baseline_px_m, 36.0);
  EXPECT_EQ(back.noise->depth.quantisation_m, 0.011);
  EXPECT_EQ(back.noise->depth.lateral_sigma_px, 0.57);
  EXPECT_EQ(back.noise->depth.correlation_px, 0.86);
  EXPECT_EQ(back.noise->depth.pixels_per_sample, 12.8);
  EXPECT_EQ(back.noise->depth.inverse_depth_bias_sigma_per_m, 2.17e-4);
  EXPECT_EQ(back.noise->intensity.sigma, 2.86);
  EXPECT_EQ(back.noise->intensity.lateral_sigma_px, 0.4);
  EXPECT_EQ(back.noise->intensity.correlation_px, 0.69);
  EXPECT_EQ(back.noise->intensity.pixels_per_sample, 4.1);
}

TEST(Kalibr, MeasuredNoiseTyposAndImplausibleValuesAreErrors) {
  RigCalibration calibration;
  calibration.camera = PinholeCamera::create(320, 240, 240.6, 240.0, 159.5, 119.5);
  calibration.noise =
      CameraNoiseModel{.depth = {.disparity_sigma_px = 0.05, .focal_baseline_px_m = 36.0}, .intensity = {.sigma = 2.7}};
  const std::string text = calibrationYamlText(calibration);
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string edited = text;
    edited.replace(edited.find(from), from.size(), to);
    return edited;
  };
  expectError([&] { readCalibrationYamlText(with("disparity_sigma_px:", "disparity_sigma:"), "c.yaml"); },
              "unknown key 'disparity_sigma' in depth_noise");
  expectError([&] { readCalibrationYamlText(with("disparity_sigma_px: 0.05", "disparity_sigma_px: 50"), "c.yaml"); },
              "'disparity_sigma_px' in depth_noise must be in [0.000000, 10.000000], got 50");
  expectError(
      [&] {
        readCalibrationYamlText(with("inverse_depth_bias_sigma_per_m: 0", "inverse_depth_bias_sigma_per_m: -1e-4"),
                                "c.yaml");
      },
      "'inverse_depth_bias_sigma_per_m' in depth_noise must be in [0.000000, 0.100000], got -1e-4");
  const RigCalibration without_bias_sigma =
      readCalibrationYamlText(with("  inverse_depth_bias_sigma_per_m: 0\n", ""), "calibration written before the key");
  EXPECT_EQ(without_bias_sigma.noise->depth.inverse_depth_bias_sigma_per_m, 0.0) << "absent: no systematic bound";
  expectError([&] { readCalibrationYamlText(with("  sigma: 2.7", "  sigma: -1"), "c.yaml"); },
              "'sigma' in intensity_noise must be in");
  expectError([&] { readCalibrationYamlText(with("focal_baseline_px_m: 36", "focal_baseline_px_m: .nan"), "c.yaml"); },
              "'focal_baseline_px_m' is not a finite number");
  const std::string depth_only = text.substr(0, text.find("intensity_noise:"));
  expectError([&] { readCalibrationYamlText(depth_only, "c.yaml"); },
              "'depth_noise' and 'intensity_noise' must both be mappings");
}

TEST(Kalibr, MisspeltNestedKeyIsAnErrorWithItsLine) {
  TempDir tmp;
  std::string camchain = kCamchain;
  camchain.replace(camchain.find("timeshift_cam_imu"), 17, "timeshift_cam_im");
  writeText(tmp / "camchain-imucam.yaml", camchain);
  writeText(tmp / "imu.yaml", kImuFlat);
  expectError([&] { readKalibr(tmp / "camchain-imucam.yaml", tmp / "imu.yaml"); },
              "camchain-imucam.yaml line 14: unknown key 'timeshift_cam_im' in cam0");
  writeText(tmp / "camchain-imucam.yaml", kCamchain);
  writeText(tmp / "imu.yaml", std::string(kImuFlat) + "gyroscope_randomwalk: 1e-5\n");
  expectError([&] { readKalibr(tmp / "camchain-imucam.yaml", tmp / "imu.yaml"); },
              "imu.yaml line 9: unknown key 'gyroscope_randomwalk' in the IMU file");
}

// cam1 is the depth camera (ZR300: the IR pair). Kalibr's T_cn_cnm1 maps cam0 points into cam1 (T_D_C); its
// T_cam_imu must agree with cam0's through that chain.
constexpr const char* kDepthCamera = R"(cam1:
  T_cam_imu:
  - [0.0, -1.0, 0.0, 0.075]
  - [1.0, 0.0, 0.0, 0.2]
  - [0.0, 0.0, 1.0, 0.3]
  - [0.0, 0.0, 0.0, 1.0]
  T_cn_cnm1:
  - [1.0, 0.0, 0.0, -0.025]
  - [0.0, 1.0, 0.0, 0.0]
  - [0.0, 0.0, 1.0, 0.0]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  distortion_coeffs: [0.0, 0.0, 0.0, 0.0]
  distortion_model: radtan
  intrinsics: [580.0, 581.0, 318.0, 242.0]
  resolution: [640, 480]
  rostopic: /camera/depth/image_raw
)";

TEST(Kalibr, SecondCameraIsTheDepthCamera) {
  TempDir tmp;
  writeText(tmp / "camchain-imucam.yaml", std::string(kCamchain) + kDepthCamera);
  writeText(tmp / "imu.yaml", kImuFlat);
  const RigCalibration calibration = readKalibr(tmp / "camchain-imucam.yaml", tmp / "imu.yaml");
  ASSERT_TRUE(calibration.depth_camera.has_value());
  EXPECT_EQ(calibration.depth_camera->camera.fx, 580.0);
  EXPECT_EQ(calibration.depth_camera->camera.cy, 242.0);
  EXPECT_EQ(calibration.depth_camera->camera.width, 640);
  // p_C = T_C_D · p_D: the depth camera's origin sits 25 mm along +x of the colour camera.
  EXPECT_MATRIX_NEAR(calibration.depth_camera->T_C_D.translation(), Eigen::Vector3d(0.025, 0.0, 0.0), 1e-15);

  std::string inconsistent = kDepthCamera;
  inconsistent.replace(inconsistent.find("0.075"), 5, "0.085");  // cam1's T_cam_imu off by 10 mm
  writeText(tmp / "camchain-imucam.yaml", std::string(kCamchain) + inconsistent);
  expectError([&] { readKalibr(tmp / "camchain-imucam.yaml", tmp / "imu.yaml"); },
              "line 17: cam1 'T_cam_imu' disagrees with cam0's 'T_cam_imu' and 'T_cn_cnm1' by 10.0 mm and 0.00 mrad");

  std::string unchained = kDepthCamera;
  unchained.erase(unchained.find("  T_cn_cnm1:"), unchained.find("  camera_model") - unchained.find("  T_cn_cnm1:"));
  writeText(tmp / "camchain-imucam.yaml", std::string(kCamchain) + unchained);
  expectError([&] { readKalibr(tmp / "camchain-imucam.yaml", tmp / "imu.yaml"); }, "missing key 'T_cn_cnm1'");

  writeText(tmp / "camchain-imucam.yaml", std::string(kCamchain) + kDepthCamera + "cam2:\n  camera_model: pinhole\n");
  expectError([&] { readKalibr(tmp / "camchain-imucam.yaml", tmp / "imu.yaml"); }, "unknown key 'cam2'");
}

class KalibrCorruption : public ::testing::Test {
 protected:
  void expectCamchainError(const std::string& from, const std::string& to, const std::string& expected) {
    std::string camchain = kCamchain;
    const std::size_t at = camchain.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    camchain.replace(at, from.size(), to);
    writeText(tmp_ / "camchain-imucam.yaml", camchain);
    writeText(tmp_ / "imu.yaml", kImuFlat);
    expectError([&] { readKalibr(tmp_ / "camchain-imucam.yaml", tmp_ / "imu.yaml"); }, expected);
  }
  TempDir tmp_;
};

TEST_F(KalibrCorruption, MissingIntrinsics) {
  expectCamchainError("  intrinsics: [617.5, 618.25, 321.75, 238.5]\n", "",
                      "camchain-imucam.yaml line 2: missing key 'intrinsics'");
}

TEST_F(KalibrCorruption, ShortIntrinsics) {
  expectCamchainError("[617.5, 618.25, 321.75, 238.5]", "[617.5, 618.25, 321.75]",
                      "line 11: 'intrinsics' must be a list of 4 numbers");
}

TEST_F(KalibrCorruption, NaNIntrinsic) {
  expectCamchainError("618.25", ".nan", "line 11: 'intrinsics[1]' is not a finite number: '.nan'");
}

TEST_F(KalibrCorruption, NonPinholeModel) {
  expectCamchainError("camera_model: pinhole", "camera_model: omni", "camera_model 'omni' is not supported");
}

TEST_F(KalibrCorruption, NonZeroDistortion) {
  expectCamchainError("[0.0, 0.0, 0.0, 0.0]", "[0.1, 0.0, 0.0, 0.0]", "'distortion_coeffs' must be zero");
}

TEST_F(KalibrCorruption, NonRotationExtrinsic) {
  expectCamchainError("[0.0, -1.0, 0.0, 0.1]", "[0.0, -2.0, 0.0, 0.1]",
                      "line 3: 'T_cam_imu' rotation block is not a rotation matrix");
}

// Found by fuzz_calibration_yaml: a key whose value is not a mapping escaped as a yaml-cpp exception.
TEST_F(KalibrCorruption, CameraThatIsNotAMappingIsNamed) {
  std::string camchain = "cam0: 5\n";
  writeText(tmp_ / "camchain-imucam.yaml", camchain);
  writeText(tmp_ / "imu.yaml", kImuFlat);
  expectError([&] { readKalibr(tmp_ / "camchain-imucam.yaml", tmp_ / "imu.yaml"); }, "camchain-imucam.yaml line 1: ");
}

TEST(Kalibr, CalibrationTextThatIsNotAMappingIsNamed) {
  expectError([&] { readCalibrationYamlText("cam0", "recorded.yaml"); },
              "recorded.yaml: expected a mapping of keys at the top level");
  expectError([&] { readCalibrationYamlText("- cam0\n- imu0\n", "recorded.yaml"); },
              "recorded.yaml: expected a mapping of keys at the top level");
}

TEST_F(KalibrCorruption, YamlSyntaxError) {
  expectCamchainError("resolution: [640, 480]", "resolution: [640, 480",
                      "camchain-imucam.yaml line 13: YAML syntax error");
}

TEST(Kalibr, InvalidNoiseIsAnError) {
  TempDir tmp;
  writeText(tmp / "camchain-imucam.yaml", kCamchain);
  std::string imu = kImuFlat;
  imu.replace(imu.find("1.87e-04"), 8, "-1.87e-4");
  writeText(tmp / "imu.yaml", imu);
  expectError([&] { readKalibr(tmp / "camchain-imucam.yaml", tmp / "imu.yaml"); }, "'gyro_noise_density'");
}

TEST(Kalibr, MissingFileIsAnError) {
  TempDir tmp;
  expectError([&] { readCalibrationYaml(tmp / "calibration.yaml"); }, "calibration.yaml: cannot open file");
}

}  // namespace
}  // namespace vifusion::datasets::test
