#pragma once
// Shared by the crash and full-disk tests: the dataset a recording is made from (every frame decoded once),
// the checks that a recording is a bit-exact prefix of it, child processes (`vifusion`, `node`) and the
// message list of an MCAP file as vifusion's reader and @mcap/core's stream reader see it.

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vifusion/core/sensor_data.hpp"
#include "vifusion/recording/recording_reader.hpp"

namespace vifusion::test {

/// Paths compiled in by tests/recording/CMakeLists.txt.
inline const char* const kVifusionCli = VIFUSION_CLI;
inline const std::filesystem::path kDatasetDir = VIFUSION_RECORDING_DATASET;
inline const std::filesystem::path kWorkDir = VIFUSION_RECORDING_WORK_DIR;
inline const std::string kNodeProgram = VIFUSION_NODE_PROGRAM;
inline const std::filesystem::path kNodeDir = VIFUSION_NODE_DIR;

/// The dataset directory the recordings are made from, decoded once per test binary.
struct DatasetContents {
  std::vector<RgbdFrame> frames;
  std::vector<std::uint32_t> depth_fnv1a, rgb_fnv1a;
  std::vector<ImuSample> imu;
  std::int64_t max_frame_period_ns = 0;    ///< the largest gap between consecutive frames
  std::int64_t time_shift_cam_imu_ns = 0;  ///< t_imu = t_cam + shift (calibration)
};
const DatasetContents& datasetContents();

/// How much of the dataset a recording holds; gtest failures for anything that is not a bit-exact prefix
/// (frames: stamp, index and both images; IMU samples: stamp and all six values).
struct PrefixCounts {
  std::size_t frames = 0;
  std::size_t imu_samples = 0;
  std::int64_t last_frame_t_ns = 0;  ///< camera time of the last frame (0: none)
  std::int64_t last_imu_t_ns = 0;    ///< IMU time of the last sample (0: none)
};
PrefixCounts expectDatasetPrefix(recording::RecordingReader& reader);

/// A child process with stdout and stderr into files.
class Child {
 public:
  /// fork + execv of argv[0] (a path); stdout and stderr to `output_base`.stdout / .stderr.
  Child(const std::vector<std::string>& argv, const std::filesystem::path& output_base);
  /// Kills it (SIGKILL) if still running.
  ~Child();
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  /// Waits for the end; the wait status (waitpid).
  int wait();
  /// True when it has already ended (status in *status).
  bool ended(int* status);
  pid_t pid() const { return pid_; }
  std::string stdoutText() const;
  std::string stderrText() const;

 private:
  pid_t pid_ = -1;
  bool reaped_ = false;
  int status_ = 0;
  std::filesystem::path stdout_path_, stderr_path_;
};

/// Runs a program to its end. Returns its exit code, or 128 + signal, with stdout and stderr in `out`/`err`.
int runToEnd(const std::vector<std::string>& argv, const std::filesystem::path& output_base, std::string* out,
             std::string* err);

/// "exit code N" or "killed by signal S" for a wait status.
std::string describeStatus(int status);

/// One message as both readers report it (read_mcap.mjs's fields).
struct MessageSummary {
  std::string topic;
  std::uint32_t sequence = 0;
  std::int64_t log_time_ns = 0;
  std::int64_t publish_time_ns = 0;
  std::size_t size = 0;
  std::uint32_t crc32 = 0;
  bool operator==(const MessageSummary&) const = default;
};
std::string describe(const MessageSummary& message);

/// Every message vifusion's McapReader accepts, in file order, with its note() and complete().
struct McapContents {
  std::vector<MessageSummary> messages;
  std::size_t chunks = 0;
  bool complete = false;
  bool summary_used = false;
  std::string note;
};
McapContents readWithMcapReader(const std::filesystem::path& path);

/// What tests/node/read_mcap.mjs --stream (@mcap/core's McapStreamReader) prints for a file: every message
/// and its summary line's counts. gtest failures when node fails or its output does not parse.
struct StreamReaderContents {
  std::vector<MessageSummary> messages;
  std::size_t chunks = 0;
  bool done = false;
  std::uint64_t trailing_bytes = 0;
};
StreamReaderContents readWithMcapStreamReader(const std::filesystem::path& path);

}  // namespace vifusion::test
