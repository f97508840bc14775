#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "simulated_link.hpp"
#include "vifusion/clock/clock_mapper.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::clock {
namespace {

using test::LinkModel;
using test::LinkSample;
using test::SimulatedLink;

constexpr std::int64_t kOffsetToleranceNs = 10 * kNsPerMicrosecond;

/// Feeds the link until `until_ns` of device time has passed since its start; returns the last sample fed.
LinkSample feed(SimulatedLink& link, ClockMapper& mapper, std::int64_t until_ns) {
  LinkSample s;
  do {
    s = link.next();
    const ClockSampleResult result = mapper.addSample(s.device_ns, s.receive_ns);
    EXPECT_TRUE(result.accepted()) << result.message();
  } while (s.device_ns - link.model().start_device_ns < until_ns);
  return s;
}

/// The worst |mapped − true| of each transfer as it arrives, over the next `duration_ns` of device time.
std::int64_t onlineErrorNs(SimulatedLink& link, ClockMapper& mapper, std::int64_t duration_ns) {
  const LinkSample first = link.next();
  std::int64_t worst_ns = 0;
  for (LinkSample s = first; s.device_ns - first.device_ns < duration_ns; s = link.next()) {
    EXPECT_TRUE(mapper.addSample(s.device_ns, s.receive_ns).accepted());
    worst_ns = std::max(worst_ns, std::abs(*mapper.toHostNs(s.device_ns) - s.true_host_ns));
  }
  return worst_ns;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(ClockMapperBadInput, EachRejectionIsCountedAndNamed) {
  LinkModel model;
  SimulatedLink link(model, 11);
  ClockMapper mapper;
  const LinkSample last = feed(link, mapper, 12 * kNsPerSecond);
  ASSERT_TRUE(mapper.valid());
  const ClockEstimate before = mapper.estimate();
  const LinkSample next = link.next();

  // Host time 5 ms before the newest accepted one.
  ClockSampleResult r = mapper.addSample(next.device_ns, last.receive_ns - 5 * kNsPerMillisecond);
  EXPECT_EQ(r.outcome, ClockSampleOutcome::kHostBackwards);
  EXPECT_TRUE(contains(
      r.message(), "host_ns goes backwards (5.000 ms before the previous sample's " + std::to_string(last.receive_ns)))
      << r.message();
  // The same device time again (a duplicated transfer).
  r = mapper.addSample(last.device_ns, next.receive_ns);
  EXPECT_EQ(r.outcome, ClockSampleOutcome::kDeviceNotIncreasing);
  EXPECT_TRUE(contains(r.message(), "device_ns does not increase (0.000 ms before")) << r.message();
  // A corrupt device time 5 s ahead: it would arrive 5 s before the mapping allows.
  r = mapper.addSample(next.device_ns + 5 * kNsPerSecond, next.receive_ns);
  EXPECT_EQ(r.outcome, ClockSampleOutcome::kEarly);
  EXPECT_NEAR(static_cast<double>(r.reference_ns - r.host_ns), 5.00025e9, 1e6);  // 5 s plus 50 ppm of it
  EXPECT_TRUE(contains(r.message(), "earlier than the mapping allows (latency cannot be negative)")) << r.message();
  // Negative and absurd times.
  r = mapper.addSample(-1, next.receive_ns);
  EXPECT_EQ(r.outcome, ClockSampleOutcome::kOutOfRange);
  EXPECT_TRUE(contains(r.message(), "device_ns or host_ns is outside [0, 2305843009213693952]")) << r.message();
  EXPECT_EQ(mapper.addSample(next.device_ns, INT64_MAX).outcome, ClockSampleOutcome::kOutOfRange);

  // None of it moved the fit, and the good sample still goes in.
  EXPECT_EQ(mapper.estimate().ref_device_ns, before.ref_device_ns);
  EXPECT_EQ(mapper.estimate().skew, before.skew);
  EXPECT_EQ(mapper.addSample(next.device_ns, next.receive_ns).outcome, ClockSampleOutcome::kAccepted);
  const ClockMapperStats& stats = mapper.stats();
  EXPECT_EQ(stats.host_backwards, 1u);
  EXPECT_EQ(stats.device_not_increasing, 1u);
  EXPECT_EQ(stats.early, 1u);
  EXPECT_EQ(stats.out_of_range, 2u);
  EXPECT_EQ(stats.rejected(), 5u);
  EXPECT_EQ(stats.restarts, 0u);
  EXPECT_EQ(stats.samples, stats.accepted + stats.rejected());
  EXPECT_LE(onlineErrorNs(link, mapper, 5 * kNsPerSecond), kOffsetToleranceNs);
}

TEST(ClockMapperBadInput, ScatteredCorruptTimestampsNeverRestart) {
  // Every 10th transfer carries a device time 2–9 s ahead: seven such in a row would be needed to look
  // like a step, and each is dropped without touching the fit.
  LinkModel model;
  SimulatedLink link(model, 12);
  ClockMapper mapper;
  feed(link, mapper, 5 * kNsPerSecond);
  std::int64_t worst_ns = 0;
  for (int i = 0; i < 4500; ++i) {
    const LinkSample s = link.next();
    if (i % 10 == 0) {
      const std::int64_t corrupt_ns = s.device_ns + (2 + i % 8) * kNsPerSecond;
      EXPECT_EQ(mapper.addSample(corrupt_ns, s.receive_ns).outcome, ClockSampleOutcome::kEarly);
    }
    EXPECT_TRUE(mapper.addSample(s.device_ns, s.receive_ns).accepted());
    worst_ns = std::max(worst_ns, std::abs(*mapper.toHostNs(s.device_ns) - s.true_host_ns));
  }
  EXPECT_EQ(mapper.stats().early, 450u);
  EXPECT_EQ(mapper.stats().restarts, 0u);
  EXPECT_LE(worst_ns, kOffsetToleranceNs);
}

TEST(ClockMapperSteps, HostSuspendRestartsTheWindow) {
  // CLOCK_MONOTONIC stops for 3 s at 15 s while the device counts on: every later transfer arrives 3 s
  // "early". step_confirm_samples of them in a row confirm the step; the skew is carried over.
  LinkModel model;
  model.host_pause_after_ns = 15 * kNsPerSecond;
  model.host_pause_ns = 3 * kNsPerSecond;
  SimulatedLink link(model, 13);
  const ClockMapperOptions options;
  ClockMapper mapper(options);
  feed(link, mapper, model.host_pause_after_ns - link.periodNs());  // the last transfer before the suspend
  ASSERT_TRUE(mapper.valid());
  for (std::size_t i = 1; i < options.step_confirm_samples; ++i) {
    const LinkSample s = link.next();
    const ClockSampleResult r = mapper.addSample(s.device_ns, s.receive_ns);
    ASSERT_EQ(r.outcome, ClockSampleOutcome::kEarly) << r.message();
    EXPECT_NEAR(static_cast<double>(r.reference_ns - r.host_ns), 3e9, 1e6);
  }
  const LinkSample confirming = link.next();
  const ClockSampleResult r = mapper.addSample(confirming.device_ns, confirming.receive_ns);
  ASSERT_EQ(r.outcome, ClockSampleOutcome::kRestarted) << r.message();
  EXPECT_EQ(r.reference_ns, static_cast<std::int64_t>(options.step_confirm_samples));
  EXPECT_TRUE(contains(r.message(), "clock step confirmed by 8 samples")) << r.message();
  EXPECT_EQ(mapper.state(), ClockMapperState::kWarmingUp);
  EXPECT_EQ(mapper.windowSize(), options.step_confirm_samples);
  EXPECT_NEAR(mapper.skewPpm(), 50.0, 1.0);  // carried from the last valid fit
  // Warming up: good to the lowest of 8 latencies, not yet to µs.
  const std::int64_t warm_error_ns = std::abs(*mapper.toHostNs(confirming.device_ns) - confirming.true_host_ns);
  EXPECT_LT(warm_error_ns, 1 * kNsPerMillisecond);
  EXPECT_EQ(mapper.stats().restarts, 1u);
  EXPECT_EQ(mapper.stats().held_back_used, options.step_confirm_samples - 1);
  // Ten seconds after the step the acceptance bounds hold again.
  feed(link, mapper, model.host_pause_after_ns + model.host_pause_ns + 10 * kNsPerSecond);
  EXPECT_TRUE(mapper.valid());
  EXPECT_NEAR(mapper.skewPpm(), 50.0, 1.0);
  EXPECT_LE(onlineErrorNs(link, mapper, 5 * kNsPerSecond), kOffsetToleranceNs);
  std::printf("[ measured ] 3 s host suspend: restart after %zu samples, warm-up error %.1f us\n",
              options.step_confirm_samples, static_cast<double>(warm_error_ns) / 1e3);
}

TEST(ClockMapperSteps, DeviceCounterRestartRestartsTheWindow) {
  // The device resets and its time starts again near 0.1 s while the host runs on.
  LinkModel model;
  SimulatedLink link(model, 14);
  const ClockMapperOptions options;
  ClockMapper mapper(options);
  feed(link, mapper, 12 * kNsPerSecond);
  const std::int64_t shift_ns = link.next().device_ns - kNsPerSecond / 10;
  std::size_t held_back = 0;
  ClockSampleResult r;
  do {
    const LinkSample s = link.next();
    r = mapper.addSample(s.device_ns - shift_ns, s.receive_ns);
    if (r.outcome == ClockSampleOutcome::kDeviceNotIncreasing) ++held_back;
  } while (r.outcome == ClockSampleOutcome::kDeviceNotIncreasing);
  EXPECT_EQ(r.outcome, ClockSampleOutcome::kRestarted);
  EXPECT_EQ(held_back, options.step_confirm_samples - 1);
  // The new mapping holds the shifted device times.
  std::int64_t worst_ns = 0;
  for (int i = 0; i < 12 * 450; ++i) {
    const LinkSample s = link.next();
    EXPECT_TRUE(mapper.addSample(s.device_ns - shift_ns, s.receive_ns).accepted());
    if (i > 10 * 450)
      worst_ns = std::max(worst_ns, std::abs(*mapper.toHostNs(s.device_ns - shift_ns) - s.true_host_ns));
  }
  EXPECT_LE(worst_ns, kOffsetToleranceNs);
}

TEST(ClockMapperStates, EmptyWarmingUpValidAndReset) {
  ClockMapperOptions options;
  ClockMapper mapper(options);
  EXPECT_EQ(mapper.state(), ClockMapperState::kEmpty);
  EXPECT_FALSE(mapper.toHostNs(0).has_value());
  EXPECT_EQ(mapper.offsetNs(), 0);
  // One sample: the mapping is that sample, skew 0.
  const std::int64_t t0_ns = 5 * kNsPerSecond;
  const std::int64_t host0_ns = 1000 * kNsPerSecond;
  mapper.addSample(t0_ns, host0_ns + 300'000);
  EXPECT_EQ(mapper.state(), ClockMapperState::kWarmingUp);
  EXPECT_EQ(*mapper.toHostNs(t0_ns), host0_ns + 300'000);
  // A faster transfer becomes the reference: mapping = its host time, shifted by its device time.
  mapper.addSample(t0_ns + kNsPerMillisecond, host0_ns + kNsPerMillisecond + 100'000);
  EXPECT_EQ(*mapper.toHostNs(t0_ns), host0_ns + 100'000);
  EXPECT_EQ(mapper.offsetNs(), host0_ns + 100'000 - t0_ns);
  // Valid once min_samples and min_span_s are both reached: at 2 s of span with 450 transfers/s.
  LinkModel model;
  model.start_device_ns = t0_ns + 2 * kNsPerMillisecond;
  model.start_host_ns = host0_ns + 2 * kNsPerMillisecond;
  SimulatedLink link(model, 15);
  std::int64_t valid_at_span_ns = -1;
  for (int i = 0; i < 3 * 450 && valid_at_span_ns < 0; ++i) {
    const LinkSample s = link.next();
    mapper.addSample(s.device_ns, s.receive_ns);
    if (mapper.valid()) valid_at_span_ns = mapper.spanNs();
  }
  EXPECT_GE(valid_at_span_ns, options.minSpanNs());
  EXPECT_LT(valid_at_span_ns, options.minSpanNs() + link.periodNs());
  EXPECT_STREQ(clockMapperStateName(mapper.state()), "valid");
  const std::uint64_t samples = mapper.stats().samples;
  mapper.reset();
  EXPECT_EQ(mapper.state(), ClockMapperState::kEmpty);
  EXPECT_EQ(mapper.windowSize(), 0u);
  EXPECT_EQ(mapper.skewPpm(), 0.0);
  EXPECT_EQ(mapper.stats().samples, samples);  // statistics survive reset()
}

TEST(ClockMapperStates, LongGapFallsBackToWarmingUpWithTheLastSkew) {
  // No transfers for 30 s (longer than the 20 s window): everything expires but the newest sample, and
  // the mapping keeps the last skew until the window fills again.
  LinkModel model;
  SimulatedLink link(model, 16);
  ClockMapper mapper;
  feed(link, mapper, 12 * kNsPerSecond);
  for (int i = 0; i < 30 * 450; ++i) link.next();
  const LinkSample s = link.next();
  EXPECT_TRUE(mapper.addSample(s.device_ns, s.receive_ns).accepted());
  EXPECT_EQ(mapper.state(), ClockMapperState::kWarmingUp);
  EXPECT_EQ(mapper.windowSize(), 1u);
  EXPECT_NEAR(mapper.skewPpm(), 50.0, 1.0);
}

}  // namespace
}  // namespace vifusion::clock
