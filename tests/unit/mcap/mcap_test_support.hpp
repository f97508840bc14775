#pragma once
// Shared by the vifusion::mcap tests: deterministic test messages, a writer fed with them that remembers
// where each chunk ended, reading a whole file back, and temporary directories.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/mcap/mcap_writer.hpp"

namespace vifusion::mcap::test {

/// One message as written or read back, compared field by field.
struct TestMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::int64_t log_time_ns = 0;
  std::int64_t publish_time_ns = 0;
  std::vector<std::uint8_t> data;

  bool operator==(const TestMessage&) const = default;
};

/// `count` messages round-robin over channels 1..channel_count, log times `period_ns` apart from
/// `start_ns`, publish times 3 ms earlier, sizes cycling through [min_bytes, max_bytes] and contents from
/// a seeded generator (so a corrupted byte shows).
std::vector<TestMessage> makeMessages(std::size_t count, std::uint16_t channel_count, std::int64_t start_ns,
                                      std::int64_t period_ns, std::size_t min_bytes, std::size_t max_bytes,
                                      std::uint32_t seed);

/// What writeRecording() did: for chunk k, the messages written up to and including it.
struct WrittenRecording {
  std::vector<TestMessage> messages;
  std::vector<std::uint64_t> messages_through_chunk;
};

/// Opens `path` with `options`, registers `channel_count` channels on two schemas ("ros2msg"), writes
/// `messages` with write() and flushIfDue(log time) after each, an attachment "calibration.yaml" after
/// half of them, and closes. Fails the calling test on any writer error.
WrittenRecording writeRecording(const std::string& path, const McapWriterOptions& options,
                                const std::vector<TestMessage>& messages, std::uint16_t channel_count);

/// Every message readNext() gives.
std::vector<TestMessage> readAll(McapReader& reader);

/// A reader over the first `bytes` of `file` (which the caller keeps alive).
McapReader readerOverPrefix(const std::vector<std::uint8_t>& file, std::size_t bytes);

std::vector<std::uint8_t> readFileBytes(const std::string& path);
void writeFileBytes(const std::string& path, std::span<const std::uint8_t> bytes);

/// The calibration attachment writeRecording() stores.
std::vector<std::uint8_t> calibrationYaml();

/// A fresh directory under the system temporary directory, removed with what it holds.
class TempDir {
 public:
  TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  ~TempDir();
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace vifusion::mcap::test
