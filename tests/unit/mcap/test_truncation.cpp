// A recording cut anywhere — the crash cases: SIGKILL, power loss, a full disk — opens and yields exactly
// the messages of the chunks completed before the cut.

#include <gtest/gtest.h>

#include <random>

#include "mcap_test_support.hpp"
#include "vifusion/core/little_endian.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/mcap/mcap_format.hpp"
#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::mcap {
namespace {

using test::TestMessage;

constexpr std::int64_t kStartNs = 2'000 * kNsPerSecond;
constexpr std::uint16_t kChannels = 3;
constexpr std::size_t kMagicBytes = 8;
constexpr std::size_t kDataEndRecordBytes = kRecordHeaderBytes + 4;

struct Recording {
  std::vector<std::uint8_t> bytes;
  test::WrittenRecording written;
  std::vector<ChunkInfo> chunks;  ///< from the complete file's summary
  std::uint64_t data_end = 0;     ///< offset of the DataEnd record
};

Recording record(std::size_t messages, std::size_t chunk_target_bytes, std::size_t max_bytes) {
  test::TempDir dir;
  McapWriterOptions options;
  options.sync = SyncPolicy::kNone;
  options.chunk_target_bytes = chunk_target_bytes;
  Recording r;
  r.written = test::writeRecording(
      dir.file("r.mcap"), options,
      test::makeMessages(messages, kChannels, kStartNs, kNsPerMillisecond, 0, max_bytes, 4), kChannels);
  r.bytes = test::readFileBytes(dir.file("r.mcap"));
  McapReader complete = test::readerOverPrefix(r.bytes, r.bytes.size());
  EXPECT_TRUE(complete.summaryUsed());
  r.chunks = complete.chunks();
  // After the last chunk come its Message Index records, then DataEnd (opcode 0x0F).
  const ChunkInfo& last = r.chunks.back();
  r.data_end = last.offset + last.record_bytes;
  while (r.bytes[r.data_end] != 0x0F) r.data_end += kRecordHeaderBytes + loadU64(&r.bytes[r.data_end + 1]);
  return r;
}

/// Messages of the chunks that end at or before `cut`.
std::size_t completeMessagesBefore(const Recording& r, std::size_t cut) {
  std::size_t messages = 0;
  for (std::size_t k = 0; k < r.chunks.size(); ++k) {
    if (r.chunks[k].offset + r.chunks[k].record_bytes <= cut) messages = r.written.messages_through_chunk[k];
  }
  return messages;
}

void expectCutReadsTheCompleteChunks(const Recording& r, std::size_t cut) {
  SCOPED_TRACE("cut at byte " + std::to_string(cut) + " of " + std::to_string(r.bytes.size()));
  if (cut < kMagicBytes) {
    vifusion::test::expectError([&] { test::readerOverPrefix(r.bytes, cut); }, cut == 0 ? "is empty" : "magic");
    return;
  }
  McapReader reader = test::readerOverPrefix(r.bytes, cut);
  const std::vector<TestMessage> read = test::readAll(reader);
  const std::size_t expected = completeMessagesBefore(r, cut);
  ASSERT_EQ(read.size(), expected);
  EXPECT_TRUE(std::equal(read.begin(), read.end(), r.written.messages.begin()));
  EXPECT_EQ(reader.statistics().message_count, expected);
  EXPECT_EQ(reader.summaryUsed(), cut == r.bytes.size());
  // Complete once the whole DataEnd record is there (the scan then knows the data section ended).
  EXPECT_EQ(reader.complete(), cut >= r.data_end + kDataEndRecordBytes) << reader.note();
  if (!reader.complete()) {
    const bool in_header = cut < r.chunks.front().offset && reader.schemas().empty() && reader.profile().empty();
    EXPECT_NE(reader.note().find(in_header ? "the file ends inside the Header record" : "stopped at offset"),
              std::string::npos)
        << reader.note();
  }
}

TEST(McapTruncation, EveryCutOfASmallRecordingOpensWithItsCompleteChunks) {
  const Recording r = record(60, 256, 40);
  ASSERT_GE(r.chunks.size(), 8u);
  ASSERT_LT(r.bytes.size(), 8000u);
  for (std::size_t cut = 0; cut <= r.bytes.size(); ++cut) {
    expectCutReadsTheCompleteChunks(r, cut);
    if (::testing::Test::HasFailure()) break;  // one cut's report is enough
  }
}

TEST(McapTruncation, ADenseSampleOfCutsOfABiggerRecording) {
  const Recording r = record(3000, 64 * 1024, 2000);
  ASSERT_GE(r.chunks.size(), 40u);
  std::mt19937 random(5);
  std::uniform_int_distribution<std::size_t> offset(0, r.bytes.size());
  for (int i = 0; i < 400; ++i) {
    expectCutReadsTheCompleteChunks(r, offset(random));
    if (::testing::Test::HasFailure()) break;
  }
  for (const ChunkInfo& chunk : r.chunks) {  // right at and around each chunk's end
    for (const std::size_t cut : {chunk.offset + chunk.record_bytes - 1, chunk.offset + chunk.record_bytes}) {
      expectCutReadsTheCompleteChunks(r, cut);
    }
  }
}

TEST(McapTruncation, TheNoteSaysWhereAndWhy) {
  const Recording r = record(60, 256, 40);
  const ChunkInfo& third = r.chunks[2];
  const std::size_t cut = third.offset + 100;
  McapReader reader = test::readerOverPrefix(r.bytes, cut);
  EXPECT_EQ(reader.note(), "cut.mcap: data accepted up to byte " + std::to_string(third.offset) + " of " +
                               std::to_string(cut) + " (2 chunks, " +
                               std::to_string(r.written.messages_through_chunk[1]) + " messages); stopped at offset " +
                               std::to_string(third.offset) + ": the file ends inside a Chunk record (content of " +
                               std::to_string(third.record_bytes - 9) + " bytes, 91 present)");
  EXPECT_EQ(reader.summaryProblem(), "the file does not end with the MCAP magic (it was cut while recording)");
  EXPECT_EQ(reader.channels().size(), 3u);
  EXPECT_EQ(reader.schemas().size(), 2u);
  EXPECT_EQ(reader.chunks().size(), 2u);

  McapReader in_header = test::readerOverPrefix(r.bytes, 20);
  EXPECT_EQ(in_header.note(), "cut.mcap: no data: the file ends inside the Header record (20 bytes)");
}

TEST(McapTruncation, AttachmentsBeforeTheCutSurvive) {
  const Recording r = record(60, 256, 40);
  // The attachment is written after half the messages: find the first cut at which it is there.
  std::size_t first_with = 0;
  for (std::size_t cut = kMagicBytes; cut <= r.bytes.size() && first_with == 0; ++cut) {
    if (test::readerOverPrefix(r.bytes, cut).attachments().size() == 1) first_with = cut;
  }
  ASSERT_GT(first_with, 0u);
  McapReader reader = test::readerOverPrefix(r.bytes, first_with);
  EXPECT_EQ(reader.attachments()[0].data, test::calibrationYaml());
  // It ends a record: the byte before it is an Attachment record's last CRC byte, its start an 0x09.
  const std::size_t record_bytes = 9 + 8 + 8 + 4 + 16 + 4 + 16 + 8 + test::calibrationYaml().size() + 4;
  EXPECT_EQ(r.bytes[first_with - record_bytes], 0x09);
}

}  // namespace
}  // namespace vifusion::mcap
