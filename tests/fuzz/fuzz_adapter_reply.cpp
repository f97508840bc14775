// libFuzzer target: the adapter-board reply decoder (and the request decoder of the scripted device) on
// arbitrary bytes. Bad input must end in vifusion::Error, never a crash; what is accepted must re-encode to
// the same bytes.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "vifusion/core/error.hpp"
#include "vifusion/motion/adapter_command.hpp"

namespace {

using namespace vifusion::motion;

void require(bool condition) {
  if (!condition) __builtin_trap();
}

bool sameBytes(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] != b[i]) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  // First byte: bit 7 picks the decoder (one per input: a thrown Error is the slow path, and one per input
  // keeps 1 M executions within the test's time); bits 0–6 the opcode the reply is checked against (any
  // value, undocumented ones included) and the minimum data length asked for. The rest: the bytes read.
  constexpr std::uint8_t kRequestBit = 0x80;
  const bool fuzz_request = (data[0] & kRequestBit) != 0;
  const auto expected = static_cast<AdapterOpcode>(data[0] & ~kRequestBit);
  const std::size_t min_data_bytes = data[0] % 8;
  const std::span<const std::uint8_t> bytes(data + 1, size - 1);
  std::array<std::uint8_t, kMaxCommandBytes> encoded{};
  try {
    if (fuzz_request) {
      const AdapterRequest request = decodeRequest(bytes);
      require(isAdapterOpcode(static_cast<std::uint32_t>(request.opcode)));
      const std::size_t length = encodeRequest(request, encoded);
      require(sameBytes(std::span(encoded).first(length), bytes));
    } else {
      const std::span<const std::uint8_t> reply_data = decodeReply(expected, bytes, min_data_bytes);
      require(reply_data.size() + kReplyOpcodeBytes == bytes.size() && reply_data.size() >= min_data_bytes);
      const std::size_t length = encodeReply(expected, reply_data, encoded);
      require(sameBytes(std::span(encoded).first(length), bytes));
    }
  } catch (const vifusion::Error&) {
  }
  return 0;
}
