#include "recording_test_support.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fnv1a.hpp"
#include "vifusion/core/crc32.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/mcap/mcap_reader.hpp"

namespace vifusion::test {
namespace {

/// Exit status of the child when execv fails (no shell is involved: 127 is what a shell would say).
constexpr int kExecFailedExitCode = 127;
constexpr int kSignalExitBase = 128;

std::string readText(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

DatasetContents loadDataset() {
  DatasetContents contents;
  const std::unique_ptr<datasets::DatasetReader> reader = datasets::openDataset("dataset:" + kDatasetDir.string());
  for (RgbdFrame frame; reader->nextFrame(frame);) {
    if (!contents.frames.empty()) {
      contents.max_frame_period_ns = std::max(contents.max_frame_period_ns, frame.t_ns - contents.frames.back().t_ns);
    }
    contents.depth_fnv1a.push_back(fnv1aOfDepth(frame.depth));
    contents.rgb_fnv1a.push_back(fnv1aOfRgb(frame.rgb));
    contents.frames.push_back(frame);
  }
  contents.imu.assign(reader->imu().begin(), reader->imu().end());
  contents.time_shift_cam_imu_ns = reader->calibration().time_shift_cam_imu_ns;
  return contents;
}

/// The first differing pixel of two images, or "" when they are equal.
template <class T, class Describe>
std::string firstDifference(const Image<T>& got, const Image<T>& want, Describe describe) {
  if (got.width() != want.width() || got.height() != want.height()) {
    return std::to_string(got.width()) + "x" + std::to_string(got.height()) + " instead of " +
           std::to_string(want.width()) + "x" + std::to_string(want.height());
  }
  for (int y = 0; y < want.height(); ++y) {
    for (int x = 0; x < want.width(); ++x) {
      if (!(got(x, y) == want(x, y))) {
        return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): " + describe(got(x, y)) + " instead of " +
               describe(want(x, y));
      }
    }
  }
  return "";
}

std::string describeRgb(const Rgb8& c) {
  return std::to_string(c.r) + "," + std::to_string(c.g) + "," + std::to_string(c.b);
}

}  // namespace

const DatasetContents& datasetContents() {
  static const DatasetContents contents = loadDataset();
  return contents;
}

PrefixCounts expectDatasetPrefix(recording::RecordingReader& reader) {
  const DatasetContents& dataset = datasetContents();
  PrefixCounts counts;
  EXPECT_LE(reader.frameCount(), dataset.frames.size());
  RgbdFrame frame, last;
  for (; reader.nextFrame(frame); ++counts.frames) {
    const std::size_t i = counts.frames;
    if (i >= dataset.frames.size()) {
      ADD_FAILURE() << "frame " << i << ": the dataset has only " << dataset.frames.size();
      break;
    }
    const RgbdFrame& want = dataset.frames[i];
    EXPECT_EQ(frame.t_ns, want.t_ns) << "frame " << i;
    EXPECT_EQ(frame.index, want.index) << "frame " << i;
    EXPECT_EQ(frame.depth_scale_m, want.depth_scale_m) << "frame " << i;
    EXPECT_EQ(fnv1aOfDepth(frame.depth), dataset.depth_fnv1a[i]) << "frame " << i << ": depth differs";
    EXPECT_EQ(fnv1aOfRgb(frame.rgb), dataset.rgb_fnv1a[i]) << "frame " << i << ": colour differs";
    std::swap(frame, last);
  }
  EXPECT_EQ(counts.frames, reader.frameCount());
  if (counts.frames > 0) {
    // The newest frame pixel by pixel: it sits right before the cut.
    const RgbdFrame& want = dataset.frames[std::min(counts.frames, dataset.frames.size()) - 1];
    EXPECT_EQ(firstDifference(last.depth, want.depth, [](std::uint16_t d) { return std::to_string(d); }), "")
        << "the last frame's depth (frame " << counts.frames - 1 << ")";
    EXPECT_EQ(firstDifference(last.rgb, want.rgb, describeRgb), "")
        << "the last frame's colour (frame " << counts.frames - 1 << ")";
  }

  const std::span<const ImuSample> imu = reader.imu();
  EXPECT_LE(imu.size(), dataset.imu.size());
  for (std::size_t i = 0; i < std::min(imu.size(), dataset.imu.size()); ++i) {
    const ImuSample& want = dataset.imu[i];
    if (imu[i].t_ns != want.t_ns || imu[i].gyro_rad_s != want.gyro_rad_s || imu[i].accel_mps2 != want.accel_mps2) {
      ADD_FAILURE() << "IMU sample " << i << " (t " << imu[i].t_ns << " ns) differs from the dataset's (t " << want.t_ns
                    << " ns)";
      break;
    }
  }
  counts.imu_samples = imu.size();
  if (counts.frames > 0) counts.last_frame_t_ns = last.t_ns;
  if (!imu.empty()) counts.last_imu_t_ns = imu.back().t_ns;
  return counts;
}

Child::Child(const std::vector<std::string>& argv, const std::filesystem::path& output_base)
    : stdout_path_(output_base.string() + ".stdout"), stderr_path_(output_base.string() + ".stderr") {
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  const std::string out = stdout_path_.string(), err = stderr_path_.string();
  pid_ = ::fork();
  if (pid_ == 0) {
    // The child: only async-signal-safe calls until execv.
    const int out_fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err_fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out_fd < 0 || err_fd < 0 || ::dup2(out_fd, STDOUT_FILENO) < 0 || ::dup2(err_fd, STDERR_FILENO) < 0) {
      ::_exit(kExecFailedExitCode);
    }
    ::execv(args[0], args.data());
    ::_exit(kExecFailedExitCode);
  }
  if (pid_ < 0) ADD_FAILURE() << "fork failed: " << std::strerror(errno);
}

