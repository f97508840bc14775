#include "vifusion/ros2_msgs/geometry_tf.hpp"

#include <algorithm>

namespace vifusion::ros2_msgs {
namespace {

/// Fewest bytes one TransformStamped takes in CDR, padding aside: the stamp (int32 + uint32), two strings
/// at their shortest (a zero length alone), 7 float64. Bounds a count before any element is read.
constexpr std::size_t kMinTransformStampedBytes =
    sizeof(std::int32_t) + sizeof(std::uint32_t) + 2 * sizeof(std::uint32_t) + 7 * sizeof(double);

}  // namespace

void Vector3::serialize(CdrWriter& writer) const {
  writer.writeFloat64(x);
  writer.writeFloat64(y);
  writer.writeFloat64(z);
}

void Vector3::deserialize(CdrReader& reader) {
  x = reader.readFloat64("x");
  y = reader.readFloat64("y");
  z = reader.readFloat64("z");
}

void Quaternion::serialize(CdrWriter& writer) const {
  writer.writeFloat64(x);
  writer.writeFloat64(y);
  writer.writeFloat64(z);
  writer.writeFloat64(w);
}

void Quaternion::deserialize(CdrReader& reader) {
  x = reader.readFloat64("x");
  y = reader.readFloat64("y");
  z = reader.readFloat64("z");
  w = reader.readFloat64("w");
}

void Transform::serialize(CdrWriter& writer) const {
  translation.serialize(writer);
  rotation.serialize(writer);
}

void Transform::deserialize(CdrReader& reader) {
  readNested(reader, "translation", translation);
  readNested(reader, "rotation", rotation);
}

void TransformStamped::serialize(CdrWriter& writer) const {
  header.serialize(writer);
  writer.writeString(child_frame_id);
  transform.serialize(writer);
}

void TransformStamped::deserialize(CdrReader& reader) {
  readNested(reader, "header", header);
  child_frame_id = reader.readString("child_frame_id");
  readNested(reader, "transform", transform);
}

bool TfMessage::operator==(const TfMessage& other) const { return std::ranges::equal(active(), other.active()); }

bool TfMessage::add(const TransformStamped& transform) {
  if (transform_count >= kCapacity) return false;
  transforms[transform_count++] = transform;
  return true;
}

void TfMessage::serialize(CdrWriter& writer) const {
  if (transform_count > kCapacity) {
    writer.fail("tf2_msgs/msg/TFMessage: transform_count exceeds kCapacity");
    return;
  }
  writer.writeSequenceLength(transform_count);
  for (const TransformStamped& transform : active()) transform.serialize(writer);
}

void TfMessage::deserialize(CdrReader& reader) {
  transform_count = 0;
  const std::size_t count = reader.readSequenceLength("transforms", kMinTransformStampedBytes, kCapacity);
  for (std::size_t i = 0; i < count; ++i) {
    CdrReader::FieldScope scope(reader, "transforms", i);
    transforms[i].deserialize(reader);
  }
  transform_count = count;
}

}  // namespace vifusion::ros2_msgs
