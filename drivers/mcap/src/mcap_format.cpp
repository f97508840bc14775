#include "vifusion/mcap/mcap_format.hpp"

namespace vifusion::mcap {
namespace {

// Indexed by opcode; index 0 is no valid opcode.
constexpr std::string_view kOpcodeNames[] = {
    "opcode 0x00", "Header",         "Footer",         "Schema",     "Channel",          "Message",
    "Chunk",       "Message Index",  "Chunk Index",    "Attachment", "Attachment Index", "Statistics",
    "Metadata",    "Metadata Index", "Summary Offset", "Data End"};

}  // namespace

std::string_view opcodeName(std::uint8_t opcode) {
  if (opcode < std::size(kOpcodeNames)) return kOpcodeNames[opcode];
  return opcode >= 0x80 ? "private record" : "reserved record";
}

}  // namespace vifusion::mcap
