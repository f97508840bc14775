#pragma once
// One call to serialise or read a whole message of any type here, and the concept they rely on. The
// recorder pairs these with each type's kTypeName (MCAP Schema.name), kMcapSchemaEncoding and kDefinition
// (Schema.data), and kMcapMessageEncoding (Channel.message_encoding).

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "vifusion/ros2_msgs/cdr_reader.hpp"
#include "vifusion/ros2_msgs/cdr_writer.hpp"

namespace vifusion::ros2_msgs {

/// A ROS 2 message type of this library: its ROS name ("sensor_msgs/msg/Image"), its ros2msg definition,
/// and CDR serialisation both ways.
template <typename Message>
concept CdrMessage = std::default_initializable<Message> &&
    requires(const Message& message, Message& target, CdrWriter& writer, CdrReader& reader) {
  { Message::kTypeName } -> std::convertible_to<std::string_view>;
  { Message::kDefinition } -> std::convertible_to<std::string_view>;
  message.serialize(writer);
  target.deserialize(reader);
};

/// Serialises `message`, encapsulation header included, into `buffer`. The returned writer says whether
/// it fit (ok(), bytes()) and otherwise how many bytes it needs (size()) or what was invalid (failure()).
template <CdrMessage Message>
CdrWriter serializeMessage(const Message& message, std::span<std::uint8_t> buffer) {
  CdrWriter writer(buffer);
  message.serialize(writer);
  return writer;
}

/// Bytes `message` takes in CDR, encapsulation header included (a dry run into no buffer).
template <CdrMessage Message>
std::size_t serializedSize(const Message& message) {
  return serializeMessage(message, std::span<std::uint8_t>()).size();
}

/// Reads one message; its strings and byte spans point into `bytes`. Throws vifusion::Error naming the
/// type, field and byte offset for bytes that are not a valid message of this type.
template <CdrMessage Message>
Message deserializeMessage(std::span<const std::uint8_t> bytes) {
  CdrReader reader(bytes, Message::kTypeName);
  Message message;
  message.deserialize(reader);
  return message;
}

}  // namespace vifusion::ros2_msgs
