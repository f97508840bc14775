// Corrupt bytes are caught (a chunk's CRC-32, the summary's CRC-32, malformed records) and named, and
// never crash the reader.

#include <gtest/gtest.h>

#include "mcap_test_support.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::mcap {
namespace {

using test::TestMessage;

constexpr std::int64_t kStartNs = 3'000 * kNsPerSecond;
constexpr std::uint16_t kChannels = 2;
/// Chunk record bytes before its records: opcode, length, times, sizes, CRC, compression, records length.
constexpr std::size_t kChunkPrefixBytes = 9 + 8 + 8 + 8 + 4 + 4 + 8;

struct Recording {
  std::vector<std::uint8_t> bytes;
  test::WrittenRecording written;
  std::vector<ChunkInfo> chunks;
};

Recording record() {
  test::TempDir dir;
  McapWriterOptions options;
  options.sync = SyncPolicy::kNone;
  options.chunk_target_bytes = 300;
  Recording r;
  r.written = test::writeRecording(dir.file("r.mcap"), options,
                                   test::makeMessages(80, kChannels, kStartNs, kNsPerMillisecond, 5, 30, 6), kChannels);
  r.bytes = test::readFileBytes(dir.file("r.mcap"));
  r.chunks = test::readerOverPrefix(r.bytes, r.bytes.size()).chunks();
  return r;
}

TEST(McapCorruption, ABitFlipInAChunkIsCaughtByItsCrcAndNamed) {
  Recording r = record();
  ASSERT_GE(r.chunks.size(), 6u);
  const ChunkInfo& bad = r.chunks[3];
  r.bytes[bad.offset + kChunkPrefixBytes + 40] ^= 0x10;  // inside the second record's data or fields

  // Complete file: the summary is intact, the chunk's CRC fails when it is read.
  McapReader reader = test::readerOverPrefix(r.bytes, r.bytes.size());
  ASSERT_TRUE(reader.summaryUsed());
  std::vector<TestMessage> read;
  MessageView view;
  try {
    while (reader.readNext(view)) read.push_back({view.channel_id, view.sequence, view.log_time_ns, 0, {}});
    ADD_FAILURE() << "no error for the flipped bit";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("cut.mcap: chunk at offset " + std::to_string(bad.offset) +
                           ": Chunk.uncompressed_crc: CRC mismatch: stored 0x"),
              std::string::npos)
        << message;
  }
  EXPECT_EQ(read.size(), r.written.messages_through_chunk[2]);  // the three chunks before it
  // Reading on skips the bad chunk and gives all the others.
  std::size_t after = 0;
  while (reader.readNext(view)) ++after;
  EXPECT_EQ(read.size() + after,
            r.written.messages.size() - (r.written.messages_through_chunk[3] - r.written.messages_through_chunk[2]));

  // Cut file (no summary): the scan stops at the corrupt chunk and says so.
  McapReader scanned = test::readerOverPrefix(r.bytes, r.bytes.size() - 1);
  EXPECT_FALSE(scanned.complete());
  EXPECT_NE(scanned.note().find("stopped at offset " + std::to_string(bad.offset) +
                                ": the Chunk record there is corrupt: Chunk.uncompressed_crc: CRC mismatch"),
            std::string::npos)
      << scanned.note();
  EXPECT_EQ(test::readAll(scanned).size(), r.written.messages_through_chunk[2]);
}

TEST(McapCorruption, ADamagedSummaryFallsBackToTheScan) {
  Recording r = record();
  r.bytes[r.bytes.size() - 60] ^= 0x01;  // inside the summary offsets / statistics
  McapReader reader = test::readerOverPrefix(r.bytes, r.bytes.size());
  EXPECT_FALSE(reader.summaryUsed());
  EXPECT_NE(reader.summaryProblem().find("Footer.summary_crc: CRC mismatch"), std::string::npos)
      << reader.summaryProblem();
  EXPECT_TRUE(reader.complete());
  EXPECT_EQ(test::readAll(reader), r.written.messages);
}

TEST(McapCorruption, NotMcapIsAnErrorNamingTheFile) {
  const std::vector<std::uint8_t> text = {'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd', '\n'};
  vifusion::test::expectError([&] { test::readerOverPrefix(text, text.size()); },
                              "cut.mcap: not an MCAP file: it does not start with the MCAP magic");
  vifusion::test::expectError([&] { test::readerOverPrefix(text, 0); }, "cut.mcap: the file is empty (0 bytes)");
  vifusion::test::expectError([&] { McapReader missing("/nonexistent/run.mcap"); },
                              "/nonexistent/run.mcap: cannot open: No such file or directory");
  Recording r = record();
  r.bytes[8] = 0x05;  // the first record is no longer a Header
  vifusion::test::expectError([&] { test::readerOverPrefix(r.bytes, r.bytes.size()); },
                              "the record after the magic is a Message record, not a Header");
}

TEST(McapCorruption, EveryByteInvertedInTurnNeverCrashes) {
  // Each variant either opens (maybe with a note) and reads, or throws vifusion::Error — nothing else.
  const Recording r = record();
  std::size_t opened = 0;
  std::size_t refused = 0;
  for (std::size_t at = 0; at < r.bytes.size(); ++at) {
    std::vector<std::uint8_t> bytes = r.bytes;
    bytes[at] ^= 0xFF;
    try {
      McapReader reader = test::readerOverPrefix(bytes, bytes.size());
      MessageView view;
      for (int guard = 0; guard < 100000; ++guard) {
        try {
          if (!reader.readNext(view)) break;
        } catch (const Error&) {
          // a corrupt chunk: read on
        }
      }
      ++opened;
    } catch (const Error&) {
      ++refused;
    }
  }
  EXPECT_EQ(opened + refused, r.bytes.size());
  EXPECT_GT(opened, r.bytes.size() * 9 / 10);  // only the magic and the Header make a file unreadable
}

}  // namespace
}  // namespace vifusion::mcap
