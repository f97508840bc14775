// Writes one serialised message of every type for an independent decoder (tests/node/decode_cdr.mjs,
// Foxglove's ROS 2 libraries): in DIR, for each message NAME.cdr (the CDR bytes) and NAME.msgdef (its
// type's kDefinition), manifest.json (name, type, files) and expected.json (every field's value as
// decode_cdr.mjs prints what it decoded). Usage: ros2_msgs_write_fixtures DIR

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "json_writer.hpp"
#include "sample_messages.hpp"
#include "vifusion/ros2_msgs/message_io.hpp"

namespace vifusion::ros2_msgs::test {
namespace {

void writeValue(JsonWriter& json, const Time& time) {
  json.beginObject().key("sec").integer(time.sec).key("nanosec").integer(time.nanosec).endObject();
}

void writeValue(JsonWriter& json, const Header& header) {
  json.beginObject().key("stamp");
  writeValue(json, header.stamp);
  json.key("frame_id").string(header.frame_id).endObject();
}

void writeValue(JsonWriter& json, const Vector3& vector) {
  json.beginObject().key("x").number(vector.x).key("y").number(vector.y).key("z").number(vector.z).endObject();
}

void writeValue(JsonWriter& json, const Quaternion& q) {
  json.beginObject().key("x").number(q.x).key("y").number(q.y).key("z").number(q.z).key("w").number(q.w).endObject();
}

void writeNumbers(JsonWriter& json, std::span<const double> values) {
  json.beginArray();
  for (double value : values) json.number(value);
  json.endArray();
}

void writeBytes(JsonWriter& json, std::span<const std::uint8_t> bytes) {
  json.beginArray();
  for (std::uint8_t byte : bytes) json.integer(byte);
  json.endArray();
}

void writeValue(JsonWriter& json, const ImageView& image) {
  json.beginObject().key("header");
  writeValue(json, image.header);
  json.key("height").integer(image.height).key("width").integer(image.width);
  json.key("encoding").string(image.encoding).key("is_bigendian").integer(image.is_bigendian);
  json.key("step").integer(image.step).key("data");
  writeBytes(json, image.data);
  json.endObject();
}

void writeValue(JsonWriter& json, const Imu& imu) {
  json.beginObject().key("header");
  writeValue(json, imu.header);
  json.key("orientation");
  writeValue(json, imu.orientation);
  json.key("orientation_covariance");
  writeNumbers(json, imu.orientation_covariance);
  json.key("angular_velocity");
  writeValue(json, imu.angular_velocity);
  json.key("angular_velocity_covariance");
  writeNumbers(json, imu.angular_velocity_covariance);
  json.key("linear_acceleration");
  writeValue(json, imu.linear_acceleration);
  json.key("linear_acceleration_covariance");
  writeNumbers(json, imu.linear_acceleration_covariance);
  json.endObject();
}

void writeValue(JsonWriter& json, const CameraInfo& info) {
  json.beginObject().key("header");
  writeValue(json, info.header);
  json.key("height").integer(info.height).key("width").integer(info.width);
  json.key("distortion_model").string(info.distortion_model);
  json.key("d");
  writeNumbers(json, info.distortion());
  json.key("k");
  writeNumbers(json, info.k);
  json.key("r");
  writeNumbers(json, info.r);
  json.key("p");
  writeNumbers(json, info.p);
  json.key("binning_x").integer(info.binning_x).key("binning_y").integer(info.binning_y);
  json.key("roi").beginObject();
  json.key("x_offset").integer(info.roi.x_offset).key("y_offset").integer(info.roi.y_offset);
  json.key("height").integer(info.roi.height).key("width").integer(info.roi.width);
  json.key("do_rectify").boolean(info.roi.do_rectify).endObject();
  json.endObject();
}

void writeValue(JsonWriter& json, const TransformStamped& transform) {
  json.beginObject().key("header");
  writeValue(json, transform.header);
  json.key("child_frame_id").string(transform.child_frame_id);
  json.key("transform").beginObject().key("translation");
  writeValue(json, transform.transform.translation);
  json.key("rotation");
  writeValue(json, transform.transform.rotation);
  json.endObject().endObject();
}

void writeValue(JsonWriter& json, const TfMessage& message) {
  json.beginObject().key("transforms").beginArray();
  for (const TransformStamped& transform : message.active()) writeValue(json, transform);
  json.endArray().endObject();
}

void writeValue(JsonWriter& json, const FrameStamps& stamps) {
  json.beginObject().key("header");
  writeValue(json, stamps.header);
  json.key("index").bigInteger(stamps.index);
  json.key("device_frame_number").integer(stamps.device_frame_number);
  json.key("kernel_mid_exposure_ns").bigInteger(stamps.kernel_mid_exposure_ns);
  json.key("device_event_ns").bigInteger(stamps.device_event_ns);
  json.key("device_event_clock_ns").bigInteger(stamps.device_event_clock_ns);
  json.key("stamped_by_device_event").boolean(stamps.stamped_by_device_event);
  json.key("depth_sequence").integer(stamps.depth_sequence);
  json.key("colour_sequence").integer(stamps.colour_sequence);
  json.key("depth_scale_m").number(stamps.depth_scale_m);
  json.endObject();
}

void writeValue(JsonWriter& json, const MotionPacket& packet) {
  json.beginObject().key("header");
  writeValue(json, packet.header);
  json.key("data");
  writeBytes(json, packet.data);
  json.key("transfer_index").integer(packet.transfer_index).endObject();
}

void writeValue(JsonWriter& json, const SyncEdge& edge) {
  json.beginObject().key("header");
  writeValue(json, edge.header);
  json.key("rising").boolean(edge.rising).key("sequence").bigUnsigned(edge.sequence).endObject();
}

void writeValue(JsonWriter& json, const ClockMapping& mapping) {
  json.beginObject().key("header");
  writeValue(json, mapping.header);
  json.key("device").string(mapping.device);
  json.key("state").integer(static_cast<std::uint8_t>(mapping.state));
  json.key("ref_device_ns").bigInteger(mapping.ref_device_ns);
  json.key("ref_host_ns").bigInteger(mapping.ref_host_ns);
  json.key("skew").number(mapping.skew);
  json.key("offset_ns").bigInteger(mapping.offset_ns);
  json.key("skew_ppm").number(mapping.skew_ppm);
  json.endObject();
}

void writeValue(JsonWriter& json, const RecordingInfo& info) {
  json.beginObject().key("header");
  writeValue(json, info.header);
  json.key("source").string(info.source).key("vifusion_version").string(info.vifusion_version);
  json.key("calibration_yaml").string(info.calibration_yaml).key("mode").string(info.mode);
  json.key("width").integer(info.width).key("height").integer(info.height);
  json.key("frame_rate_hz").number(info.frame_rate_hz).key("imu_rate_hz").number(info.imu_rate_hz);
  json.endObject();
}

class FixtureWriter {
 public:
  explicit FixtureWriter(std::filesystem::path directory) : directory_(std::move(directory)) {
    manifest_.beginArray();
    expected_.beginObject();
  }

