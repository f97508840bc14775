#include "vifusion/recording/recording_file.hpp"

#include <exception>
#include <string_view>

#include "vifusion/core/error.hpp"
#include "vifusion/core/version.hpp"
#include "vifusion/datasets/kalibr.hpp"
#include "vifusion/motion/packet_format.hpp"
#include "vifusion/recording/topics.hpp"
#include "vifusion/ros2_msgs/cdr_encoding.hpp"
#include "vifusion/ros2_msgs/conversions.hpp"
#include "vifusion/ros2_msgs/geometry_tf.hpp"
#include "vifusion/ros2_msgs/message_io.hpp"
#include "vifusion/ros2_msgs/sensor_msgs.hpp"
#include "vifusion/ros2_msgs/vifusion_msgs.hpp"

namespace vifusion::recording {
namespace {

using namespace ros2_msgs;

std::span<const std::uint8_t> bytesOf(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

template <class Message>
std::uint16_t schemaFor(mcap::McapWriter& writer) {
  return writer.registerSchema(Message::kTypeName, kMcapSchemaEncoding, bytesOf(Message::kDefinition));
}

}  // namespace

/// One channel and its message counter per topic.
struct RecordingFile::Channels {
  std::uint16_t info = 0, colour_info = 0, depth_info = 0, tf_static = 0, stamps = 0, depth = 0, colour = 0, imu = 0,
                edges = 0, clock = 0, ground_truth = 0, motion = 0;
  std::uint32_t info_seq = 0, colour_info_seq = 0, depth_info_seq = 0, tf_static_seq = 0, stamps_seq = 0, depth_seq = 0,
                colour_seq = 0, imu_seq = 0, edges_seq = 0, clock_seq = 0, ground_truth_seq = 0, motion_seq = 0;
};

RecordingFile::RecordingFile(const mcap::McapWriterOptions& options)
    : writer_(options), channels_(std::make_unique<Channels>()) {}

RecordingFile::~RecordingFile() = default;

void RecordingFile::fail(const char* what, const std::exception& error) {
  if (problem_.empty()) problem_ = std::string(what) + ": " + error.what();
}

template <class Message>
bool RecordingFile::put(std::uint16_t channel, std::uint32_t& sequence, const Message& message,
                        std::int64_t log_time_ns, std::int64_t publish_time_ns) {
  if (failed()) return false;
  const std::span<std::uint8_t> space = writer_.reserveMessage(writer_.options().max_message_bytes);
  if (space.empty()) return false;
  const CdrWriter cdr = serializeMessage(message, space);
  if (!cdr.ok()) {
    if (problem_.empty()) {
      problem_ = std::string(Message::kTypeName) + " could not be encoded: " +
                 (cdr.overflowed() ? std::to_string(cdr.size()) + " bytes exceed the largest message"
                                   : std::string(cdr.failure()));
    }
    return false;
  }
  return writer_.commitMessage(channel, sequence++, log_time_ns, publish_time_ns, cdr.size());
}

bool RecordingFile::open(const std::filesystem::path& path, const RecordingHeader& header) {
  if (!(header.frame_rate_hz > 0.0)) throw Error("recording: frame_rate_hz must be > 0");
  const RigCalibration& calibration = header.calibration;
  const PinholeCamera& depth_camera = calibration.depth_camera ? calibration.depth_camera->camera : calibration.camera;
  colour_width_ = calibration.camera.width;
  colour_height_ = calibration.camera.height;
  depth_width_ = depth_camera.width;
  depth_height_ = depth_camera.height;
  const std::size_t colour_bytes = static_cast<std::size_t>(colour_width_) * colour_height_ * sizeof(Rgb8);
  if (colour_bytes + 4096 > writer_.options().max_message_bytes) {
    throw Error("recording: a " + std::to_string(colour_width_) + "x" + std::to_string(colour_height_) +
                " colour image does not fit the largest message (" +
                std::to_string(writer_.options().max_message_bytes) + " bytes)");
  }
  if (!writer_.open(path.string())) return false;

  Channels& c = *channels_;
  const std::uint16_t info_schema = schemaFor<RecordingInfo>(writer_);
  const std::uint16_t camera_info_schema = schemaFor<CameraInfo>(writer_);
  const std::uint16_t tf_schema = schemaFor<TfMessage>(writer_);
  const std::uint16_t stamps_schema = schemaFor<FrameStamps>(writer_);
  const std::uint16_t image_schema = schemaFor<ros2_msgs::ImageView>(writer_);
  const std::uint16_t imu_schema = schemaFor<Imu>(writer_);
  const std::uint16_t edge_schema = schemaFor<SyncEdge>(writer_);
  const std::uint16_t clock_schema = schemaFor<ClockMapping>(writer_);
  const std::uint16_t transform_schema = schemaFor<TransformStamped>(writer_);
  const std::uint16_t packet_schema = schemaFor<MotionPacket>(writer_);
  const auto channel = [&](std::string_view topic, std::uint16_t schema) {
    return writer_.registerChannel(topic, schema, kMcapMessageEncoding);
  };
  c.info = channel(kTopicRecordingInfo, info_schema);
  c.colour_info = channel(kTopicColourInfo, camera_info_schema);
  c.depth_info = channel(kTopicDepthInfo, camera_info_schema);
  c.tf_static = writer_.registerChannel(kTopicTfStatic, tf_schema, kMcapMessageEncoding,
                                        {{"offered_qos_profiles", "transient_local"}});
  c.stamps = channel(kTopicFrameStamps, stamps_schema);
  c.depth = channel(kTopicDepth, image_schema);
  c.colour = channel(kTopicColour, image_schema);
  c.imu = channel(kTopicImu, imu_schema);
  c.edges = channel(kTopicSyncEdges, edge_schema);
  c.clock = channel(kTopicClock, clock_schema);
  c.ground_truth = channel(kTopicGroundTruth, transform_schema);
  c.motion = channel(kTopicMotionPackets, packet_schema);
  if (writer_.failed()) return false;

  const std::string yaml = datasets::calibrationYamlText(calibration);
  const std::int64_t t_ns = header.t_ns;
  try {
    RecordingInfo info;
    info.header = makeHeader(t_ns, "");
    info.source = header.source;
    info.vifusion_version = versionString();
    info.calibration_yaml = yaml;
    info.mode = header.mode;
    info.width = static_cast<std::uint32_t>(colour_width_);
    info.height = static_cast<std::uint32_t>(colour_height_);
    info.frame_rate_hz = header.frame_rate_hz;
    info.imu_rate_hz = header.imu_rate_hz;
    put(c.info, c.info_seq, info, t_ns, t_ns);
    put(c.colour_info, c.colour_info_seq, cameraInfoFromPinhole(calibration.camera, makeHeader(t_ns, kFrameColour)),
        t_ns, t_ns);
    put(c.depth_info, c.depth_info_seq,
        cameraInfoFromPinhole(depth_camera, makeHeader(t_ns, calibration.depth_camera ? kFrameDepth : kFrameColour)),
        t_ns, t_ns);
    TfMessage tf;
    tf.add(TransformStamped{makeHeader(t_ns, kFrameColour), kFrameImu, transformFromSe3(calibration.T_S_C.inverse())});
    if (calibration.depth_camera) {
      tf.add(TransformStamped{makeHeader(t_ns, kFrameColour), kFrameDepth,
                              transformFromSe3(calibration.depth_camera->T_C_D)});
    }
    put(c.tf_static, c.tf_static_seq, tf, t_ns, t_ns);
  } catch (const std::exception& error) {
    fail("recording header", error);
    return false;
  }
  writer_.writeAttachment(kCalibrationAttachment, "application/yaml", bytesOf(yaml), t_ns, t_ns);
  // On disk at once: a recording cut right after it started still says what it is and holds its calibration.
  writer_.flush();
  return !failed();
}

bool RecordingFile::writeFrame(const RgbdFrame& frame, std::int64_t log_time_ns) {
  if (frame.depth.width() != depth_width_ || frame.depth.height() != depth_height_ ||
      frame.rgb.width() != colour_width_ || frame.rgb.height() != colour_height_) {
    if (problem_.empty()) {
      problem_ = "frame " + std::to_string(frame.index) + ": images of " + std::to_string(frame.depth.width()) + "x" +
                 std::to_string(frame.depth.height()) + " depth and " + std::to_string(frame.rgb.width()) + "x" +
                 std::to_string(frame.rgb.height()) + " colour, not the calibration's sizes";
    }
    return false;
  }
  Channels& c = *channels_;
  try {
    const Header depth_header = makeHeader(frame.t_ns, kFrameDepth);
    const Header colour_header = makeHeader(frame.t_ns, kFrameColour);
    FrameStamps stamps;
    stamps.header = colour_header;
    stamps.index = frame.index;
    stamps.device_frame_number = frame.timing.device_frame_number;
    stamps.kernel_mid_exposure_ns = frame.timing.kernel_mid_exposure_ns;
    stamps.device_event_ns = frame.timing.device_event_ns;
    stamps.device_event_clock_ns = frame.timing.device_event_clock_ns;
    stamps.stamped_by_device_event = frame.timing.stamped_by_device_event;
    stamps.depth_scale_m = frame.depth_scale_m;
    const bool ok = put(c.stamps, c.stamps_seq, stamps, log_time_ns, frame.t_ns) &&
                    put(c.depth, c.depth_seq, depthImageView(depth_header, frame.depth), log_time_ns, frame.t_ns) &&
                    put(c.colour, c.colour_seq, rgbImageView(colour_header, frame.rgb), log_time_ns, frame.t_ns);
    if (ok) ++counts_.frames;
    return ok;
  } catch (const std::exception& error) {
    fail("frame", error);
    return false;
  }
}

bool RecordingFile::writeImu(const ImuSample& sample, std::int64_t log_time_ns) {
  try {
    const bool ok = put(channels_->imu, channels_->imu_seq, imuFromSample(sample, kFrameImu), log_time_ns, sample.t_ns);
    if (ok) ++counts_.imu_samples;
    return ok;
  } catch (const std::exception& error) {
    fail("IMU sample", error);
    return false;
  }
}

bool RecordingFile::writeSyncEdge(std::int64_t t_ns, bool rising, std::uint64_t sequence, std::int64_t log_time_ns) {
  try {
    const bool ok = put(channels_->edges, channels_->edges_seq,
                        SyncEdge{makeHeader(t_ns, kFrameSyncLine), rising, sequence}, log_time_ns, t_ns);
    if (ok) ++counts_.sync_edges;
    return ok;
  } catch (const std::exception& error) {
    fail("sync edge", error);
    return false;
  }
}

bool RecordingFile::writeClock(const ClockRecord& clock, std::int64_t log_time_ns) {
  try {
    ClockMapping mapping;
    mapping.header = makeHeader(clock.t_ns, "");
    mapping.device = kMotionClock;
    mapping.state = static_cast<ClockMappingState>(clock.state);
    mapping.ref_device_ns = clock.ref_device_ns;
    mapping.ref_host_ns = clock.ref_host_ns;
    mapping.skew = clock.skew;
    mapping.offset_ns = clock.ref_host_ns - clock.ref_device_ns;
    mapping.skew_ppm = clock.skew * 1e6;
    const bool ok = put(channels_->clock, channels_->clock_seq, mapping, log_time_ns, clock.t_ns);
    if (ok) ++counts_.clock_records;
    return ok;
  } catch (const std::exception& error) {
    fail("clock mapping", error);
    return false;
  }
}

bool RecordingFile::writeMotionTransfer(std::int64_t host_receive_ns, std::uint32_t transfer_index,
                                        std::span<const std::uint8_t> bytes, std::int64_t log_time_ns) {
  try {
    const Header header = makeHeader(host_receive_ns, kFrameMotionModule);
    // Whole packets only: a short transfer's tail (counted by the driver) carries no complete packet.
    for (std::size_t at = 0; at + motion::kPacketBytes <= bytes.size(); at += motion::kPacketBytes) {
      const MotionPacket packet{header, bytes.subspan(at, motion::kPacketBytes), transfer_index};
      if (!put(channels_->motion, channels_->motion_seq, packet, log_time_ns, host_receive_ns)) return false;
      ++counts_.motion_packets;
    }
    return true;
  } catch (const std::exception& error) {
    fail("motion transfer", error);
    return false;
  }
}

bool RecordingFile::writeGroundTruthPose(std::int64_t t_ns, const SE3d& T_W_C, std::int64_t log_time_ns) {
  try {
    const TransformStamped pose{makeHeader(t_ns, kFrameWorld), kFrameColour, transformFromSe3(T_W_C)};
    const bool ok = put(channels_->ground_truth, channels_->ground_truth_seq, pose, log_time_ns, t_ns);
    if (ok) ++counts_.ground_truth_poses;
    return ok;
  } catch (const std::exception& error) {
    fail("ground-truth pose", error);
    return false;
  }
}

bool RecordingFile::flushIfDue(std::int64_t now_ns) { return !failed() && writer_.flushIfDue(now_ns); }

bool RecordingFile::close() {
  const bool closed = writer_.close();
  return closed && problem_.empty();
}

}  // namespace vifusion::recording