Child::~Child() {
  if (pid_ > 0 && !reaped_) {
    ::kill(pid_, SIGKILL);
    wait();
  }
}

int Child::wait() {
  if (pid_ > 0 && !reaped_) {
    while (::waitpid(pid_, &status_, 0) < 0 && errno == EINTR) {
    }
    reaped_ = true;
  }
  return status_;
}

bool Child::ended(int* status) {
  if (pid_ > 0 && !reaped_ && ::waitpid(pid_, &status_, WNOHANG) == pid_) reaped_ = true;
  *status = status_;
  return reaped_;
}

std::string Child::stdoutText() const { return readText(stdout_path_); }
std::string Child::stderrText() const { return readText(stderr_path_); }

int runToEnd(const std::vector<std::string>& argv, const std::filesystem::path& output_base, std::string* out,
             std::string* err) {
  Child child(argv, output_base);
  const int status = child.wait();
  if (out != nullptr) *out = child.stdoutText();
  if (err != nullptr) *err = child.stderrText();
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return kSignalExitBase + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

std::string describeStatus(int status) {
  if (WIFEXITED(status)) return "exit code " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "killed by signal " + std::to_string(WTERMSIG(status));
  return "wait status " + std::to_string(status);
}

std::string describe(const MessageSummary& m) {
  return m.topic + " #" + std::to_string(m.sequence) + " log " + std::to_string(m.log_time_ns) + " publish " +
         std::to_string(m.publish_time_ns) + " size " + std::to_string(m.size) + " crc " + std::to_string(m.crc32);
}

McapContents readWithMcapReader(const std::filesystem::path& path) {
  mcap::McapReader reader(path.string());
  McapContents contents;
  for (mcap::MessageView m; reader.readNext(m);) {
    const mcap::ChannelInfo* channel = reader.channel(m.channel_id);
    contents.messages.push_back({channel != nullptr ? channel->topic : "?", m.sequence, m.log_time_ns,
                                 m.publish_time_ns, m.data.size(), crc32(m.data)});
  }
  contents.chunks = reader.chunks().size();
  contents.complete = reader.complete();
  contents.summary_used = reader.summaryUsed();
  contents.note = reader.note();
  return contents;
}

StreamReaderContents readWithMcapStreamReader(const std::filesystem::path& path) {
  StreamReaderContents contents;
  if (kNodeProgram.empty()) {
    ADD_FAILURE() << "Node.js (node) was not found when configuring: run .ci/install-deps, then cmake again";
    return contents;
  }
  std::string out, err;
  const int code = runToEnd({kNodeProgram, (kNodeDir / "read_mcap.mjs").string(), "--stream", path.string()},
                            path.string() + ".node", &out, &err);
  if (code != 0) {
    ADD_FAILURE() << "read_mcap.mjs --stream " << path << ": exit code " << code << "\n" << err;
    return contents;
  }
  std::istringstream lines(out);
  bool summary = false;
  for (std::string line; std::getline(lines, line);) {
    if (line.empty()) continue;
    try {
      const nlohmann::json json = nlohmann::json::parse(line);
      if (json.contains("summary")) {
        const nlohmann::json& s = json["summary"];
        contents.chunks = s.at("chunks").get<std::size_t>();
        contents.done = s.at("done").get<bool>();
        contents.trailing_bytes = s.at("trailing_bytes").get<std::uint64_t>();
        EXPECT_EQ(s.at("messages").get<std::size_t>(), contents.messages.size());
        summary = true;
        continue;
      }
      contents.messages.push_back({json.at("topic").get<std::string>(), json.at("sequence").get<std::uint32_t>(),
                                   std::stoll(json.at("log_time").get<std::string>()),
                                   std::stoll(json.at("publish_time").get<std::string>()),
                                   json.at("size").get<std::size_t>(), json.at("crc32").get<std::uint32_t>()});
    } catch (const std::exception& error) {
      ADD_FAILURE() << "read_mcap.mjs --stream " << path << ": cannot parse '" << line.substr(0, 200)
                    << "': " << error.what();
      return contents;
    }
  }
  EXPECT_TRUE(summary) << "read_mcap.mjs --stream " << path << " printed no summary line";
  return contents;
}

}  // namespace vifusion::test
