#pragma once
// Caller-owned storage for what the parser accepted from one interrupt transfer. Sized for a number of
// packets at construction; parsing only overwrites it, so the per-transfer path allocates nothing.

#include <cstddef>
#include <span>
#include <vector>

#include "vifusion/motion/motion_packet.hpp"
#include "vifusion/motion/packet_format.hpp"
#include "vifusion/motion/packet_problem.hpp"

namespace vifusion::motion {

class PacketParser;

class ParsedTransfer {
 public:
  /// Room for `max_packets` packets (≥ 1; default: a full kMaxTransferBytes transfer).
  /// @throws vifusion::Error if max_packets is 0.
  explicit ParsedTransfer(std::size_t max_packets = kMaxPacketsPerTransfer);

  /// Headers of the packets accepted, in order (packets with errors or bad counts are absent).
  std::span<const PacketHeader> headers() const { return {headers_.data(), header_count_}; }
  /// Accepted accelerometer and gyroscope entries in transfer order.
  std::span<const ImuEntry> imuEntries() const { return {imu_.data(), imu_count_}; }
  /// Accepted frame and GPIO events in transfer order.
  std::span<const TimestampEntry> timestampEntries() const { return {timestamps_.data(), timestamp_count_}; }

  /// Problems met in this transfer (each also counted in the parser's stats) and the first of them
  /// (meaningful when problemCount() > 0).
  std::size_t problemCount() const { return problem_count_; }
  const PacketProblem& firstProblem() const { return first_problem_; }

  std::size_t maxPackets() const { return headers_.size(); }

 private:
  friend class PacketParser;

  void clear();
  void addHeader(const PacketHeader& header) { headers_[header_count_++] = header; }
  void addImu(const ImuEntry& entry) { imu_[imu_count_++] = entry; }
  void addTimestamp(const TimestampEntry& entry) { timestamps_[timestamp_count_++] = entry; }
  void noteProblem(const PacketProblem& problem);
  bool full() const { return header_count_ == headers_.size(); }

  std::vector<PacketHeader> headers_;
  std::vector<ImuEntry> imu_;
  std::vector<TimestampEntry> timestamps_;
  std::size_t header_count_ = 0;
  std::size_t imu_count_ = 0;
  std::size_t timestamp_count_ = 0;
  std::size_t problem_count_ = 0;
  PacketProblem first_problem_;
};

}  // namespace vifusion::motion
