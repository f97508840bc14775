#include "vifusion/ros2_msgs/sensor_msgs.hpp"

#include <algorithm>
#include <string>

namespace vifusion::ros2_msgs {

void ImageView::serialize(CdrWriter& writer) const {
  if (data.size() != static_cast<std::size_t>(step) * height) {
    writer.fail("sensor_msgs/msg/Image: data is not step × height bytes");
  }
  header.serialize(writer);
  writer.writeUint32(height);
  writer.writeUint32(width);
  writer.writeString(encoding);
  writer.writeUint8(is_bigendian);
  writer.writeUint32(step);
  writer.writeUint8Sequence(data);
}

void ImageView::deserialize(CdrReader& reader) {
  readNested(reader, "header", header);
  height = reader.readUint32("height");
  width = reader.readUint32("width");
  encoding = reader.readString("encoding");
  is_bigendian = reader.readUint8("is_bigendian");
  step = reader.readUint32("step");
  data = reader.readUint8Sequence("data");
  const std::size_t data_offset = reader.offset() - data.size() - sizeof(std::uint32_t);  // its count's offset
  const std::size_t expected_bytes = static_cast<std::size_t>(step) * height;
  if (data.size() != expected_bytes) {
    reader.failAt(data_offset, "data",
                  "holds " + std::to_string(data.size()) + " bytes, not step × height = " + std::to_string(step) +
                      " × " + std::to_string(height) + " = " + std::to_string(expected_bytes));
  }
}

void Imu::serialize(CdrWriter& writer) const {
  header.serialize(writer);
  orientation.serialize(writer);
  writer.writeFloat64Array(orientation_covariance);
  angular_velocity.serialize(writer);
  writer.writeFloat64Array(angular_velocity_covariance);
  linear_acceleration.serialize(writer);
  writer.writeFloat64Array(linear_acceleration_covariance);
}

void Imu::deserialize(CdrReader& reader) {
  readNested(reader, "header", header);
  readNested(reader, "orientation", orientation);
  reader.readFloat64Array(orientation_covariance, "orientation_covariance");
  readNested(reader, "angular_velocity", angular_velocity);
  reader.readFloat64Array(angular_velocity_covariance, "angular_velocity_covariance");
  readNested(reader, "linear_acceleration", linear_acceleration);
  reader.readFloat64Array(linear_acceleration_covariance, "linear_acceleration_covariance");
}

void RegionOfInterest::serialize(CdrWriter& writer) const {
  writer.writeUint32(x_offset);
  writer.writeUint32(y_offset);
  writer.writeUint32(height);
  writer.writeUint32(width);
  writer.writeBool(do_rectify);
}

void RegionOfInterest::deserialize(CdrReader& reader) {
  x_offset = reader.readUint32("x_offset");
  y_offset = reader.readUint32("y_offset");
  height = reader.readUint32("height");
  width = reader.readUint32("width");
  do_rectify = reader.readBool("do_rectify");
}

bool CameraInfo::setDistortion(std::span<const double> coefficients) {
  if (coefficients.size() > kMaxDistortionCoefficients) return false;
  std::ranges::copy(coefficients, d.begin());
  d_count = coefficients.size();
  return true;
}

void CameraInfo::serialize(CdrWriter& writer) const {
  if (d_count > kMaxDistortionCoefficients) {
    writer.fail("sensor_msgs/msg/CameraInfo: d_count exceeds kMaxDistortionCoefficients");
    return;
  }
  header.serialize(writer);
  writer.writeUint32(height);
  writer.writeUint32(width);
  writer.writeString(distortion_model);
  writer.writeFloat64Sequence(distortion());
  writer.writeFloat64Array(k);
  writer.writeFloat64Array(r);
  writer.writeFloat64Array(p);
  writer.writeUint32(binning_x);
  writer.writeUint32(binning_y);
  roi.serialize(writer);
}

void CameraInfo::deserialize(CdrReader& reader) {
  readNested(reader, "header", header);
  height = reader.readUint32("height");
  width = reader.readUint32("width");
  distortion_model = reader.readString("distortion_model");
  d_count = reader.readFloat64Sequence(d, "d");
  reader.readFloat64Array(k, "k");
  reader.readFloat64Array(r, "r");
  reader.readFloat64Array(p, "p");
  binning_x = reader.readUint32("binning_x");
  binning_y = reader.readUint32("binning_y");
  readNested(reader, "roi", roi);
}

bool CameraInfo::operator==(const CameraInfo& other) const {
  return header == other.header && height == other.height && width == other.width &&
         distortion_model == other.distortion_model && std::ranges::equal(distortion(), other.distortion()) &&
         k == other.k && r == other.r && p == other.p && binning_x == other.binning_x && binning_y == other.binning_y &&
         roi == other.roi;
}

}  // namespace vifusion::ros2_msgs
