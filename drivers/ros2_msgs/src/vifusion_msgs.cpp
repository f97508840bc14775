#include "vifusion/ros2_msgs/vifusion_msgs.hpp"

#include <string>

namespace vifusion::ros2_msgs {

void FrameStamps::serialize(CdrWriter& writer) const {
  header.serialize(writer);
  writer.writeInt64(index);
  writer.writeUint32(device_frame_number);
  writer.writeInt64(kernel_mid_exposure_ns);
  writer.writeInt64(device_event_ns);
  writer.writeInt64(device_event_clock_ns);
  writer.writeBool(stamped_by_device_event);
  writer.writeUint32(depth_sequence);
  writer.writeUint32(colour_sequence);
  writer.writeFloat64(depth_scale_m);
}

void FrameStamps::deserialize(CdrReader& reader) {
  readNested(reader, "header", header);
  index = reader.readInt64("index");
  device_frame_number = reader.readUint32("device_frame_number");
  kernel_mid_exposure_ns = reader.readInt64("kernel_mid_exposure_ns");
  device_event_ns = reader.readInt64("device_event_ns");
  device_event_clock_ns = reader.readInt64("device_event_clock_ns");
  stamped_by_device_event = reader.readBool("stamped_by_device_event");
  depth_sequence = reader.readUint32("depth_sequence");
  colour_sequence = reader.readUint32("colour_sequence");
  depth_scale_m = reader.readFloat64("depth_scale_m");
}

void MotionPacket::serialize(CdrWriter& writer) const {
  header.serialize(writer);
  writer.writeUint8Sequence(data);
  writer.writeUint32(transfer_index);
}

void MotionPacket::deserialize(CdrReader& reader) {
  readNested(reader, "header", header);
  data = reader.readUint8Sequence("data");
  transfer_index = reader.readUint32("transfer_index");
}

void SyncEdge::serialize(CdrWriter& writer) const {
  header.serialize(writer);
  writer.writeBool(rising);
  writer.writeUint64(sequence);
}

void SyncEdge::deserialize(CdrReader& reader) {
  readNested(reader, "header", header);
  rising = reader.readBool("rising");
  sequence = reader.readUint64("sequence");
}

void ClockMapping::serialize(CdrWriter& writer) const {
  header.serialize(writer);
  writer.writeString(device);
  writer.writeUint8(static_cast<std::uint8_t>(state));
  writer.writeInt64(ref_device_ns);
  writer.writeInt64(ref_host_ns);
  writer.writeFloat64(skew);
  writer.writeInt64(offset_ns);
  writer.writeFloat64(skew_ppm);
}

void ClockMapping::deserialize(CdrReader& reader) {
  readNested(reader, "header", header);
  device = reader.readString("device");
  const std::uint8_t raw_state = reader.readUint8("state");
  if (raw_state > static_cast<std::uint8_t>(ClockMappingState::kValid)) {
    reader.failAt(reader.offset() - sizeof(raw_state), "state",
                  std::to_string(raw_state) + " is none of STATE_EMPTY (0), STATE_WARMING_UP (1), STATE_VALID (2)");
  }
  state = static_cast<ClockMappingState>(raw_state);
  ref_device_ns = reader.readInt64("ref_device_ns");
  ref_host_ns = reader.readInt64("ref_host_ns");
  skew = reader.readFloat64("skew");
  offset_ns = reader.readInt64("offset_ns");
  skew_ppm = reader.readFloat64("skew_ppm");
}

void RecordingInfo::serialize(CdrWriter& writer) const {
  header.serialize(writer);
  writer.writeString(source);
  writer.writeString(vifusion_version);
  writer.writeString(calibration_yaml);
  writer.writeString(mode);
  writer.writeUint32(width);
  writer.writeUint32(height);
  writer.writeFloat64(frame_rate_hz);
  writer.writeFloat64(imu_rate_hz);
}

void RecordingInfo::deserialize(CdrReader& reader) {
  readNested(reader, "header", header);
  source = reader.readString("source");
  vifusion_version = reader.readString("vifusion_version");
  calibration_yaml = reader.readString("calibration_yaml");
  mode = reader.readString("mode");
  width = reader.readUint32("width");
  height = reader.readUint32("height");
  frame_rate_hz = reader.readFloat64("frame_rate_hz");
  imu_rate_hz = reader.readFloat64("imu_rate_hz");
}

}  // namespace vifusion::ros2_msgs
