#pragma once
// vifusion_msgs: what a recording must keep that no standard ROS type carries — every clock's stamp of a
// frame, the raw motion-module packets, sync-line edges, the clock mapper's state and what the recording
// was made with. Their definitions (definitions.hpp) are ros2msg text like the standard types', so
// Foxglove and other readers decode them from the bag alone. Strings and bytes are views (time_header.hpp).

#include <cstdint>
#include <span>
#include <string_view>

#include "vifusion/ros2_msgs/cdr_reader.hpp"
#include "vifusion/ros2_msgs/cdr_writer.hpp"
#include "vifusion/ros2_msgs/definitions.hpp"
#include "vifusion/ros2_msgs/time_header.hpp"

namespace vifusion::ros2_msgs {

/// Every clock's view of one RGB-D frame.
struct FrameStamps {
  static constexpr std::string_view kTypeName = "vifusion_msgs/msg/FrameStamps";
  static constexpr std::string_view kDefinition = definitions::kFrameStamps;

  Header header;                            ///< stamp: the host time SLAM used (mid-exposure)
  std::int64_t index = 0;                   ///< position of the frame in the recording: 0, 1, 2, …
  std::uint32_t device_frame_number = 0;    ///< the camera's own frame counter (DS4 metadata)
  std::int64_t kernel_mid_exposure_ns = 0;  ///< V4L2 buffer time moved to mid-exposure [host ns]
  std::int64_t device_event_ns = 0;         ///< motion module's frame event mapped to host [ns]; 0: none
  std::int64_t device_event_clock_ns = 0;   ///< that event on the device clock (unwrapped ticks as ns); 0: none
  bool stamped_by_device_event = false;     ///< header.stamp came from device_event_ns (else the kernel's)
  std::uint32_t depth_sequence = 0;         ///< V4L2 sequence number of the depth buffer
  std::uint32_t colour_sequence = 0;        ///< V4L2 sequence number of the colour buffer
  double depth_scale_m = 0.0;               ///< metres per raw depth unit

  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);
  bool operator==(const FrameStamps&) const = default;
};

/// One raw motion-module packet (104 bytes on the ZR300) as the USB transfer delivered it.
struct MotionPacket {
  static constexpr std::string_view kTypeName = "vifusion_msgs/msg/MotionPacket";
  static constexpr std::string_view kDefinition = definitions::kMotionPacket;

  Header header;                       ///< stamp: host time the USB transfer completed
  std::span<const std::uint8_t> data;  ///< the packet's bytes, a view
  std::uint32_t transfer_index = 0;    ///< which USB transfer; packets of one transfer share it

  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);
};

/// One edge on the hardware sync line.
struct SyncEdge {
  static constexpr std::string_view kTypeName = "vifusion_msgs/msg/SyncEdge";
  static constexpr std::string_view kDefinition = definitions::kSyncEdge;

  Header header;               ///< stamp: when the kernel saw the edge
  bool rising = true;          ///< true: low → high
  std::uint64_t sequence = 0;  ///< edge counter since the line was opened; a gap = edges lost

  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);
  bool operator==(const SyncEdge&) const = default;
};

/// ClockMapping.state, the values of the definition's STATE_* constants (clock::ClockMapperState).
enum class ClockMappingState : std::uint8_t {
  kEmpty = 0,      ///< no sample yet: no mapping
  kWarmingUp = 1,  ///< offset from the lowest-latency sample only
  kValid = 2,      ///< offset and skew fitted
};

/// A device clock's mapping onto host time: host = ref_host_ns + (device − ref_device_ns)·(1 + skew).
struct ClockMapping {
  static constexpr std::string_view kTypeName = "vifusion_msgs/msg/ClockMapping";
  static constexpr std::string_view kDefinition = definitions::kClockMapping;

  Header header;
  std::string_view device;  ///< which clock, e.g. "zr300_motion", a view
  ClockMappingState state = ClockMappingState::kEmpty;
  std::int64_t ref_device_ns = 0;  ///< reference point, device time [ns]
  std::int64_t ref_host_ns = 0;    ///< reference point, host time [ns]
  double skew = 0.0;               ///< host rate / device rate − 1 [dimensionless]
  std::int64_t offset_ns = 0;      ///< ref_host_ns − ref_device_ns [ns]
  double skew_ppm = 0.0;           ///< skew [ppm]

  void serialize(CdrWriter& writer) const;
  /// Throws vifusion::Error for a state other than 0, 1, 2.
  void deserialize(CdrReader& reader);
  bool operator==(const ClockMapping&) const = default;
};

/// What a recording was made from and with; written once at its start.
struct RecordingInfo {
  static constexpr std::string_view kTypeName = "vifusion_msgs/msg/RecordingInfo";
  static constexpr std::string_view kDefinition = definitions::kRecordingInfo;

  Header header;
  std::string_view source;  ///< the source spec recorded ("zr300", "sim:living_room_0")
  std::string_view vifusion_version;
  std::string_view calibration_yaml;  ///< the rig calibration in use, Kalibr-style YAML
  std::string_view mode;              ///< "rgbd", "rgbdi" or "gyro"
  std::uint32_t width = 0;            ///< [px]
  std::uint32_t height = 0;           ///< [px]
  double frame_rate_hz = 0.0;         ///< nominal RGB-D frame rate [Hz]
  double imu_rate_hz = 0.0;           ///< nominal IMU sample rate [Hz]

  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);
  bool operator==(const RecordingInfo&) const = default;
};

}  // namespace vifusion::ros2_msgs
