// Recording allocates nothing per message after open(); reading allocates nothing per message after the
// reader is constructed. Counted with the test binary's replaced operator new.

#include <gtest/gtest.h>

#include "mcap_test_support.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/mcap/mcap_writer.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::mcap {
namespace {

constexpr std::int64_t kStartNs = 6'000 * kNsPerSecond;
constexpr std::size_t kMessages = 10'000;

TEST(McapAllocations, WritingTenThousandMessagesAfterOpenAllocatesNothing) {
  test::TempDir dir;
  McapWriterOptions options;  // fdatasync per chunk, as in the field
  options.chunk_target_bytes = 256 * 1024;
  options.chunk_flush_ns = 100 * kNsPerMillisecond;  // the chunk counts below
  McapWriter writer(options);
  ASSERT_TRUE(writer.open(dir.file("alloc.mcap")));
  const std::uint16_t imu = writer.registerChannel("/imu", McapWriter::kNoId, "cdr");
  const std::uint16_t depth = writer.registerChannel("/camera/depth", McapWriter::kNoId, "cdr");
  const std::vector<std::uint8_t> sample(120, 0x5A);

  const std::uint64_t before = vifusion::test::heapAllocationCount();
  for (std::size_t i = 0; i < kMessages; ++i) {
    const std::int64_t t_ns = kStartNs + static_cast<std::int64_t>(i) * kNsPerMillisecond;
    if (i % 10 == 0) {  // an "image", serialised in place
      const std::span<std::uint8_t> space = writer.reserveMessage(2000);
      space[0] = static_cast<std::uint8_t>(i);
      writer.commitMessage(depth, static_cast<std::uint32_t>(i / 10), t_ns, t_ns, 1500);
    } else {
      writer.write(imu, static_cast<std::uint32_t>(i), t_ns, t_ns, sample);
    }
    writer.flushIfDue(t_ns);
  }
  const std::uint64_t allocations = vifusion::test::heapAllocationCount() - before;
  EXPECT_EQ(allocations, 0u);
  EXPECT_FALSE(writer.failed()) << writer.error();
  // Closed by age: 99 chunks of 101 messages (0 .. 100 ms of log time each, 29 kB, under the size target);
  // the last message is still in the open chunk.
  EXPECT_EQ(writer.chunksWritten(), 99u);
  EXPECT_EQ(writer.messagesWritten(), 99u * 101);
  EXPECT_TRUE(writer.close());

  McapReader reader(dir.file("alloc.mcap"));
  MessageView view;
  std::size_t read = 0;
  const std::uint64_t reading_before = vifusion::test::heapAllocationCount();
  while (reader.readNext(view)) ++read;
  EXPECT_EQ(vifusion::test::heapAllocationCount() - reading_before, 0u);
  EXPECT_EQ(read, kMessages);
}

}  // namespace
}  // namespace vifusion::mcap
