// Writer and reader agree on everything a recording holds, the chunks split where the options say, and
// the bytes follow the specification's layouts (built here from the documented field tables).

#include <gtest/gtest.h>

#include <cstring>

#include "mcap_test_support.hpp"
#include "vifusion/core/crc32.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/mcap/mcap_format.hpp"
#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/mcap/mcap_writer.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::mcap {
namespace {

using test::TestMessage;

constexpr std::int64_t kStartNs = 1'000 * kNsPerSecond;
constexpr std::uint16_t kChannels = 3;

McapWriterOptions fastOptions() {
  McapWriterOptions options;
  options.sync = SyncPolicy::kNone;  // fdatasync is tested on its own; here it only costs time
  return options;
}

/// The size rule, restated: a chunk is written once its records reach chunk_target_bytes; each message
/// record is 31 bytes of fields plus its data.
std::size_t expectedChunksBySize(const std::vector<TestMessage>& messages, std::size_t target_bytes) {
  std::size_t chunks = 0;
  std::size_t records = 0;
  for (const TestMessage& m : messages) {
    records += 31 + m.data.size();
    if (records >= target_bytes) {
      ++chunks;
      records = 0;
    }
  }
  return chunks + (records > 0 ? 1 : 0);
}

TEST(McapRoundTrip, ChunksSplitBySizeHoldEveryMessage) {
  test::TempDir dir;
  McapWriterOptions options = fastOptions();
  options.chunk_target_bytes = 4096;
  options.chunk_flush_ns = 60 * kNsPerSecond;  // never by age here
  const std::vector<TestMessage> messages = test::makeMessages(3000, kChannels, kStartNs, kNsPerMillisecond, 0, 300, 1);
  const test::WrittenRecording written = test::writeRecording(dir.file("size.mcap"), options, messages, kChannels);

  McapReader reader(dir.file("size.mcap"));
  EXPECT_TRUE(reader.summaryUsed()) << reader.summaryProblem();
  EXPECT_TRUE(reader.complete());
  EXPECT_EQ(reader.profile(), "ros2");
  EXPECT_EQ(reader.library(), "vifusion");
  const std::size_t expected_chunks = expectedChunksBySize(messages, options.chunk_target_bytes);
  // 3000 records of 31 + 150 bytes on average, ~4.19 kB per chunk (4096 plus part of the last record).
  EXPECT_EQ(expected_chunks, 130u);
  EXPECT_EQ(reader.chunks().size(), expected_chunks);
  EXPECT_EQ(written.messages_through_chunk.size(), expected_chunks);
  for (const ChunkInfo& chunk : reader.chunks()) {
    EXPECT_GE(chunk.records_bytes, chunk.offset == reader.chunks().back().offset ? 1u : options.chunk_target_bytes);
    EXPECT_LT(chunk.records_bytes, options.chunk_target_bytes + 31 + 300);
  }
  EXPECT_EQ(test::readAll(reader), messages);

  const McapStatistics& statistics = reader.statistics();
  EXPECT_EQ(statistics.message_count, 3000u);
  EXPECT_EQ(statistics.chunk_count, expected_chunks);
  EXPECT_EQ(statistics.schema_count, 2u);
  EXPECT_EQ(statistics.channel_count, 3u);
  EXPECT_EQ(statistics.attachment_count, 1u);
  EXPECT_EQ(statistics.message_start_time_ns, kStartNs);
  EXPECT_EQ(statistics.message_end_time_ns, kStartNs + 2999 * kNsPerMillisecond);
  const std::map<std::uint16_t, std::uint64_t> per_channel = {{1, 1000}, {2, 1000}, {3, 1000}};
  EXPECT_EQ(statistics.channel_message_counts, per_channel);
}

TEST(McapRoundTrip, ChunksSplitByAgeAtTheFlushBudget) {
  test::TempDir dir;
  McapWriterOptions options = fastOptions();
  options.chunk_flush_ns = 100 * kNsPerMillisecond;
  // 10 ms apart, flushIfDue(log time) after each: a chunk closes with the message 100 ms after its first,
  // so it holds 11 messages spanning exactly 100 ms.
  const std::vector<TestMessage> messages =
      test::makeMessages(110, kChannels, kStartNs, 10 * kNsPerMillisecond, 10, 20, 2);
  test::writeRecording(dir.file("age.mcap"), options, messages, kChannels);

  McapReader reader(dir.file("age.mcap"));
  ASSERT_EQ(reader.chunks().size(), 10u);
  for (std::size_t k = 0; k < reader.chunks().size(); ++k) {
    const ChunkInfo& chunk = reader.chunks()[k];
    EXPECT_EQ(chunk.message_start_time_ns, kStartNs + static_cast<std::int64_t>(k) * 110 * kNsPerMillisecond);
    EXPECT_EQ(chunk.message_end_time_ns - chunk.message_start_time_ns, 100 * kNsPerMillisecond) << "chunk " << k;
  }
  EXPECT_EQ(test::readAll(reader), messages);
}

TEST(McapRoundTrip, DefinitionsAndAttachmentsComeBack) {
  test::TempDir dir;
  const std::vector<TestMessage> messages = test::makeMessages(50, kChannels, kStartNs, kNsPerMillisecond, 1, 9, 3);
  test::writeRecording(dir.file("defs.mcap"), fastOptions(), messages, kChannels);

  McapReader reader(dir.file("defs.mcap"));
  ASSERT_EQ(reader.schemas().size(), 2u);
  EXPECT_EQ(reader.schemas()[0].id, 1u);
  EXPECT_EQ(reader.schemas()[0].name, "sensor_msgs/msg/Imu");
  EXPECT_EQ(reader.schemas()[0].encoding, "ros2msg");
  EXPECT_EQ(std::string(reader.schemas()[0].data.begin(), reader.schemas()[0].data.end()), "float64 x\n");
  ASSERT_EQ(reader.channels().size(), 3u);
  const ChannelInfo* second = reader.channel(2);
  ASSERT_NE(second, nullptr);
  EXPECT_EQ(second->topic, "/sensor_2");
  EXPECT_EQ(second->schema_id, 2u);
  EXPECT_EQ(second->message_encoding, "cdr");
  EXPECT_EQ(second->metadata.at("offered_qos_profiles"), "reliability: 1");
  EXPECT_EQ(reader.channel(4), nullptr);
  ASSERT_EQ(reader.attachments().size(), 1u);
  EXPECT_EQ(reader.attachments()[0].name, "calibration.yaml");
  EXPECT_EQ(reader.attachments()[0].media_type, "application/yaml");
  EXPECT_EQ(reader.attachments()[0].log_time_ns, 5 * kNsPerSecond);
  EXPECT_EQ(reader.attachments()[0].data, test::calibrationYaml());

  // The same file read by scanning (its last byte gone, so no summary) gives the same.
  const std::vector<std::uint8_t> bytes = test::readFileBytes(dir.file("defs.mcap"));
  McapReader scanned = test::readerOverPrefix(bytes, bytes.size() - 1);
  EXPECT_FALSE(scanned.summaryUsed());
  EXPECT_EQ(scanned.summaryProblem(), "the file does not end with the MCAP magic (it was cut while recording)");
  EXPECT_TRUE(scanned.complete()) << scanned.note();  // the scan reached DataEnd
  EXPECT_EQ(scanned.channels().size(), 3u);
  EXPECT_EQ(scanned.attachments().size(), 1u);
  EXPECT_EQ(scanned.statistics().message_count, 50u);
  EXPECT_EQ(scanned.statistics().channel_message_counts, reader.statistics().channel_message_counts);
  EXPECT_EQ(test::readAll(scanned), messages);
}

TEST(McapRoundTrip, ReserveAndCommitWriteInPlace) {
  test::TempDir dir;
  McapWriter writer(fastOptions());
  ASSERT_TRUE(writer.open(dir.file("zero_copy.mcap")));
  const std::uint16_t channel = writer.registerChannel("/imu", McapWriter::kNoId, "cdr");
  for (std::uint32_t i = 0; i < 5; ++i) {
    std::span<std::uint8_t> space = writer.reserveMessage(64);
    ASSERT_EQ(space.size(), 64u);
    for (std::size_t b = 0; b <= i; ++b) space[b] = static_cast<std::uint8_t>(0xA0 + b);
    EXPECT_TRUE(writer.commitMessage(channel, i, kStartNs + i, kStartNs + i, i + 1));  // uses i + 1 of 64
  }
  EXPECT_TRUE(writer.close());
  EXPECT_EQ(writer.messagesWritten(), 5u);
  EXPECT_EQ(writer.chunksWritten(), 1u);

  McapReader reader(dir.file("zero_copy.mcap"));
  const std::vector<TestMessage> read = test::readAll(reader);
  ASSERT_EQ(read.size(), 5u);
  EXPECT_EQ(read[4].data, (std::vector<std::uint8_t>{0xA0, 0xA1, 0xA2, 0xA3, 0xA4}));
  EXPECT_EQ(read[4].sequence, 4u);
  EXPECT_EQ(reader.channel(channel)->schema_id, 0u);
}

TEST(McapRoundTrip, AFullMessageIndexClosesTheChunkEarly) {
  test::TempDir dir;
  McapWriterOptions options = fastOptions();
  options.max_messages_per_chunk = 4;
  const std::vector<TestMessage> messages = test::makeMessages(10, kChannels, kStartNs, kNsPerMillisecond, 1, 5, 10);
  test::writeRecording(dir.file("index_full.mcap"), options, messages, kChannels);
  McapReader reader(dir.file("index_full.mcap"));
  ASSERT_EQ(reader.chunks().size(), 3u);  // 4 + 4 + 2 messages
  EXPECT_EQ(reader.chunks()[1].message_start_time_ns, kStartNs + 4 * kNsPerMillisecond);
  EXPECT_EQ(reader.chunks()[1].message_end_time_ns, kStartNs + 7 * kNsPerMillisecond);
  EXPECT_EQ(test::readAll(reader), messages);
}

TEST(McapRoundTrip, AnEmptyRecordingIsValid) {
  test::TempDir dir;
  McapWriter writer(fastOptions());
  ASSERT_TRUE(writer.open(dir.file("empty.mcap")));
  EXPECT_TRUE(writer.close());
  McapReader reader(dir.file("empty.mcap"));
  EXPECT_TRUE(reader.summaryUsed()) << reader.summaryProblem();
  EXPECT_EQ(reader.statistics().message_count, 0u);
  MessageView view;
  EXPECT_FALSE(reader.readNext(view));
}

TEST(McapRoundTrip, RefusedMessagesAreCountedAndTheWriterGoesOn) {
  test::TempDir dir;
  McapWriterOptions options = fastOptions();
  options.max_message_bytes = 100;
  McapWriter writer(options);
  ASSERT_TRUE(writer.open(dir.file("refused.mcap")));
  const std::uint16_t channel = writer.registerChannel("/imu", McapWriter::kNoId, "cdr");
  const std::vector<std::uint8_t> data(10, 1);
  EXPECT_FALSE(writer.commitMessage(channel, 0, kStartNs, kStartNs, 0));  // nothing reserved
  EXPECT_EQ(writer.firstRejection(),
            "commitMessage(channel 1, sequence 0): no space was reserved (call reserveMessage first)");
  EXPECT_TRUE(writer.reserveMessage(101).empty());
  EXPECT_FALSE(writer.write(7, 0, kStartNs, kStartNs, data));
  EXPECT_FALSE(writer.write(channel, 3, -1, kStartNs, data));
  writer.reserveMessage(10);
  EXPECT_FALSE(writer.commitMessage(channel, 4, kStartNs, kStartNs, 11));
  EXPECT_EQ(writer.messagesRejected(), 5u);
  EXPECT_FALSE(writer.failed());
  EXPECT_TRUE(writer.write(channel, 5, kStartNs, kStartNs, data));
  EXPECT_TRUE(writer.close());
  McapReader reader(dir.file("refused.mcap"));
  EXPECT_EQ(reader.statistics().message_count, 1u);
}

TEST(McapRoundTrip, MisuseOfTheSetupCallsIsAnError) {
  test::TempDir dir;
  McapWriter writer(fastOptions());
  vifusion::test::expectError([&] { writer.registerChannel("/imu", 0, "cdr"); },
                              "McapWriter::registerChannel: no file is open");
  ASSERT_TRUE(writer.open(dir.file("misuse.mcap")));
  vifusion::test::expectError([&] { writer.open(dir.file("other.mcap")); }, "misuse.mcap is still open");
  vifusion::test::expectError([&] { writer.registerChannel("/imu", 3, "cdr"); },
                              "registerChannel(\"/imu\"): schema id 3 is not registered (0 schemas)");
  vifusion::test::expectError([&] { writer.registerChannel("", 0, "cdr"); }, "the topic is empty");
  const std::vector<std::uint8_t> text = {'x'};
  vifusion::test::expectError([&] { writer.registerSchema("pkg/msg/X", "", text); },
                              "registerSchema(\"pkg/msg/X\"): 1 bytes of data without an encoding");
  McapWriterOptions bad;
  bad.chunk_target_bytes = 0;
  vifusion::test::expectError([&] { McapWriter refused(bad); }, "McapWriterOptions.chunk_target_bytes");
}

/// Little-endian field appenders for the expected bytes.
void appendU16(std::vector<std::uint8_t>& out, std::uint16_t v) {
  for (int i = 0; i < 2; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void appendU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void appendU64(std::vector<std::uint8_t>& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void appendString(std::vector<std::uint8_t>& out, std::string_view s) {
  appendU32(out, static_cast<std::uint32_t>(s.size()));
  out.insert(out.end(), s.begin(), s.end());
}

TEST(McapRoundTrip, BytesFollowTheSpecificationsLayouts) {
  test::TempDir dir;
  McapWriter writer(fastOptions());
  ASSERT_TRUE(writer.open(dir.file("layout.mcap")));
  const std::vector<std::uint8_t> schema_text = {'i', 'n', 't', '8', ' ', 'x'};
  const std::uint16_t schema = writer.registerSchema("pkg/msg/X", "ros2msg", schema_text);
  const std::uint16_t channel = writer.registerChannel("/x", schema, "cdr");
  const std::vector<std::uint8_t> payload = {0xDE, 0xAD};
  ASSERT_TRUE(writer.write(channel, 9, 1000, 900, payload));
  ASSERT_TRUE(writer.close());

  // magic, Header(op 0x01: profile, library), Schema(op 0x03: id, name, encoding, u32-prefixed data),
  // Channel(op 0x04: id, schema_id, topic, message_encoding, metadata map), then the Chunk (op 0x06).
  std::vector<std::uint8_t> expected(kMagic.begin(), kMagic.end());
  expected.push_back(0x01);
  appendU64(expected, 4 + 4 + 4 + 8);
  appendString(expected, "ros2");
  appendString(expected, "vifusion");
  expected.push_back(0x03);
  appendU64(expected, 2 + 4 + 9 + 4 + 7 + 4 + 6);
  appendU16(expected, 1);
  appendString(expected, "pkg/msg/X");
  appendString(expected, "ros2msg");
  appendU32(expected, 6);
  expected.insert(expected.end(), schema_text.begin(), schema_text.end());
  expected.push_back(0x04);
  appendU64(expected, 2 + 2 + 4 + 2 + 4 + 3 + 4);
  appendU16(expected, 1);
  appendU16(expected, 1);
  appendString(expected, "/x");
  appendString(expected, "cdr");
  appendU32(expected, 0);  // empty metadata map
  // Chunk: start/end time, uncompressed size, CRC, compression "", u64-prefixed records = one Message.
  std::vector<std::uint8_t> message = {0x05};
  appendU64(message, 2 + 4 + 8 + 8 + 2);
  appendU16(message, 1);
  appendU32(message, 9);
  appendU64(message, 1000);
  appendU64(message, 900);
  message.insert(message.end(), payload.begin(), payload.end());
  expected.push_back(0x06);
  appendU64(expected, 8 + 8 + 8 + 4 + 4 + 8 + message.size());
  appendU64(expected, 1000);
  appendU64(expected, 1000);
  appendU64(expected, message.size());
  appendU32(expected, crc32(message));
  appendString(expected, "");
  appendU64(expected, message.size());
  expected.insert(expected.end(), message.begin(), message.end());
  // Message Index (op 0x07): channel, array of (log_time, offset in the records).
  expected.push_back(0x07);
  appendU64(expected, 2 + 4 + 16);
  appendU16(expected, 1);
  appendU32(expected, 16);
  appendU64(expected, 1000);
  appendU64(expected, 0);
  // DataEnd (op 0x0F) with the data section CRC left at 0 ("not computed").
  expected.push_back(0x0F);
  appendU64(expected, 4);
  appendU32(expected, 0);

  const std::vector<std::uint8_t> file = test::readFileBytes(dir.file("layout.mcap"));
  ASSERT_GT(file.size(), expected.size());
  EXPECT_TRUE(std::equal(expected.begin(), expected.end(), file.begin()));
  // Data 234 bytes; summary: Schema 41 + Channel 30 + Chunk Index 91 + Statistics 65, 4 Summary Offsets of
  // 26, Footer 29, magic 8.
  EXPECT_EQ(file.size(), 234u + 41 + 30 + 91 + 65 + 4 * 26 + 29 + 8);
  EXPECT_TRUE(std::equal(kMagic.begin(), kMagic.end(), file.end() - 8));
}

}  // namespace
}  // namespace vifusion::mcap
