#include "sample_messages.hpp"

#include <array>

#include "vifusion/core/time.hpp"

namespace vifusion::ros2_msgs::test {
namespace {

constexpr std::int64_t kBaseNs = 1'234 * kNsPerSecond + 567'890'123;  // a host CLOCK_MONOTONIC time
constexpr std::int64_t kFramePeriodNs = 33'333'333;                   // 30 Hz
constexpr std::int64_t kImuPeriodNs = 5'000'000;                      // 200 Hz

/// Bytes that differ per position and per image, so a shifted or swapped buffer cannot pass.
std::vector<std::uint8_t> patternBytes(std::size_t count, std::uint8_t seed) {
  std::vector<std::uint8_t> bytes(count);
  for (std::size_t i = 0; i < count; ++i) bytes[i] = static_cast<std::uint8_t>(seed + 37 * i);
  return bytes;
}

ImageView imageOf(const Header& header, std::string_view encoding, std::uint32_t bytes_per_pixel,
                  const std::vector<std::uint8_t>& bytes) {
  ImageView image;
  image.header = header;
  image.width = kSampleImageWidth;
  image.height = kSampleImageHeight;
  image.encoding = encoding;
  image.step = kSampleImageWidth * bytes_per_pixel;
  image.data = bytes;
  return image;
}

TransformStamped transformOf(std::string_view parent, std::string_view child, const Vector3& t, const Quaternion& q) {
  TransformStamped transform;
  transform.header = makeHeader(kBaseNs, parent);
  transform.child_frame_id = child;
  transform.transform = Transform{t, q};
  return transform;
}

}  // namespace

SampleMessages::SampleMessages()
    : depth_bytes_(patternBytes(kSampleImageWidth * kSampleImageHeight * 2, 11)),
      rgb_bytes_(patternBytes(kSampleImageWidth * kSampleImageHeight * 3, 101)),
      yuyv_bytes_(patternBytes(kSampleImageWidth * kSampleImageHeight * 2, 200)),
      motion_bytes_(patternBytes(kSampleMotionPacketBytes, 7)),
      calibration_yaml_("cam0:\n  intrinsics: [617.2, 617.4, 318.9, 243.1]\n  resolution: [640, 480]\n") {
  time = Time::fromNs(-1'700'000'000);
  header = makeHeader(kBaseNs, "camera_depth_optical_frame");  // 26 characters: 1 padding byte follows

  depth = imageOf(makeHeader(kBaseNs, "depth"), image_encodings::kDepth16, 2, depth_bytes_);
  rgb = imageOf(makeHeader(kBaseNs + 1, "colour"), image_encodings::kRgb8, 3, rgb_bytes_);
  yuyv = imageOf(makeHeader(kBaseNs + 2, "colour"), image_encodings::kYuyv, 2, yuyv_bytes_);

  imu.header = makeHeader(kBaseNs + kImuPeriodNs, "imu");
  imu.angular_velocity = Vector3{0.0125, -0.25, 3.0e-5};
  imu.linear_acceleration = Vector3{0.31, 9.7921, -0.0625};
  imu.angular_velocity_covariance = {2.88e-6, 0, 0, 0, 2.88e-6, 0, 0, 0, 2.88e-6};
  imu.linear_acceleration_covariance = {1.28e-2, 0, 0, 0, 1.28e-2, 0, 0, 0, 1.5e-2};

  camera_info_plumb_bob.header = makeHeader(kBaseNs, "depth");
  camera_info_plumb_bob.width = 640;
  camera_info_plumb_bob.height = 480;
  camera_info_plumb_bob.distortion_model = distortion_models::kPlumbBob;
  camera_info_plumb_bob.setDistortion(std::array<double, 5>{0.1044, -0.2591, 0.0012, -0.0007, 0.1356});
  camera_info_plumb_bob.k = {617.25, 0, 318.875, 0, 617.5, 243.125, 0, 0, 1};
  camera_info_plumb_bob.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  camera_info_plumb_bob.p = {617.25, 0, 318.875, 0, 0, 617.5, 243.125, 0, 0, 0, 1, 0};
  camera_info_plumb_bob.binning_x = 1;
  camera_info_plumb_bob.binning_y = 1;
  camera_info_plumb_bob.roi = RegionOfInterest{8, 4, 472, 624, true};

  camera_info_equidistant.header = makeHeader(kBaseNs, "fisheye");
  camera_info_equidistant.width = 640;
  camera_info_equidistant.height = 480;
  camera_info_equidistant.distortion_model = distortion_models::kEquidistant;
  camera_info_equidistant.setDistortion(std::array<double, 4>{-0.0091, 0.0433, -0.0406, 0.0129});
  camera_info_equidistant.k = {277.5, 0, 320.25, 0, 277.75, 240.5, 0, 0, 1};
  camera_info_equidistant.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  camera_info_equidistant.p = {277.5, 0, 320.25, 0, 0, 277.75, 240.5, 0, 0, 0, 1, 0};

  transform = transformOf("imu", "depth", Vector3{0.0213, -0.0042, 0.0105}, Quaternion{0.5, -0.5, 0.5, -0.5});
  tf_static.add(transform);
  tf_static.add(
      transformOf("imu", "colour", Vector3{-0.0365, -0.0041, 0.0108}, Quaternion{0.4997, -0.5003, 0.5001, -0.4999}));
  tf_static.add(transformOf("base_link", "imu", Vector3{0.12, 0.0, 0.35}, Quaternion{}));

  frame_stamps.header = makeHeader(kBaseNs + 7 * kFramePeriodNs, "depth");
  frame_stamps.index = 7;
  frame_stamps.device_frame_number = 4'000'000'007u;
  frame_stamps.kernel_mid_exposure_ns = kBaseNs + 7 * kFramePeriodNs - 412'345;
  frame_stamps.device_event_ns = kBaseNs + 7 * kFramePeriodNs;
  frame_stamps.device_event_clock_ns = 5'141'592'653'589;
  frame_stamps.stamped_by_device_event = true;
  frame_stamps.depth_sequence = 1'007;
  frame_stamps.colour_sequence = 2'007;
  frame_stamps.depth_scale_m = 0.001;

  motion_packet.header = makeHeader(kBaseNs + 3 * kImuPeriodNs, "imu");
  motion_packet.data = motion_bytes_;
  motion_packet.transfer_index = 65'537;

  sync_edge.header = makeHeader(kBaseNs + 2 * kFramePeriodNs, "sync");
  sync_edge.rising = false;
  sync_edge.sequence = 0x1234'5678'9abc'def0ull;  // above 2^53: a double would round it

  clock_mapping.header = makeHeader(kBaseNs + kNsPerSecond, "");
  clock_mapping.device = "zr300_motion";
  clock_mapping.state = ClockMappingState::kWarmingUp;
  clock_mapping.ref_device_ns = 987'654'321'012;
  clock_mapping.ref_host_ns = kBaseNs + 999;
  clock_mapping.skew = 4.25e-5;
  clock_mapping.offset_ns = clock_mapping.ref_host_ns - clock_mapping.ref_device_ns;  // negative
  clock_mapping.skew_ppm = 42.5;

  recording_info.header = makeHeader(kBaseNs, "");
  recording_info.source = "zr300";
  recording_info.vifusion_version = "0.18.0-dev";
  recording_info.calibration_yaml = calibration_yaml_;
  recording_info.mode = "rgbdi";
  recording_info.width = 640;
  recording_info.height = 480;
  recording_info.frame_rate_hz = 30.0;
  recording_info.imu_rate_hz = 200.0;
}

}  // namespace vifusion::ros2_msgs::test
