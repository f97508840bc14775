#include <gtest/gtest.h>

#include "vifusion/gpio_sync/edge_detection.hpp"
#include "vifusion/gpio_sync/sync_line_options.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::gpio_sync {
namespace {

template <typename Change>
void expectInvalid(Change&& change, const std::string& expected) {
  SyncLineOptions options;
  change(options);
  test::expectError([&] { options.validate(); }, expected);
}

TEST(SyncLineOptions, DefaultsAreValid) {
  const SyncLineOptions options;
  EXPECT_NO_THROW(options.validate());
  EXPECT_EQ(options.chip, "gpiochip0");
  EXPECT_EQ(options.edges, EdgeDetection::kRising);
}

TEST(SyncLineOptions, NameTheBadFieldAndItsRange) {
  expectInvalid([](SyncLineOptions& o) { o.chip.clear(); }, "SyncLineOptions.chip is empty");
  expectInvalid([](SyncLineOptions& o) { o.chip = "dev/gpiochip0"; },
                "SyncLineOptions.chip \"dev/gpiochip0\" is neither a name under /dev (no '/') nor an absolute path");
  expectInvalid([](SyncLineOptions& o) { o.line_offset = -1; },
                "SyncLineOptions.line_offset must be in [0, 65535], got -1");
  expectInvalid([](SyncLineOptions& o) { o.line_offset = 70000; },
                "SyncLineOptions.line_offset must be in [0, 65535], got 70000");
  expectInvalid([](SyncLineOptions& o) { o.edges = static_cast<EdgeDetection>(7); },
                "SyncLineOptions.edges must be rising, falling or both, got 7");
  expectInvalid([](SyncLineOptions& o) { o.ring_capacity = 0; }, "SyncLineOptions.ring_capacity must be >= 1, got 0");
  expectInvalid([](SyncLineOptions& o) { o.wait_timeout_ms = 0; },
                "SyncLineOptions.wait_timeout_ms must be in (0, 1000] ms, got 0");
  expectInvalid([](SyncLineOptions& o) { o.wait_timeout_ms = 1001; },
                "SyncLineOptions.wait_timeout_ms must be in (0, 1000] ms, got 1001");
  expectInvalid([](SyncLineOptions& o) { o.rate_window_ns = 0; },
                "SyncLineOptions.rate_window_ns must be in (0, 60000000000] ns, got 0");
  expectInvalid([](SyncLineOptions& o) { o.rate_capacity = 1; },
                "SyncLineOptions.rate_capacity must be in [2, 65536], got 1");
}

TEST(SyncLineOptions, AcceptChipNamesAndPaths) {
  SyncLineOptions options;
  options.chip = "/dev/gpio-camera-strobe";
  EXPECT_NO_THROW(options.validate());
  options.chip = "gpiochip4";
  options.line_offset = SyncLineOptions::kMaxLineOffset;
  EXPECT_NO_THROW(options.validate());
}

TEST(EdgeDetection, NamesRoundTripAndOthersAreRefused) {
  for (const EdgeDetection edges : {EdgeDetection::kRising, EdgeDetection::kFalling, EdgeDetection::kBoth}) {
    EXPECT_EQ(parseEdgeDetection(edgeDetectionName(edges)), edges);
  }
  EXPECT_EQ(edgeDetectionName(EdgeDetection::kBoth), "both");
  EXPECT_FALSE(parseEdgeDetection("Rising").has_value());
  EXPECT_FALSE(parseEdgeDetection("").has_value());
}

}  // namespace
}  // namespace vifusion::gpio_sync
