#pragma once
// RecordingReader: a vifusion recording (topics.hpp) as a source, `rec:FILE.mcap` in `vifusion run` and
// vifusiond. It reads complete files and cut ones alike (a recording killed, out of power or out of disk
// holds everything up to its last complete chunk; note() says where it stops).
//
// Opening scans the file once for everything but the images: the recording info (calibration, source,
// mode), every IMU sample, the frames' stamps, the sync-line edges, the clock mappings and any ground
// truth; nextFrame() then streams the images from a second pass. A frame is delivered when its stamps,
// depth and colour (one stamp) are all there; a frame missing a part is counted and skipped, so a file
// cut between a frame's messages ends at the frame before.
//
// Frames and IMU samples come out bit for bit as they were recorded: the replay of a live run sees what
// the live run saw.

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/motion/packet_format.hpp"
#include "vifusion/recording/recording_file.hpp"

namespace vifusion::mcap {
class McapReader;
}  // namespace vifusion::mcap

namespace vifusion::recording {

/// One sync-line edge as recorded.
struct RecordedSyncEdge {
  std::int64_t t_ns = 0;
  bool rising = true;
  std::uint64_t sequence = 0;
};

/// One motion-module packet as recorded: the bytes as they came off the bus, and when.
struct RecordedMotionPacket {
  std::int64_t host_receive_ns = 0;  ///< arrival of its transfer, host CLOCK_MONOTONIC [ns]
  std::uint32_t transfer_index = 0;  ///< the transfer it came in (packets of one transfer share it)
  std::array<std::uint8_t, motion::kPacketBytes> bytes{};
};

class RecordingReader final : public datasets::DatasetReader {
 public:
  /// @throws vifusion::Error when the file is not MCAP, not a vifusion recording (no recording info), or a
  /// message cannot be decoded (naming the file, topic and message).
  explicit RecordingReader(const std::filesystem::path& path);
  ~RecordingReader() override;

  const RigCalibration& calibration() const override { return calibration_; }
  std::size_t frameCount() const override { return stamps_.size(); }
  bool nextFrame(RgbdFrame& frame) override;
  std::span<const ImuSample> imu() const override { return imu_; }
  std::span<const std::string> skippedImuRows() const override { return skipped_imu_rows_; }
  std::span<const datasets::StampedPose> groundTruth() const override { return ground_truth_; }
  std::string describe() const override;

  /// Where and why the data stops before the file's end (a cut recording); empty for a complete file.
  const std::string& note() const { return note_; }
  const std::string& source() const { return source_; }
  const std::string& mode() const { return mode_; }
  double frameRateHz() const { return frame_rate_hz_; }
  double imuRateHz() const { return imu_rate_hz_; }
  /// Every frame's timing, in frame order (index and t_ns included), images aside.
  struct FrameStampsRecord {
    std::int64_t t_ns = 0;
    std::int64_t index = 0;
    FrameTiming timing;
  };
  std::span<const FrameStampsRecord> frameStamps() const { return stamps_; }
  std::span<const RecordedSyncEdge> syncEdges() const { return edges_; }
  std::span<const ClockRecord> clockRecords() const { return clocks_; }
  std::span<const RecordedMotionPacket> motionPackets() const { return packets_; }
  /// Frames skipped because a part (stamps, depth or colour) was missing or out of order.
  std::size_t incompleteFrames() const { return incomplete_frames_; }

 private:
  void scan(mcap::McapReader& reader);

  std::filesystem::path path_;
  std::unique_ptr<mcap::McapReader> images_;
  RigCalibration calibration_;
  std::string source_, mode_, note_;
  double frame_rate_hz_ = 0.0, imu_rate_hz_ = 0.0;
  std::vector<ImuSample> imu_;
  std::vector<std::string> skipped_imu_rows_;  ///< damaged or out-of-order IMU messages, each named
  std::vector<datasets::StampedPose> ground_truth_;
  std::vector<FrameStampsRecord> stamps_;
  std::vector<RecordedSyncEdge> edges_;
  std::vector<ClockRecord> clocks_;
  std::vector<RecordedMotionPacket> packets_;
  std::size_t next_frame_ = 0;
  std::size_t incomplete_frames_ = 0;
  std::uint16_t depth_channel_ = 0, colour_channel_ = 0, stamps_channel_ = 0;
};

}  // namespace vifusion::recording