  template <CdrMessage Message>
  void add(std::string_view name, const Message& message) {
    std::vector<std::uint8_t> bytes(serializedSize(message));
    const CdrWriter writer = serializeMessage(message, bytes);
    if (!writer.ok()) throw std::runtime_error(std::string(name) + ": " + std::string(writer.failure()));
    const std::string stem(name);
    writeFile(stem + ".cdr", std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
    writeFile(stem + ".msgdef", Message::kDefinition);

    manifest_.beginObject().key("name").string(name).key("type").string(Message::kTypeName);
    manifest_.key("cdr").string(stem + ".cdr").key("definition").string(stem + ".msgdef").endObject();

    expected_.key(name).beginObject().key("type").string(Message::kTypeName);
    // Foxglove's reader must consume every byte we wrote, no more, no fewer.
    expected_.key("bytes").integer(static_cast<std::int64_t>(bytes.size()));
    expected_.key("decoded_bytes").integer(static_cast<std::int64_t>(bytes.size()));
    expected_.key("message");
    writeValue(expected_, message);
    expected_.endObject();
  }

  void finish() {
    writeFile("manifest.json", manifest_.endArray().text() + "\n");
    writeFile("expected.json", expected_.endObject().text() + "\n");
  }

 private:
  void writeFile(const std::string& name, std::string_view content) const {
    std::ofstream file(directory_ / name, std::ios::binary | std::ios::trunc);
    file.write(content.data(), static_cast<std::streamsize>(content.size()));
    if (!file) throw std::runtime_error("cannot write " + (directory_ / name).string());
  }

  std::filesystem::path directory_;
  JsonWriter manifest_;
  JsonWriter expected_;
};

}  // namespace
}  // namespace vifusion::ros2_msgs::test

int main(int argc, char** argv) {
  using namespace vifusion::ros2_msgs;
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  try {
    std::filesystem::create_directories(argv[1]);
    const test::SampleMessages samples;
    test::FixtureWriter fixtures(argv[1]);
    fixtures.add("time", samples.time);
    fixtures.add("header", samples.header);
    fixtures.add("image_depth", samples.depth);
    fixtures.add("image_rgb", samples.rgb);
    fixtures.add("image_yuyv", samples.yuyv);
    fixtures.add("imu", samples.imu);
    fixtures.add("camera_info_plumb_bob", samples.camera_info_plumb_bob);
    fixtures.add("camera_info_equidistant", samples.camera_info_equidistant);
    fixtures.add("transform_stamped", samples.transform);
    fixtures.add("tf_static", samples.tf_static);
    fixtures.add("frame_stamps", samples.frame_stamps);
    fixtures.add("motion_packet", samples.motion_packet);
    fixtures.add("sync_edge", samples.sync_edge);
    fixtures.add("clock_mapping", samples.clock_mapping);
    fixtures.add("recording_info", samples.recording_info);
    fixtures.finish();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ros2_msgs_write_fixtures: %s\n", e.what());
    return 1;
  }
  return 0;
}
