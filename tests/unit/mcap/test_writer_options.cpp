#include <gtest/gtest.h>

#include "vifusion/mcap/mcap_writer_options.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::mcap {
namespace {

template <typename Change>
void expectInvalid(Change&& change, const std::string& expected) {
  McapWriterOptions options;
  change(options);
  vifusion::test::expectError([&] { options.validate(); }, expected);
}

TEST(McapWriterOptions, DefaultsAreTheDocumentedOnes) {
  const McapWriterOptions options;
  EXPECT_NO_THROW(options.validate());
  EXPECT_EQ(options.chunk_target_bytes, 4u * 1024 * 1024);
  EXPECT_EQ(options.chunk_flush_ns, 50'000'000);
  EXPECT_EQ(options.max_message_bytes, 2u * 1024 * 1024);
  EXPECT_EQ(options.sync, SyncPolicy::kFdatasyncPerChunk);
  EXPECT_EQ(options.profile, "ros2");
  EXPECT_EQ(options.library, "vifusion");
}

TEST(McapWriterOptions, NameTheBadFieldAndItsRange) {
  expectInvalid([](McapWriterOptions& o) { o.chunk_target_bytes = 0; },
                "McapWriterOptions.chunk_target_bytes must be in [1, 1073741824] bytes, got 0");
  expectInvalid([](McapWriterOptions& o) { o.chunk_flush_ns = 0; },
                "McapWriterOptions.chunk_flush_ns must be in (0, 60000000000] ns, got 0");
  expectInvalid([](McapWriterOptions& o) { o.chunk_flush_ns = -5; },
                "McapWriterOptions.chunk_flush_ns must be in (0, 60000000000] ns, got -5");
  expectInvalid([](McapWriterOptions& o) { o.max_message_bytes = 0; },
                "McapWriterOptions.max_message_bytes must be in [1, 1073741824] bytes, got 0");
  expectInvalid([](McapWriterOptions& o) { o.max_messages_per_chunk = 0; },
                "McapWriterOptions.max_messages_per_chunk must be in [1, 1048576], got 0");
  expectInvalid([](McapWriterOptions& o) { o.max_channels = 65536; },
                "McapWriterOptions.max_channels must be in [1, 65535], got 65536");
  expectInvalid([](McapWriterOptions& o) { o.reserved_chunks = 0; },
                "McapWriterOptions.reserved_chunks must be in [1, 10000000], got 0");
  expectInvalid([](McapWriterOptions& o) { o.sync = static_cast<SyncPolicy>(9); },
                "McapWriterOptions.sync must be none or fdatasync per chunk, got 9");
}

}  // namespace
}  // namespace vifusion::mcap
