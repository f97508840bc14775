#include "recording_fixtures.hpp"

#include <unistd.h>

#include <random>
#include <string>

namespace vifusion::recording::test {

TempDir::TempDir() {
  std::random_device random;
  path_ = std::filesystem::temp_directory_path() /
          ("vifusion_recording_" + std::to_string(::getpid()) + "_" + std::to_string(random()));
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

RigCalibration rigCalibration() {
  RigCalibration calibration;
  calibration.camera = PinholeCamera::create(kWidth, kHeight, 30.5, 31.25, 15.5, 11.75);
  calibration.depth_camera = DepthCameraCalibration{
      PinholeCamera::create(kWidth, kHeight, 28.0, 28.5, 16.0, 12.0),
      SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY())), Eigen::Vector3d(0.025, 0, 0))};
  calibration.depth_scale_m = 0.001;
  calibration.T_S_C = SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 2, 3).normalized())),
                           Eigen::Vector3d(0.01, -0.02, 0.03));
  calibration.time_shift_cam_imu_ns = 1'234'567;
  calibration.imu = ImuNoiseParams::zr300();
  return calibration;
}

RecordingHeader recordingHeader() {
  RecordingHeader header;
  header.source = "zr300:SN_TEST";
  header.mode = "rgbdi";
  header.calibration = rigCalibration();
  header.imu_rate_hz = 200.0;
  header.t_ns = kStartNs;
  return header;
}

RgbdFrame makeFrame(int k) {
  RgbdFrame frame;
  frame.t_ns = kStartNs + k * kFramePeriodNs;
  frame.index = k;
  frame.depth_scale_m = 0.001;
  frame.depth.resize(kWidth, kHeight);
  frame.rgb.resize(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      frame.depth(x, y) = static_cast<std::uint16_t>(1000 + 37 * k + 5 * x + 11 * y);
      frame.rgb(x, y) = Rgb8{static_cast<std::uint8_t>(k + x), static_cast<std::uint8_t>(3 * k + y),
                             static_cast<std::uint8_t>(x * y + k)};
    }
  }
  frame.timing.device_frame_number = 4094u + static_cast<std::uint32_t>(k);  // crosses the 12-bit wrap
  frame.timing.kernel_mid_exposure_ns = frame.t_ns + 400'000 + k;
  frame.timing.device_event_ns = frame.t_ns;
  frame.timing.device_event_clock_ns = 7'000'000'000 + k * kFramePeriodNs;
  frame.timing.stamped_by_device_event = k % 3 != 2;
  return frame;
}

ImuSample makeImu(int k) {
  ImuSample sample;
  sample.t_ns = kStartNs - 20 * kImuPeriodNs + k * kImuPeriodNs;
  sample.gyro_rad_s = Eigen::Vector3d(0.1 + 1e-3 * k, -0.2, 1.0 / (k + 3));
  sample.accel_mps2 = Eigen::Vector3d(0.05, 9.81 - 1e-4 * k, std::sqrt(2.0) * k);
  return sample;
}

ClockRecord makeClock(int k) {
  return ClockRecord{kStartNs + k * kFramePeriodNs, 2, 7'000'000'000 + k * kFramePeriodNs,
                     kStartNs + k * kFramePeriodNs + 17, 25e-6 + 1e-9 * k};
}

bool sameFrame(const RgbdFrame& a, const RgbdFrame& b) {
  if (a.t_ns != b.t_ns || a.index != b.index || a.depth_scale_m != b.depth_scale_m) return false;
  const FrameTiming& s = a.timing;
  const FrameTiming& t = b.timing;
  if (s.device_frame_number != t.device_frame_number || s.kernel_mid_exposure_ns != t.kernel_mid_exposure_ns ||
      s.device_event_ns != t.device_event_ns || s.device_event_clock_ns != t.device_event_clock_ns ||
      s.stamped_by_device_event != t.stamped_by_device_event) {
    return false;
  }
  if (a.depth.width() != b.depth.width() || a.depth.height() != b.depth.height() || a.rgb.width() != b.rgb.width() ||
      a.rgb.height() != b.rgb.height()) {
    return false;
  }
  for (int y = 0; y < a.depth.height(); ++y) {
    for (int x = 0; x < a.depth.width(); ++x) {
      if (a.depth(x, y) != b.depth(x, y)) return false;
    }
  }
  for (int y = 0; y < a.rgb.height(); ++y) {
    for (int x = 0; x < a.rgb.width(); ++x) {
      if (!(a.rgb(x, y) == b.rgb(x, y))) return false;
    }
  }
  return true;
}

}  // namespace vifusion::recording::test
