#pragma once
// RecordingFile: writes one vifusion recording (topics.hpp) into an MCAP file through mcap::McapWriter,
// synchronously, on the caller's thread: `vifusion sim --out FILE.mcap` uses it directly, the live
// recorder (recorder.hpp) from its own thread.
//
// open() registers every schema and channel and writes what is fixed for the whole recording (recording
// info with the calibration YAML, both cameras' CameraInfo, /tf_static, the calibration attachment).
// Per message, the CDR bytes are serialised straight into the space the MCAP writer reserves in its chunk:
// nothing is copied twice and nothing is allocated. A failed write (disk full, storage gone) leaves the
// writer failed (failed(), error()); every later call returns false and does nothing, so the data already
// in the file stays readable up to its last complete chunk.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/mcap/mcap_writer.hpp"

namespace vifusion::recording {

/// What is fixed for a whole recording.
struct RecordingHeader {
  std::string source;  ///< the source spec recorded ("zr300", "sim:living_room_0")
  std::string mode;    ///< the SLAM mode it was recorded for ("rgbd", "rgbdi", "gyro"), or "" (none)
  RigCalibration calibration;
  double frame_rate_hz = 30.0;  ///< nominal RGB-D frame rate [Hz], > 0
  double imu_rate_hz = 0.0;     ///< nominal IMU rate [Hz]; 0: no IMU
  std::int64_t t_ns = 0;        ///< the recording's start, host CLOCK_MONOTONIC [ns] (stamps the fixed messages)
};

/// The device→host mapping of one device clock at some moment (clock::ClockEstimate with its state).
struct ClockRecord {
  std::int64_t t_ns = 0;   ///< when it was taken [host ns]
  std::uint8_t state = 0;  ///< 0 empty, 1 warming up, 2 valid (clock::ClockMapperState's order)
  std::int64_t ref_device_ns = 0;
  std::int64_t ref_host_ns = 0;
  double skew = 0.0;  ///< host rate / device rate − 1
};

struct RecordingCounts {
  std::uint64_t frames = 0;
  std::uint64_t imu_samples = 0;
  std::uint64_t sync_edges = 0;
  std::uint64_t clock_records = 0;
  std::uint64_t motion_packets = 0;
  std::uint64_t ground_truth_poses = 0;
};

class RecordingFile {
 public:
  /// Sizes the writer for frames of the calibration's image sizes. @throws vifusion::Error for bad options.
  explicit RecordingFile(const mcap::McapWriterOptions& options = {});
  ~RecordingFile();
  RecordingFile(const RecordingFile&) = delete;
  RecordingFile& operator=(const RecordingFile&) = delete;

  /// Creates `path` and writes the fixed part. False (error()) when the file cannot be created or written.
  /// @throws vifusion::Error when the header is invalid (no frame rate, images larger than the writer takes).
  bool open(const std::filesystem::path& path, const RecordingHeader& header);

  /// Depth (16UC1), colour (rgb8) and the frame's FrameStamps. The images must have the calibration's sizes.
  bool writeFrame(const RgbdFrame& frame, std::int64_t log_time_ns);
  bool writeImu(const ImuSample& sample, std::int64_t log_time_ns);
  bool writeSyncEdge(std::int64_t t_ns, bool rising, std::uint64_t sequence, std::int64_t log_time_ns);
  bool writeClock(const ClockRecord& clock, std::int64_t log_time_ns);
  /// One motion-module transfer as received at `host_receive_ns`: each of its packets becomes a message.
  bool writeMotionTransfer(std::int64_t host_receive_ns, std::uint32_t transfer_index,
                           std::span<const std::uint8_t> bytes, std::int64_t log_time_ns);
  /// The simulator's true camera pose T_world_camera at a frame.
  bool writeGroundTruthPose(std::int64_t t_ns, const SE3d& T_W_C, std::int64_t log_time_ns);

  /// Writes the current chunk when it is older than the writer's chunk_flush_ns (mcap_writer.hpp).
  bool flushIfDue(std::int64_t now_ns);
  /// Completes the file (summary). False when anything failed, now or before.
  bool close();

  bool isOpen() const { return writer_.isOpen(); }
  bool failed() const { return writer_.failed() || !problem_.empty(); }
  /// The first failure: the MCAP writer's (disk, storage) or a message that could not be encoded.
  const std::string& error() const { return problem_.empty() ? writer_.error() : problem_; }
  const RecordingCounts& counts() const { return counts_; }
  std::uint64_t bytesWritten() const { return writer_.bytesWritten(); }
  /// Messages in complete chunks: what a reader finds if the recording stops now.
  std::uint64_t messagesWritten() const { return writer_.messagesWritten(); }

 private:
  struct Channels;
  template <class Message>
  bool put(std::uint16_t channel, std::uint32_t& sequence, const Message& message, std::int64_t log_time_ns,
           std::int64_t publish_time_ns);
  void fail(const char* what, const std::exception& error);

  mcap::McapWriter writer_;
  std::unique_ptr<Channels> channels_;
  RecordingCounts counts_;
  int colour_width_ = 0, colour_height_ = 0, depth_width_ = 0, depth_height_ = 0;
  std::string problem_;
};

}  // namespace vifusion::recording
