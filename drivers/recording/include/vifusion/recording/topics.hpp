#pragma once
// What a vifusion recording holds, topic by topic (MCAP, profile "ros2", CDR messages with ros2msg schemas),
// so that `ros2 bag play`, Foxglove and PlotJuggler read it as it is. Names follow realsense-ros where a
// camera driver has one. Every stamp is host CLOCK_MONOTONIC [ns] (DESIGN.md §3); a message's MCAP
// publish_time is its stamp, its log_time when the recorder wrote it.
//
//   /vifusion/recording_info       vifusion_msgs/RecordingInfo   once, first: source, mode, calibration YAML
//   /camera/color/camera_info      sensor_msgs/CameraInfo        once: the colour camera C
//   /camera/depth/camera_info      sensor_msgs/CameraInfo        once: the depth camera D (C when registered)
//   /tf_static                     tf2_msgs/TFMessage            once: T_C_S (C → IMU), T_C_D (C → depth)
//   /vifusion/frame_stamps         vifusion_msgs/FrameStamps     per frame, before its images: every clock's time
//   /camera/depth/image_rect_raw   sensor_msgs/Image 16UC1       per frame, raw units (FrameStamps.depth_scale_m)
//   /camera/color/image_raw        sensor_msgs/Image rgb8        per frame
//   /camera/imu                    sensor_msgs/Imu               per IMU sample (gyro and accel merged), in S
//   /vifusion/sync_edges           vifusion_msgs/SyncEdge        per sync-line edge
//   /vifusion/clock                vifusion_msgs/ClockMapping    per frame: the device→host mapping in use
//   /vifusion/motion_packets       vifusion_msgs/MotionPacket    per motion-module packet as received: every IMU
//                                                                sample's device ticks and counters
//   /ground_truth/camera_pose      geometry_msgs/TransformStamped simulator only: T_world_camera per frame
// The calibration YAML is also an attachment, calibration.yaml, for tools that read attachments.

#include <string_view>

namespace vifusion::recording {

inline constexpr std::string_view kTopicRecordingInfo = "/vifusion/recording_info";
inline constexpr std::string_view kTopicColourInfo = "/camera/color/camera_info";
inline constexpr std::string_view kTopicDepthInfo = "/camera/depth/camera_info";
inline constexpr std::string_view kTopicTfStatic = "/tf_static";
inline constexpr std::string_view kTopicFrameStamps = "/vifusion/frame_stamps";
inline constexpr std::string_view kTopicDepth = "/camera/depth/image_rect_raw";
inline constexpr std::string_view kTopicColour = "/camera/color/image_raw";
inline constexpr std::string_view kTopicImu = "/camera/imu";
inline constexpr std::string_view kTopicSyncEdges = "/vifusion/sync_edges";
inline constexpr std::string_view kTopicClock = "/vifusion/clock";
inline constexpr std::string_view kTopicMotionPackets = "/vifusion/motion_packets";
inline constexpr std::string_view kTopicGroundTruth = "/ground_truth/camera_pose";

/// Frame ids (ROS optical frames: x right, y down, z forward, as the pipeline's C and D).
inline constexpr std::string_view kFrameColour = "camera_color_optical_frame";
inline constexpr std::string_view kFrameDepth = "camera_depth_optical_frame";
inline constexpr std::string_view kFrameImu = "camera_imu_frame";
inline constexpr std::string_view kFrameWorld = "world";
inline constexpr std::string_view kFrameSyncLine = "sync_line";
inline constexpr std::string_view kFrameMotionModule = "zr300_motion_module";

/// ClockMapping.device of the ZR300's motion module clock.
inline constexpr std::string_view kMotionClock = "zr300_motion";

inline constexpr std::string_view kCalibrationAttachment = "calibration.yaml";

}  // namespace vifusion::recording
