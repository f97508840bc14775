#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "vifusion/clock/clock_mapper.hpp"
#include "vifusion/clock/clock_mapper_options.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::clock {
namespace {

/// Validating options with one field changed by `change` must fail with `expected` in the message.
void expectInvalid(const std::function<void(ClockMapperOptions&)>& change, const std::string& expected) {
  ClockMapperOptions options;
  change(options);
  test::expectError([&] { options.validate(); }, expected);
  test::expectError([&] { ClockMapper mapper(options); }, expected);  // the constructor validates too
}

TEST(ClockMapperOptions, DefaultsAreValid) {
  const ClockMapperOptions options;
  EXPECT_NO_THROW(options.validate());
  EXPECT_EQ(options.windowNs(), 20'000'000'000);
  EXPECT_EQ(options.minSpanNs(), 2'000'000'000);
}

TEST(ClockMapperOptions, EachBadFieldIsNamed) {
  expectInvalid([](auto& o) { o.window_s = 0.0; }, "'window_s' = 0 must be finite and in (0, 3600]");
  expectInvalid([](auto& o) { o.window_s = 1e9; }, "'window_s' = 1e+09 must be finite and in (0, 3600]");
  expectInvalid([](auto& o) { o.window_s = std::nan(""); }, "'window_s' = nan must be");
  expectInvalid([](auto& o) { o.min_span_s = 25.0; }, "'min_span_s' = 25 must be finite and in (0, window_s = 20)");
  expectInvalid([](auto& o) { o.min_samples = 1; }, "'min_samples' = 1 must be >= 2");
  expectInvalid([](auto& o) { o.window_samples = 10; }, "'window_samples' = 10 must be >= min_samples = 64");
  expectInvalid([](auto& o) { o.fixed_latency_ns = -1; }, "'fixed_latency_ns' = -1 must be in [0, 1000000000)");
  expectInvalid([](auto& o) { o.max_early_ns = 0; }, "'max_early_ns' = 0 must be > 0");
  expectInvalid([](auto& o) { o.step_confirm_samples = 0; }, "'step_confirm_samples' = 0 must be in [1, 64]");
  expectInvalid([](auto& o) { o.step_confirm_samples = 65; }, "'step_confirm_samples' = 65 must be in [1, 64]");
}

}  // namespace
}  // namespace vifusion::clock
