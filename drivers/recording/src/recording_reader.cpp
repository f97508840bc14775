#include "vifusion/recording/recording_reader.hpp"

#include <algorithm>
#include <cstring>
#include <exception>
#include <string_view>

#include "vifusion/core/error.hpp"
#include "vifusion/datasets/kalibr.hpp"
#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/recording/topics.hpp"
#include "vifusion/ros2_msgs/conversions.hpp"
#include "vifusion/ros2_msgs/geometry_tf.hpp"
#include "vifusion/ros2_msgs/message_io.hpp"
#include "vifusion/ros2_msgs/sensor_msgs.hpp"
#include "vifusion/ros2_msgs/vifusion_msgs.hpp"

namespace vifusion::recording {
namespace {

using namespace ros2_msgs;

constexpr std::string_view kDepthEncoding = "16UC1";
constexpr std::string_view kColourEncoding = "rgb8";

/// The id of `topic`'s channel, 0 when the recording has none.
std::uint16_t channelId(const mcap::McapReader& reader, std::string_view topic) {
  for (const mcap::ChannelInfo& channel : reader.channels()) {
    if (channel.topic == topic) return channel.id;
  }
  return 0;
}

/// Decodes one message, naming the file, topic and message index on failure.
template <class Message>
Message decode(const mcap::McapReader& reader, const mcap::MessageView& message, std::string_view topic) {
  try {
    return deserializeMessage<Message>(message.data);
  } catch (const std::exception& error) {
    throw Error(reader.name() + ": " + std::string(topic) + " message " + std::to_string(message.sequence) + ": " +
                error.what());
  }
}

/// Copies an image message's pixels into `out` (resized when its size differs), checking the encoding.
template <class Pixel>
void copyImage(const ros2_msgs::ImageView& image, std::string_view encoding, const std::string& what,
               Image<Pixel>& out) {
  if (image.encoding != encoding || image.step != image.width * sizeof(Pixel)) {
    throw Error(what + ": encoding '" + std::string(image.encoding) + "' with a step of " + std::to_string(image.step) +
                " bytes, expected " + std::string(encoding) + " with " + std::to_string(image.width * sizeof(Pixel)));
  }
  const int width = static_cast<int>(image.width), height = static_cast<int>(image.height);
  if (out.width() != width || out.height() != height) out.resize(width, height);
  std::memcpy(out.data(), image.data.data(), image.data.size());
}

}  // namespace

RecordingReader::RecordingReader(const std::filesystem::path& path) : path_(path) {
  mcap::McapReader scan_reader(path.string());
  scan(scan_reader);
  images_ = std::make_unique<mcap::McapReader>(path.string());
}

RecordingReader::~RecordingReader() = default;

void RecordingReader::scan(mcap::McapReader& reader) {
  note_ = reader.note();
  const std::uint16_t info = channelId(reader, kTopicRecordingInfo);
  const std::uint16_t imu = channelId(reader, kTopicImu);
  const std::uint16_t edges = channelId(reader, kTopicSyncEdges);
  const std::uint16_t clock = channelId(reader, kTopicClock);
  const std::uint16_t truth = channelId(reader, kTopicGroundTruth);
  const std::uint16_t packets = channelId(reader, kTopicMotionPackets);
  stamps_channel_ = channelId(reader, kTopicFrameStamps);
  depth_channel_ = channelId(reader, kTopicDepth);
  colour_channel_ = channelId(reader, kTopicColour);
  if (info == 0)
    throw Error(reader.name() + ": not a vifusion recording (no " + std::string(kTopicRecordingInfo) + ")");

  bool have_info = false;
  // A frame counts once its stamps, depth and colour, in that order and with one stamp, are all there.
  FrameStampsRecord pending;
  int parts = 0;
  mcap::MessageView message;
  while (reader.readNext(message)) {
    const std::uint16_t id = message.channel_id;
    if (id == 0) continue;
    if (id == info && !have_info) {
      const RecordingInfo recording = decode<RecordingInfo>(reader, message, kTopicRecordingInfo);
      calibration_ = datasets::readCalibrationYamlText(std::string(recording.calibration_yaml),
                                                       path_.filename().string() + " (recording info)");
      source_ = recording.source;
      mode_ = recording.mode;
      frame_rate_hz_ = recording.frame_rate_hz;
      imu_rate_hz_ = recording.imu_rate_hz;
      have_info = true;
    } else if (id == imu) {
      // A damaged or out-of-order sample is left out and named (the estimator sees the hole as a gap).
      try {
        const ImuSample sample = sampleFromImu(decode<Imu>(reader, message, kTopicImu));
        if (!imu_.empty() && sample.t_ns <= imu_.back().t_ns) {
          throw Error(reader.name() + ": " + std::string(kTopicImu) + " message " + std::to_string(message.sequence) +
                      ": time goes backwards by " + std::to_string(imu_.back().t_ns - sample.t_ns) + " ns");
        }
        imu_.push_back(sample);
      } catch (const Error& error) {
        skipped_imu_rows_.push_back(error.what());
      }
    } else if (id == stamps_channel_) {
      if (parts != 0) ++incomplete_frames_;
      const FrameStamps stamps = decode<FrameStamps>(reader, message, kTopicFrameStamps);
      pending = FrameStampsRecord{
          stamps.header.stamp.toNs(), stamps.index,
          FrameTiming{stamps.device_frame_number, stamps.kernel_mid_exposure_ns, stamps.device_event_ns,
                      stamps.device_event_clock_ns, stamps.stamped_by_device_event}};
      parts = 1;
    } else if (id == depth_channel_ || id == colour_channel_) {
      const bool in_order = (id == depth_channel_ ? parts == 1 : parts == 2) && message.publish_time_ns == pending.t_ns;
      if (!in_order) {
        ++incomplete_frames_;
        parts = 0;
        continue;
      }
      parts = id == depth_channel_ ? 2 : 0;
      if (id == colour_channel_) {
        if (!stamps_.empty() && pending.t_ns <= stamps_.back().t_ns) {
          throw Error(reader.name() + ": frame " + std::to_string(pending.index) + ": time goes backwards by " +
                      std::to_string(stamps_.back().t_ns - pending.t_ns) + " ns");
        }
        stamps_.push_back(pending);
      }
    } else if (id == edges) {
      const SyncEdge edge = decode<SyncEdge>(reader, message, kTopicSyncEdges);
      edges_.push_back({edge.header.stamp.toNs(), edge.rising, edge.sequence});
    } else if (id == clock) {
      const ClockMapping mapping = decode<ClockMapping>(reader, message, kTopicClock);
      clocks_.push_back({mapping.header.stamp.toNs(), static_cast<std::uint8_t>(mapping.state), mapping.ref_device_ns,
                         mapping.ref_host_ns, mapping.skew});
    } else if (id == packets) {
      const MotionPacket packet = decode<MotionPacket>(reader, message, kTopicMotionPackets);
      if (packet.data.size() != motion::kPacketBytes) {
        throw Error(reader.name() + ": " + std::string(kTopicMotionPackets) + " message " +
                    std::to_string(message.sequence) + ": " + std::to_string(packet.data.size()) + " bytes, not " +
                    std::to_string(motion::kPacketBytes));
      }
      RecordedMotionPacket& kept = packets_.emplace_back();
      kept.host_receive_ns = packet.header.stamp.toNs();
      kept.transfer_index = packet.transfer_index;
      std::copy(packet.data.begin(), packet.data.end(), kept.bytes.begin());
    } else if (id == truth) {
      const TransformStamped pose = decode<TransformStamped>(reader, message, kTopicGroundTruth);
      ground_truth_.push_back({pose.header.stamp.toNs(), se3FromTransform(pose.transform)});
    }
  }
  if (parts != 0) ++incomplete_frames_;
  if (!have_info) {
    throw Error(reader.name() + ": the recording info message is missing (" + std::string(kTopicRecordingInfo) + ")");
  }
}

bool RecordingReader::nextFrame(RgbdFrame& frame) {
  if (next_frame_ >= stamps_.size()) return false;
  // Past it even when it cannot be read: the caller may skip it, and the next search passes its other messages.
  const FrameStampsRecord& wanted = stamps_[next_frame_++];
  int parts = 0;
  mcap::MessageView message;
  while (images_->readNext(message)) {
    if (message.publish_time_ns != wanted.t_ns) continue;
    if (message.channel_id == stamps_channel_) {
      const FrameStamps stamps = decode<FrameStamps>(*images_, message, kTopicFrameStamps);
      frame.depth_scale_m = stamps.depth_scale_m;
      parts = 1;
    } else if (message.channel_id == depth_channel_ && parts == 1) {
      const ros2_msgs::ImageView image = decode<ros2_msgs::ImageView>(*images_, message, kTopicDepth);
      copyImage(image, kDepthEncoding, images_->name() + ": " + std::string(kTopicDepth), frame.depth);
      parts = 2;
    } else if (message.channel_id == colour_channel_ && parts == 2) {
      const ros2_msgs::ImageView image = decode<ros2_msgs::ImageView>(*images_, message, kTopicColour);
      copyImage(image, kColourEncoding, images_->name() + ": " + std::string(kTopicColour), frame.rgb);
      frame.t_ns = wanted.t_ns;
      frame.index = wanted.index;
      frame.timing = wanted.timing;
      return true;
    }
  }
  throw Error(images_->name() + ": frame " + std::to_string(wanted.index) + " found on the first pass is missing");
}

std::string RecordingReader::describe() const {
  std::string text = "recording " + path_.string() + " (" + source_ + "): " + std::to_string(stamps_.size()) +
                     " frames " + std::to_string(calibration_.camera.width) + "x" +
                     std::to_string(calibration_.camera.height) + ", " + std::to_string(imu_.size()) + " IMU samples";
  if (!note_.empty()) text += "; cut: " + note_;
  if (incomplete_frames_ > 0) text += "; " + std::to_string(incomplete_frames_) + " incomplete frames skipped";
  return text;
}

}  // namespace vifusion::recording
