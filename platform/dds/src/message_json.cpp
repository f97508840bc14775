#include "message_json.hpp"

#include <cstdint>
#include <string>
#include <string_view>

namespace vifusion::dds::detail {
namespace {

// One overload per IDL scalar, so every integer width reaches the right JsonLine::value.
void field(JsonLine& json, std::string_view key, double value) {
  json.key(key);
  json.value(value);
}
void field(JsonLine& json, std::string_view key, float value) {
  json.key(key);
  json.value(value);
}
void field(JsonLine& json, std::string_view key, std::int32_t value) {
  json.key(key);
  json.value(static_cast<std::int64_t>(value));
}
void field(JsonLine& json, std::string_view key, std::int64_t value) {
  json.key(key);
  json.value(value);
}
void field(JsonLine& json, std::string_view key, std::uint8_t value) {
  json.key(key);
  json.value(static_cast<std::uint64_t>(value));
}
void field(JsonLine& json, std::string_view key, std::uint32_t value) {
  json.key(key);
  json.value(static_cast<std::uint64_t>(value));
}
void field(JsonLine& json, std::string_view key, std::uint64_t value) {
  json.key(key);
  json.value(value);
}
void field(JsonLine& json, std::string_view key, bool value) {
  json.key(key);
  json.value(value);
}
void field(JsonLine& json, std::string_view key, const char* value) {
  json.key(key);
  json.value(value);
}

template <std::size_t N>
void field(JsonLine& json, std::string_view key, const double (&values)[N]) {
  json.key(key);
  json.beginArray();
  for (const double v : values) json.value(v);
  json.endArray();
}

/// Runs write(element) for each element of a Cyclone sequence, inside a JSON array under `key`.
template <typename Sequence, typename Write>
void sequence(JsonLine& json, std::string_view key, const Sequence& seq, Write&& write) {
  json.key(key);
  json.beginArray();
  for (std::uint32_t i = 0; i < seq._length; ++i) write(seq._buffer[i]);
  json.endArray();
}

void object(JsonLine& json, std::string_view key, const msg::Time& time) {
  json.key(key);
  json.beginObject();
  field(json, "sec", time.sec);
  field(json, "nanosec", time.nanosec);
  json.endObject();
}

void object(JsonLine& json, std::string_view key, const msg::Header& header) {
  json.key(key);
  json.beginObject();
  object(json, "stamp", header.stamp);
  field(json, "frame_id", header.frame_id);
  json.endObject();
}

void object(JsonLine& json, std::string_view key, const msg::Vector3& v) {
  json.key(key);
  json.beginObject();
  field(json, "x", v.x);
  field(json, "y", v.y);
  field(json, "z", v.z);
  json.endObject();
}

void object(JsonLine& json, std::string_view key, const msg::Point& p) {
  json.key(key);
  json.beginObject();
  field(json, "x", p.x);
  field(json, "y", p.y);
  field(json, "z", p.z);
  json.endObject();
}

void object(JsonLine& json, std::string_view key, const msg::Quaternion& q) {
  json.key(key);
  json.beginObject();
  field(json, "x", q.x);
  field(json, "y", q.y);
  field(json, "z", q.z);
  field(json, "w", q.w);
  json.endObject();
}

void object(JsonLine& json, std::string_view key, const msg::Pose& pose) {
  json.key(key);
  json.beginObject();
  object(json, "position", pose.position);
  object(json, "orientation", pose.orientation);
  json.endObject();
}

void object(JsonLine& json, std::string_view key, const msg::Twist& twist) {
  json.key(key);
  json.beginObject();
  object(json, "linear", twist.linear);
  object(json, "angular", twist.angular);
  json.endObject();
}

void object(JsonLine& json, std::string_view key, const msg::Transform& transform) {
  json.key(key);
  json.beginObject();
  object(json, "translation", transform.translation);
  object(json, "rotation", transform.rotation);
  json.endObject();
}

void members(JsonLine& json, const msg::TransformStamped& message) {
  json.beginObject();
  object(json, "header", message.header);
  field(json, "child_frame_id", message.child_frame_id);
  object(json, "transform", message.transform);
  json.endObject();
}

void object(JsonLine& json, std::string_view key, const msg::RingCounters& ring) {
  json.key(key);
  json.beginObject();
  field(json, "fill", ring.fill);
  field(json, "capacity", ring.capacity);
  field(json, "overruns", ring.overruns);
  json.endObject();
}

}  // namespace

void writeJson(JsonLine& json, const msg::PoseStamped& message, bool) {
  json.beginObject();
  object(json, "header", message.header);
  object(json, "pose", message.pose);
  json.endObject();
}

void writeJson(JsonLine& json, const msg::Odometry& message, bool) {
  json.beginObject();
  object(json, "header", message.header);
  field(json, "child_frame_id", message.child_frame_id);
  json.key("pose");
  json.beginObject();
  object(json, "pose", message.pose.pose);
  field(json, "covariance", message.pose.covariance);
  json.endObject();
  json.key("twist");
  json.beginObject();
  object(json, "twist", message.twist.twist);
  field(json, "covariance", message.twist.covariance);
  json.endObject();
  json.endObject();
}

void writeJson(JsonLine& json, const msg::TFMessage& message, bool) {
  json.beginObject();
  sequence(json, "transforms", message.transforms, [&json](const msg::TransformStamped& t) { members(json, t); });
  json.endObject();
}

void writeJson(JsonLine& json, const msg::PointCloud2& message, bool full_arrays) {
  json.beginObject();
  object(json, "header", message.header);
  field(json, "height", message.height);
  field(json, "width", message.width);
  sequence(json, "fields", message.fields, [&json](const msg::PointField& f) {
    json.beginObject();
    field(json, "name", f.name);
    field(json, "offset", f.offset);
    field(json, "datatype", f.datatype);
    field(json, "count", f.count);
    json.endObject();
  });
  field(json, "is_bigendian", message.is_bigendian);
  field(json, "point_step", message.point_step);
  field(json, "row_step", message.row_step);
  if (full_arrays) {
    sequence(json, "data", message.data, [&json](std::uint8_t byte) { json.value(static_cast<std::uint64_t>(byte)); });
  } else {
    // As `ros2 topic echo --no-arr`: a map chunk is megabytes, nobody reads it as numbers.
    field(json, "data", ("<sequence type: uint8, length: " + std::to_string(message.data._length) + ">").c_str());
  }
  field(json, "is_dense", message.is_dense);
  json.endObject();
}

void writeJson(JsonLine& json, const msg::DiagnosticArray& message, bool) {
  json.beginObject();
  object(json, "header", message.header);
  sequence(json, "status", message.status, [&json](const msg::DiagnosticStatus& s) {
    json.beginObject();
    field(json, "level", s.level);
    field(json, "name", s.name);
    field(json, "message", s.message);
    field(json, "hardware_id", s.hardware_id);
    sequence(json, "values", s.values, [&json](const msg::KeyValue& kv) {
      json.beginObject();
      field(json, "key", kv.key);
      field(json, "value", kv.value);
      json.endObject();
    });
    json.endObject();
  });
  json.endObject();
}

void writeJson(JsonLine& json, const msg::ImuState& message, bool) {
  json.beginObject();
  object(json, "header", message.header);
  object(json, "velocity", message.velocity);
  object(json, "gyro_bias", message.gyro_bias);
  object(json, "accel_bias", message.accel_bias);
  object(json, "gravity_direction", message.gravity_direction);
  field(json, "velocity_covariance", message.velocity_covariance);
  field(json, "gyro_bias_covariance", message.gyro_bias_covariance);
  field(json, "accel_bias_covariance", message.accel_bias_covariance);
  field(json, "gravity_direction_covariance", message.gravity_direction_covariance);
  json.endObject();
}

void writeJson(JsonLine& json, const msg::Status& message, bool) {
  json.beginObject();
  object(json, "header", message.header);
  field(json, "heartbeat", message.heartbeat);
  field(json, "frame_rate_hz", message.frame_rate_hz);
  field(json, "latency_ms", message.latency_ms);
  field(json, "latency_p50_ms", message.latency_p50_ms);
  field(json, "latency_p99_ms", message.latency_p99_ms);
  field(json, "latency_max_ms", message.latency_max_ms);
  object(json, "camera_ring", message.camera_ring);
  object(json, "imu_ring", message.imu_ring);
  object(json, "output_ring", message.output_ring);
  field(json, "tracking_state", message.tracking_state);
  field(json, "surfel_count", message.surfel_count);
  field(json, "frames_processed", message.frames_processed);
  field(json, "lost_frames", message.lost_frames);
  field(json, "imu_issue_frames", message.imu_issue_frames);
  field(json, "imu_carried_frames", message.imu_carried_frames);
  field(json, "closures_accepted", message.closures_accepted);
  field(json, "closures_refused", message.closures_refused);
  field(json, "closures_agreed", message.closures_agreed);
  field(json, "relocalisations", message.relocalisations);
  field(json, "frames_skipped", message.frames_skipped);
  field(json, "frames_unreadable", message.frames_unreadable);
  field(json, "imu_samples_unreadable", message.imu_samples_unreadable);
  field(json, "source_present", message.source_present);
  field(json, "source_reopens", message.source_reopens);
  field(json, "clock_offset_ns", message.clock_offset_ns);
  field(json, "clock_skew_ppm", message.clock_skew_ppm);
  field(json, "sync_edge_rate_hz", message.sync_edge_rate_hz);
  field(json, "sync_edges", message.sync_edges);
  field(json, "map_saves", message.map_saves);
  field(json, "map_save_failures", message.map_save_failures);
  field(json, "map_save_request_done", message.map_save_request_done);
  field(json, "map_file_bytes", message.map_file_bytes);
  field(json, "map_capture_ms", message.map_capture_ms);
  field(json, "map_write_ms", message.map_write_ms);
  field(json, "vifusion_version", message.vifusion_version);
  json.endObject();
}

void writeJson(JsonLine& json, const msg::MapSaveRequest& message, bool) {
  json.beginObject();
  field(json, "request_id", message.request_id);
  json.endObject();
}

}  // namespace vifusion::dds::detail
