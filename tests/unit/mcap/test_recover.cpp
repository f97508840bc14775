// recoverMcap (the future `vifusion record --recover`): a cut file becomes a complete one with a summary.

#include <gtest/gtest.h>

#include "mcap_test_support.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/mcap/recover_mcap.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::mcap {
namespace {

using test::TestMessage;

constexpr std::int64_t kStartNs = 5'000 * kNsPerSecond;
constexpr std::uint16_t kChannels = 3;

TEST(McapRecover, ACutFileBecomesCompleteWithTheSameContents) {
  test::TempDir dir;
  McapWriterOptions options;
  options.sync = SyncPolicy::kNone;
  options.chunk_target_bytes = 2048;
  const test::WrittenRecording written =
      test::writeRecording(dir.file("full.mcap"), options,
                           test::makeMessages(500, kChannels, kStartNs, kNsPerMillisecond, 0, 100, 8), kChannels);
  std::vector<std::uint8_t> bytes = test::readFileBytes(dir.file("full.mcap"));
  const std::vector<ChunkInfo> chunks = test::readerOverPrefix(bytes, bytes.size()).chunks();
  ASSERT_GE(chunks.size(), 10u);
  const ChunkInfo& cut_chunk = chunks[chunks.size() - 3];
  bytes.resize(cut_chunk.offset + cut_chunk.record_bytes / 2);  // killed while writing this chunk
  test::writeFileBytes(dir.file("cut.mcap"), bytes);

  const RecoveryResult result = recoverMcap(dir.file("cut.mcap"), dir.file("recovered.mcap"));
  const std::uint64_t kept = written.messages_through_chunk[chunks.size() - 4];
  EXPECT_EQ(result.messages, kept);
  EXPECT_EQ(result.chunks_read, chunks.size() - 3);
  EXPECT_EQ(result.schemas, 2u);
  EXPECT_EQ(result.channels, 3u);
  EXPECT_EQ(result.attachments, 1u);
  EXPECT_FALSE(result.input_complete);
  EXPECT_NE(result.note.find("stopped at offset " + std::to_string(cut_chunk.offset) +
                             ": the file ends inside a Chunk record"),
            std::string::npos)
      << result.note;

  McapReader recovered(dir.file("recovered.mcap"));
  EXPECT_TRUE(recovered.summaryUsed()) << recovered.summaryProblem();
  EXPECT_TRUE(recovered.complete());
  EXPECT_EQ(result.bytes_written, test::readFileBytes(dir.file("recovered.mcap")).size());
  EXPECT_EQ(recovered.statistics().message_count, kept);
  EXPECT_EQ(recovered.statistics().chunk_count, result.chunks_written);
  const std::vector<TestMessage> messages = test::readAll(recovered);
  ASSERT_EQ(messages.size(), kept);
  EXPECT_TRUE(std::equal(messages.begin(), messages.end(), written.messages.begin()));
  McapReader original(dir.file("full.mcap"));
  EXPECT_EQ(recovered.channels().size(), original.channels().size());
  for (const ChannelInfo& channel : original.channels()) {
    ASSERT_NE(recovered.channel(channel.id), nullptr);
    EXPECT_EQ(recovered.channel(channel.id)->topic, channel.topic);  // ids kept
    EXPECT_EQ(recovered.channel(channel.id)->metadata, channel.metadata);
  }
  EXPECT_EQ(recovered.schemas()[1].name, original.schemas()[1].name);
  EXPECT_EQ(recovered.attachments()[0].data, test::calibrationYaml());
  EXPECT_EQ(recovered.profile(), "ros2");
}

TEST(McapRecover, ACompleteFileIsCopiedWhole) {
  test::TempDir dir;
  McapWriterOptions options;
  options.sync = SyncPolicy::kNone;
  const test::WrittenRecording written =
      test::writeRecording(dir.file("in.mcap"), options,
                           test::makeMessages(100, kChannels, kStartNs, kNsPerMillisecond, 0, 50, 9), kChannels);
  const RecoveryResult result = recoverMcap(dir.file("in.mcap"), dir.file("out.mcap"));
  EXPECT_TRUE(result.input_complete);
  EXPECT_TRUE(result.note.empty()) << result.note;
  EXPECT_EQ(result.messages, 100u);
  McapReader out(dir.file("out.mcap"));
  EXPECT_EQ(test::readAll(out), written.messages);
  vifusion::test::expectError([&] { recoverMcap(dir.file("in.mcap"), dir.file("in.mcap")); }, "is the input itself");
}

}  // namespace
}  // namespace vifusion::mcap
