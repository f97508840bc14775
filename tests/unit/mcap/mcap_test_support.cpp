#include "mcap_test_support.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <fstream>
#include <iterator>
#include <random>

#include "vifusion/core/time.hpp"

namespace vifusion::mcap::test {
namespace {

constexpr std::int64_t kPublishLeadNs = 3 * kNsPerMillisecond;  // publish (sensor) time before log time
constexpr std::int64_t kAttachmentLogTimeNs = 5 * kNsPerSecond;

std::vector<std::uint8_t> bytesOf(const std::string& text) { return {text.begin(), text.end()}; }

}  // namespace

std::vector<TestMessage> makeMessages(std::size_t count, std::uint16_t channel_count, std::int64_t start_ns,
                                      std::int64_t period_ns, std::size_t min_bytes, std::size_t max_bytes,
                                      std::uint32_t seed) {
  std::mt19937 random(seed);
  std::vector<TestMessage> messages(count);
  const std::size_t size_span = max_bytes - min_bytes + 1;
  for (std::size_t i = 0; i < count; ++i) {
    TestMessage& m = messages[i];
    m.channel_id = static_cast<std::uint16_t>(1 + i % channel_count);
    m.sequence = static_cast<std::uint32_t>(i / channel_count);
    m.log_time_ns = start_ns + static_cast<std::int64_t>(i) * period_ns;
    m.publish_time_ns = m.log_time_ns - kPublishLeadNs;
    m.data.resize(min_bytes + (i * 7919) % size_span);  // a prime stride visits every size
    for (std::uint8_t& byte : m.data) byte = static_cast<std::uint8_t>(random());
  }
  return messages;
}

WrittenRecording writeRecording(const std::string& path, const McapWriterOptions& options,
                                const std::vector<TestMessage>& messages, std::uint16_t channel_count) {
  WrittenRecording written;
  McapWriter writer(options);
  EXPECT_TRUE(writer.open(path)) << writer.error();
  const std::uint16_t imu_schema = writer.registerSchema("sensor_msgs/msg/Imu", "ros2msg", bytesOf("float64 x\n"));
  const std::uint16_t image_schema =
      writer.registerSchema("sensor_msgs/msg/Image", "ros2msg", bytesOf("uint32 height\nuint32 width\n"));
  for (std::uint16_t c = 1; c <= channel_count; ++c) {
    const std::uint16_t id =
        writer.registerChannel("/sensor_" + std::to_string(c), c % 2 == 1 ? imu_schema : image_schema, "cdr",
                               {{"offered_qos_profiles", "reliability: 1"}});
    EXPECT_EQ(id, c);
  }
  std::uint64_t chunks = 0;
  for (std::size_t i = 0; i < messages.size(); ++i) {
    const TestMessage& m = messages[i];
    if (i == messages.size() / 2) {
      EXPECT_TRUE(
          writer.writeAttachment("calibration.yaml", "application/yaml", calibrationYaml(), kAttachmentLogTimeNs));
    }
    EXPECT_TRUE(writer.write(m.channel_id, m.sequence, m.log_time_ns, m.publish_time_ns, m.data)) << writer.error();
    EXPECT_TRUE(writer.flushIfDue(m.log_time_ns));
    for (; chunks < writer.chunksWritten(); ++chunks)
      written.messages_through_chunk.push_back(writer.messagesWritten());
    written.messages.push_back(m);
  }
  EXPECT_TRUE(writer.close()) << writer.error();
  for (; chunks < writer.chunksWritten(); ++chunks) written.messages_through_chunk.push_back(writer.messagesWritten());
  return written;
}

std::vector<TestMessage> readAll(McapReader& reader) {
  std::vector<TestMessage> out;
  MessageView view;
  while (reader.readNext(view)) {
    out.push_back({view.channel_id, view.sequence, view.log_time_ns, view.publish_time_ns,
                   std::vector<std::uint8_t>(view.data.begin(), view.data.end())});
  }
  return out;
}

McapReader readerOverPrefix(const std::vector<std::uint8_t>& file, std::size_t bytes) {
  return McapReader(std::make_unique<MemoryByteSource>(std::span(file).first(bytes), "cut.mcap"));
}

std::vector<std::uint8_t> readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeFileBytes(const std::string& path, std::span<const std::uint8_t> bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

std::vector<std::uint8_t> calibrationYaml() {
  return bytesOf("cam0:\n  intrinsics: [615.0, 615.0, 320.0, 240.0]\n  T_cam_imu: identity\n");
}

TempDir::TempDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "vifusion-mcap-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) ADD_FAILURE() << "mkdtemp failed for " << pattern;
  path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace vifusion::mcap::test
