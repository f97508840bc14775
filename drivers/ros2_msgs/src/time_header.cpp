#include "vifusion/ros2_msgs/time_header.hpp"

#include <limits>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::ros2_msgs {

Time Time::fromNs(std::int64_t t_ns) {
  std::int64_t sec = t_ns / kNsPerSecond;
  std::int64_t nanosec = t_ns % kNsPerSecond;
  if (nanosec < 0) {  // C++ division truncates toward zero; ROS wants the floor
    sec -= 1;
    nanosec += kNsPerSecond;
  }
  if (sec < std::numeric_limits<std::int32_t>::min() || sec > std::numeric_limits<std::int32_t>::max()) {
    throw Error("builtin_interfaces/msg/Time: " + std::to_string(t_ns) +
                " ns is outside its range (int32 seconds, about ±68 years)");
  }
  return Time{static_cast<std::int32_t>(sec), static_cast<std::uint32_t>(nanosec)};
}

std::int64_t Time::toNs() const { return static_cast<std::int64_t>(sec) * kNsPerSecond + nanosec; }

void Time::serialize(CdrWriter& writer) const {
  writer.writeInt32(sec);
  writer.writeUint32(nanosec);
}

void Time::deserialize(CdrReader& reader) {
  sec = reader.readInt32("sec");
  const std::uint32_t value = reader.readUint32("nanosec");
  if (value >= static_cast<std::uint64_t>(kNsPerSecond)) {
    reader.failAt(reader.offset() - sizeof(value), "nanosec",
                  std::to_string(value) + " ns is not below one second (1000000000)");
  }
  nanosec = value;
}

void Header::serialize(CdrWriter& writer) const {
  stamp.serialize(writer);
  writer.writeString(frame_id);
}

void Header::deserialize(CdrReader& reader) {
  readNested(reader, "stamp", stamp);
  frame_id = reader.readString("frame_id");
}

Header makeHeader(std::int64_t t_ns, std::string_view frame_id) { return Header{Time::fromNs(t_ns), frame_id}; }

}  // namespace vifusion::ros2_msgs
