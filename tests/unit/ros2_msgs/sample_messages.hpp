#pragma once
// One filled-in message of every type, with values chosen to exercise the layout: odd string lengths
// (padding before the next 4- and 8-byte field), negative and extreme integers, non-trivial floats, bytes
// that differ per position. Shared by the round-trip tests and the fixture writer that Foxglove's decoder
// checks, so both prove the same messages. The object owns every string and byte its messages view, so it
// stays where it was built (no copy, no move).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "vifusion/ros2_msgs/geometry_tf.hpp"
#include "vifusion/ros2_msgs/sensor_msgs.hpp"
#include "vifusion/ros2_msgs/time_header.hpp"
#include "vifusion/ros2_msgs/vifusion_msgs.hpp"

namespace vifusion::ros2_msgs::test {

/// Small images keep the decoded JSON short while still covering several rows.
inline constexpr std::uint32_t kSampleImageWidth = 5;
inline constexpr std::uint32_t kSampleImageHeight = 3;
/// The ZR300 motion module's packet size [bytes].
inline constexpr std::size_t kSampleMotionPacketBytes = 104;

class SampleMessages {
 public:
  SampleMessages();
  SampleMessages(const SampleMessages&) = delete;
  SampleMessages& operator=(const SampleMessages&) = delete;

  Time time;  ///< negative: −1.7 s
  Header header;
  ImageView depth;  ///< 16UC1
  ImageView rgb;    ///< rgb8
  ImageView yuyv;   ///< yuv422_yuy2
  Imu imu;
  CameraInfo camera_info_plumb_bob;
  CameraInfo camera_info_equidistant;
  TransformStamped transform;
  TfMessage tf_static;  ///< three transforms
  FrameStamps frame_stamps;
  MotionPacket motion_packet;
  SyncEdge sync_edge;
  ClockMapping clock_mapping;
  RecordingInfo recording_info;

 private:
  std::vector<std::uint8_t> depth_bytes_;
  std::vector<std::uint8_t> rgb_bytes_;
  std::vector<std::uint8_t> yuyv_bytes_;
  std::vector<std::uint8_t> motion_bytes_;
  std::string calibration_yaml_;
};

}  // namespace vifusion::ros2_msgs::test
