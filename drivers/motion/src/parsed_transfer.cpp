#include "vifusion/motion/parsed_transfer.hpp"

#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::motion {
namespace {

std::size_t checkedMaxPackets(std::size_t max_packets) {
  if (max_packets == 0) throw Error("ParsedTransfer: max_packets = 0 is invalid (must hold at least one packet)");
  return max_packets;
}

}  // namespace

ParsedTransfer::ParsedTransfer(std::size_t max_packets)
    : headers_(checkedMaxPackets(max_packets)),
      imu_(max_packets * kImuSlotCount),
      timestamps_(max_packets * kTimestampSlotCount) {}

void ParsedTransfer::clear() {
  header_count_ = 0;
  imu_count_ = 0;
  timestamp_count_ = 0;
  problem_count_ = 0;
  first_problem_ = PacketProblem{};
}

void ParsedTransfer::noteProblem(const PacketProblem& problem) {
  if (problem_count_ == 0) first_problem_ = problem;
  ++problem_count_;
}

}  // namespace vifusion::motion
