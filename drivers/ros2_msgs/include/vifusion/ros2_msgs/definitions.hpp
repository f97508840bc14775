#pragma once
// The "ros2msg" definition text of every message type this library writes (MCAP Schema.data), so that a
// reader with no ROS installation (Foxglove, PlotJuggler, rosbags, Foxglove's npm libraries) can decode
// the CDR bytes. Field lines are those of ROS 2's common_interfaces, rcl_interfaces (builtin_interfaces)
// and geometry2 (tf2_msgs) .msg files (types, names, Quaternion's defaults); their comments are left out,
// which changes no decoder's result. vifusion_msgs are ours, documented with units here because this text
// is what a person sees of them in Foxglove. Layout: definition_text.hpp. Each struct's kDefinition
// points here; tests decode every type with Foxglove's parser to prove the texts.

#include <string_view>

#include "vifusion/ros2_msgs/definition_text.hpp"

namespace vifusion::ros2_msgs::definitions {

/// .msg texts of single types, each ending in "\n".
namespace msg {
inline constexpr std::string_view kTime = "int32 sec\nuint32 nanosec\n";
inline constexpr std::string_view kHeader = "builtin_interfaces/Time stamp\nstring frame_id\n";
inline constexpr std::string_view kVector3 = "float64 x\nfloat64 y\nfloat64 z\n";
inline constexpr std::string_view kQuaternion = "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n";
inline constexpr std::string_view kTransform = "Vector3 translation\nQuaternion rotation\n";
inline constexpr std::string_view kTransformStamped =
    "std_msgs/Header header\n"
    "string child_frame_id\n"
    "Transform transform\n";
inline constexpr std::string_view kTfMessage = "geometry_msgs/TransformStamped[] transforms\n";
inline constexpr std::string_view kImage =
    "std_msgs/Header header\n"
    "uint32 height\n"
    "uint32 width\n"
    "string encoding\n"
    "uint8 is_bigendian\n"
    "uint32 step\n"
    "uint8[] data\n";
inline constexpr std::string_view kImu =
    "std_msgs/Header header\n"
    "geometry_msgs/Quaternion orientation\n"
    "float64[9] orientation_covariance\n"
    "geometry_msgs/Vector3 angular_velocity\n"
    "float64[9] angular_velocity_covariance\n"
    "geometry_msgs/Vector3 linear_acceleration\n"
    "float64[9] linear_acceleration_covariance\n";
inline constexpr std::string_view kRegionOfInterest =
    "uint32 x_offset\n"
    "uint32 y_offset\n"
    "uint32 height\n"
    "uint32 width\n"
    "bool do_rectify\n";
inline constexpr std::string_view kCameraInfo =
    "std_msgs/Header header\n"
    "uint32 height\n"
    "uint32 width\n"
    "string distortion_model\n"
    "float64[] d\n"
    "float64[9] k\n"
    "float64[9] r\n"
    "float64[12] p\n"
    "uint32 binning_x\n"
    "uint32 binning_y\n"
    "RegionOfInterest roi\n";

inline constexpr std::string_view kFrameStamps =
    "# Every clock's view of one RGB-D frame, so that replay and synccheck can redo the time mapping.\n"
    "# header.stamp: the frame's host time SLAM used (CLOCK_MONOTONIC, mid-exposure).\n"
    "std_msgs/Header header\n"
    "int64 index                    # position of the frame in the recording: 0, 1, 2, ...\n"
    "uint32 device_frame_number     # the camera's own frame counter (DS4 metadata)\n"
    "int64 kernel_mid_exposure_ns   # V4L2 buffer time moved to mid-exposure, host CLOCK_MONOTONIC [ns]\n"
    "int64 device_event_ns          # motion module's frame event mapped to host time [ns]; 0: none\n"
    "int64 device_event_clock_ns    # that event on the device clock, unwrapped ticks as ns; 0: none\n"
    "bool stamped_by_device_event   # true: header.stamp comes from the device event, false: the kernel\n"
    "uint32 depth_sequence          # V4L2 sequence number of the depth buffer\n"
    "uint32 colour_sequence         # V4L2 sequence number of the colour buffer\n"
    "float64 depth_scale_m          # metres per raw depth unit of the frame's 16UC1 image\n";
inline constexpr std::string_view kMotionPacket =
    "# One raw motion-module packet as it came over USB, so every device tick and counter is kept.\n"
    "# header.stamp: host time the USB transfer carrying it completed (CLOCK_MONOTONIC).\n"
    "std_msgs/Header header\n"
    "uint8[] data                   # the packet's bytes (104 for the ZR300 motion module)\n"
    "uint32 transfer_index          # which USB transfer it came in; packets of one transfer share it\n";
inline constexpr std::string_view kSyncEdge =
    "# One edge on the hardware sync line.\n"
    "# header.stamp: when the kernel saw the edge (CLOCK_MONOTONIC, GPIO interrupt time).\n"
    "std_msgs/Header header\n"
    "bool rising                    # true: low to high, false: high to low\n"
    "uint64 sequence                # edge counter since the line was opened; a gap = edges lost\n";
inline constexpr std::string_view kClockMapping =
    "# A device clock's mapping onto host time: host = ref_host_ns + (device - ref_device_ns) * (1 + skew).\n"
    "uint8 STATE_EMPTY=0            # no sample yet: no mapping\n"
    "uint8 STATE_WARMING_UP=1       # offset from the lowest-latency sample only, not yet accurate\n"
    "uint8 STATE_VALID=2            # offset and skew fitted over the full window\n"
    "std_msgs/Header header\n"
    "string device                  # which clock, e.g. zr300_motion\n"
    "uint8 state                    # one of STATE_*\n"
    "int64 ref_device_ns            # reference point, device time [ns]\n"
    "int64 ref_host_ns              # reference point, host time [ns]\n"
    "float64 skew                   # host rate / device rate - 1 [dimensionless]\n"
    "int64 offset_ns                # ref_host_ns - ref_device_ns [ns]\n"
    "float64 skew_ppm               # skew in parts per million\n";
inline constexpr std::string_view kRecordingInfo =
    "# What a recording was made from and with, written once at its start.\n"
    "std_msgs/Header header\n"
    "string source                  # the source spec recorded, e.g. zr300 or sim:living_room_0\n"
    "string vifusion_version\n"
    "string calibration_yaml        # the rig calibration in use, Kalibr-style YAML\n"
    "string mode                    # SLAM mode: rgbd, rgbdi or gyro\n"
    "uint32 width                   # image width [px]\n"
    "uint32 height                  # image height [px]\n"
    "float64 frame_rate_hz          # nominal RGB-D frame rate [Hz]\n"
    "float64 imu_rate_hz            # nominal IMU sample rate [Hz]\n";
}  // namespace msg

/// "MSG: <pkg>/<Type>\n" lines that open each dependency's block.
namespace tag {
inline constexpr std::string_view kTime = "MSG: builtin_interfaces/Time\n";
inline constexpr std::string_view kHeader = "MSG: std_msgs/Header\n";
inline constexpr std::string_view kVector3 = "MSG: geometry_msgs/Vector3\n";
inline constexpr std::string_view kQuaternion = "MSG: geometry_msgs/Quaternion\n";
inline constexpr std::string_view kTransform = "MSG: geometry_msgs/Transform\n";
inline constexpr std::string_view kTransformStamped = "MSG: geometry_msgs/TransformStamped\n";
inline constexpr std::string_view kRegionOfInterest = "MSG: sensor_msgs/RegionOfInterest\n";
}  // namespace tag

/// Complete definitions, dependencies in rosbag2's order (each type's dependencies sorted by name).
inline constexpr std::string_view kTime = msg::kTime;
inline constexpr std::string_view kHeader =
    JoinedText<msg::kHeader, kDefinitionSeparator, tag::kTime, msg::kTime>::kText;
inline constexpr std::string_view kVector3 = msg::kVector3;
inline constexpr std::string_view kQuaternion = msg::kQuaternion;
inline constexpr std::string_view kTransform =
    JoinedText<msg::kTransform, kDefinitionSeparator, tag::kQuaternion, msg::kQuaternion, kDefinitionSeparator,
               tag::kVector3, msg::kVector3>::kText;
inline constexpr std::string_view kTransformStamped =
    JoinedText<msg::kTransformStamped, kDefinitionSeparator, tag::kTransform, msg::kTransform, kDefinitionSeparator,
               tag::kQuaternion, msg::kQuaternion, kDefinitionSeparator, tag::kVector3, msg::kVector3,
               kDefinitionSeparator, tag::kHeader, msg::kHeader, kDefinitionSeparator, tag::kTime, msg::kTime>::kText;
inline constexpr std::string_view kTfMessage =
    JoinedText<msg::kTfMessage, kDefinitionSeparator, tag::kTransformStamped, kTransformStamped>::kText;
inline constexpr std::string_view kImage = JoinedText<msg::kImage, kDefinitionSeparator, tag::kHeader, kHeader>::kText;
inline constexpr std::string_view kImu =
    JoinedText<msg::kImu, kDefinitionSeparator, tag::kQuaternion, msg::kQuaternion, kDefinitionSeparator, tag::kVector3,
               msg::kVector3, kDefinitionSeparator, tag::kHeader, kHeader>::kText;
inline constexpr std::string_view kRegionOfInterest = msg::kRegionOfInterest;
inline constexpr std::string_view kCameraInfo =
    JoinedText<msg::kCameraInfo, kDefinitionSeparator, tag::kRegionOfInterest, msg::kRegionOfInterest,
               kDefinitionSeparator, tag::kHeader, kHeader>::kText;
inline constexpr std::string_view kFrameStamps =
    JoinedText<msg::kFrameStamps, kDefinitionSeparator, tag::kHeader, kHeader>::kText;
inline constexpr std::string_view kMotionPacket =
    JoinedText<msg::kMotionPacket, kDefinitionSeparator, tag::kHeader, kHeader>::kText;
inline constexpr std::string_view kSyncEdge =
    JoinedText<msg::kSyncEdge, kDefinitionSeparator, tag::kHeader, kHeader>::kText;
inline constexpr std::string_view kClockMapping =
    JoinedText<msg::kClockMapping, kDefinitionSeparator, tag::kHeader, kHeader>::kText;
inline constexpr std::string_view kRecordingInfo =
    JoinedText<msg::kRecordingInfo, kDefinitionSeparator, tag::kHeader, kHeader>::kText;

}  // namespace vifusion::ros2_msgs::definitions
