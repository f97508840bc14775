// libFuzzer target: the motion-module packet parser on arbitrary interrupt transfers. Besides "no crash, no
// sanitizer report", it checks what the parser promises about everything it accepts.

#include <cstddef>
#include <cstdint>
#include <span>

#include "vifusion/motion/packet_parser.hpp"

namespace {

using namespace vifusion::motion;

void require(bool condition) {
  if (!condition) __builtin_trap();
}

void checkAccepted(std::span<const std::uint8_t> transfer, const ParsedTransfer& out) {
  require(out.headers().size() <= transfer.size() / kPacketBytes);
  require(out.imuEntries().size() <= out.headers().size() * kImuSlotCount);
  require(out.timestampEntries().size() <= out.headers().size() * kTimestampSlotCount);
  for (const PacketHeader& header : out.headers()) {
    require(header.error_bitmask == 0);
    require(header.imu_entry_count <= kImuSlotCount && header.timestamp_entry_count <= kTimestampSlotCount);
  }
  for (const ImuEntry& entry : out.imuEntries()) {
    require(isImuSource(static_cast<std::uint8_t>(entry.source)) && entry.valid);
    require(entry.sample_counter < kCounterModulus);
  }
  for (const TimestampEntry& entry : out.timestampEntries()) {
    require(isTimestampSource(static_cast<std::uint8_t>(entry.source)));
    require(entry.frame_counter < kCounterModulus);
  }
  require(!describe(out.firstProblem()).view().empty());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A fresh parser per input keeps a crash reproducible from its input alone; parsing the same bytes twice
  // also drives the counter checks (every counter then repeats or steps).
  PacketParser parser;
  ParsedTransfer out;
  const std::span<const std::uint8_t> transfer(data, size);
  for (int pass = 0; pass < 2; ++pass) {
    parser.parse(transfer, out);
    checkAccepted(transfer, out);
  }
  require(parser.stats().transfers == 2);
  return 0;
}
