// libFuzzer target: the CDR decoders of every ROS 2 message type we record and replay (ros2_msgs), on
// arbitrary bytes; the first byte chooses the type (cdr_message_types.hpp). Bad bytes must end in an Error
// naming the type; a message that is accepted must be one our writer can write, and written, read back and
// written again it must give the same bytes.

#include <cstddef>
#include <cstdint>
#include <span>
#include <tuple>
#include <vector>

#include "cdr_message_types.hpp"
#include "fuzz_support.hpp"
#include "vifusion/ros2_msgs/message_io.hpp"

namespace {

using namespace vifusion;
using namespace vifusion::fuzz;

std::vector<std::uint8_t> written(const auto& message) {
  std::vector<std::uint8_t> bytes(ros2_msgs::serializedSize(message));
  const ros2_msgs::CdrWriter writer = ros2_msgs::serializeMessage(message, bytes);
  require(writer.ok() && writer.bytes().size() == bytes.size());
  return bytes;
}

template <typename Message>
void readMessage(std::span<const std::uint8_t> bytes) {
  Message message;
  if (!parsedOrNamedError({Message::kTypeName}, [&] { message = ros2_msgs::deserializeMessage<Message>(bytes); })) {
    return;
  }
  const std::vector<std::uint8_t> first = written(message);
  require(written(ros2_msgs::deserializeMessage<Message>(first)) == first);
}

template <std::size_t... I>
void readAs(std::size_t type, std::span<const std::uint8_t> bytes, std::index_sequence<I...>) {
  ((type == I ? readMessage<std::tuple_element_t<I, CdrMessageTypes>>(bytes) : void()), ...);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  constexpr std::size_t kTypes = std::tuple_size_v<CdrMessageTypes>;
  if (size == 0) return 0;
  readAs(data[0] % kTypes, std::span<const std::uint8_t>(data + 1, size - 1), std::make_index_sequence<kTypes>());
  return 0;
}
