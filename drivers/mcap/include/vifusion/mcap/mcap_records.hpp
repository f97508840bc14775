#pragma once
// What a recording holds besides message bytes, as the reader gives it and the writer takes it: schemas,
// channels, attachments, statistics, where the chunks lie, and the view of one message.
// Times are int64 ns on the recording's clock (vifusion: host CLOCK_MONOTONIC); MCAP stores them as u64.

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace vifusion::mcap {

/// A message definition (ROS 2: name "sensor_msgs/msg/Imu", encoding "ros2msg", data the .msg text).
struct SchemaInfo {
  std::uint16_t id = 0;  ///< 1..65535; 0 means "no schema" and is never a schema's id
  std::string name;
  std::string encoding;
  std::vector<std::uint8_t> data;
};

/// A topic: its messages share one schema and one message encoding (ROS 2: "cdr").
struct ChannelInfo {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;  ///< 0: messages without a schema
  std::string topic;
  std::string message_encoding;
  std::map<std::string, std::string> metadata;  ///< ROS 2: "offered_qos_profiles" and the like
};

/// A file stored beside the messages (vifusion: the rig's calibration YAML).
struct AttachmentInfo {
  std::string name;
  std::string media_type;  ///< e.g. "application/yaml"
  std::int64_t log_time_ns = 0;
  std::int64_t create_time_ns = 0;  ///< 0: unknown
  std::vector<std::uint8_t> data;
};

/// The Statistics record: counts over the whole file (or, for a cut file, over what the reader accepted).
struct McapStatistics {
  std::uint64_t message_count = 0;
  std::uint16_t schema_count = 0;
  std::uint32_t channel_count = 0;
  std::uint32_t attachment_count = 0;
  std::uint32_t metadata_count = 0;
  std::uint32_t chunk_count = 0;
  std::int64_t message_start_time_ns = 0;  ///< earliest log_time; 0 without messages
  std::int64_t message_end_time_ns = 0;    ///< latest log_time; 0 without messages
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
};

/// Where one chunk lies in the file and what it holds.
struct ChunkInfo {
  std::uint64_t offset = 0;         ///< file offset of the Chunk record's opcode byte
  std::uint64_t record_bytes = 0;   ///< the whole Chunk record, opcode and length included
  std::uint64_t records_bytes = 0;  ///< its (uncompressed) records field
  std::int64_t message_start_time_ns = 0;
  std::int64_t message_end_time_ns = 0;
};

/// One message as readNext() gives it; `data` points into the reader's chunk buffer and is valid until
/// the next readNext() or rewind().
struct MessageView {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::int64_t log_time_ns = 0;      ///< when it was recorded
  std::int64_t publish_time_ns = 0;  ///< when it was published (the sensor's time for vifusion)
  std::span<const std::uint8_t> data;
};

}  // namespace vifusion::mcap
