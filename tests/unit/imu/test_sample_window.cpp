#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "imu_test_utils.hpp"
#include "vifusion/imu/preintegration.hpp"
#include "vifusion/imu/sample_window.hpp"

namespace vifusion::imu {
namespace {

using test::kPeriodNs;

constexpr std::int64_t kStartNs = 1'000'000'000;
constexpr std::int64_t kMaxGapNs = 12'500'000;

/// 21 samples, 1.000 s … 1.100 s.
std::vector<ImuSample> cleanSamples() { return test::smoothSamples(3, kStartNs, 21); }

std::optional<ImuSampleIssue> check(const std::vector<ImuSample>& samples, std::int64_t t0_ns, std::int64_t t1_ns,
                                    SampleRange& range) {
  return checkSampleWindow(samples, t0_ns, t1_ns, kMaxGapNs, range);
}

void expectIssue(const std::optional<ImuSampleIssue>& issue, ImuSampleProblem problem, std::int64_t t_ns,
                 const std::string& text) {
  ASSERT_TRUE(issue.has_value());
  EXPECT_EQ(issue->problem, problem);
  EXPECT_EQ(issue->t_ns, t_ns);
  const std::string message = issue->message();
  EXPECT_NE(message.find("t_ns=" + std::to_string(t_ns)), std::string::npos) << message;
  EXPECT_NE(message.find(text), std::string::npos) << message;
}

TEST(SampleWindow, FindsTheBracketingSamples) {
  const std::vector<ImuSample> samples = cleanSamples();
  SampleRange range;
  // Frame times between samples: the last sample before t0 and the first after t1.
  ASSERT_FALSE(check(samples, kStartNs + 7'300'000, kStartNs + 40'100'000, range));
  EXPECT_EQ(range.first, 1u);
  EXPECT_EQ(range.last, 9u);
  // Frame times on samples: those samples themselves.
  ASSERT_FALSE(check(samples, kStartNs + 10'000'000, kStartNs + 45'000'000, range));
  EXPECT_EQ(range.first, 2u);
  EXPECT_EQ(range.last, 9u);
  // The whole span.
  ASSERT_FALSE(check(samples, kStartNs, kStartNs + 100'000'000, range));
  EXPECT_EQ(range.first, 0u);
  EXPECT_EQ(range.last, 20u);
}

TEST(SampleWindow, BracketingSamplesCutALongStreamToWhatTheChecksNeed) {
  const std::vector<ImuSample> samples = cleanSamples();
  const auto indices = [&](std::span<const ImuSample> part) {
    return std::pair<long, long>(part.data() - samples.data(), part.data() - samples.data() + long(part.size()) - 1);
  };
  // Between samples, and on samples: the same indices checkSampleWindow reports.
  EXPECT_EQ(indices(bracketingSamples(samples, kStartNs + 7'300'000, kStartNs + 40'100'000)), std::pair(1L, 9L));
  EXPECT_EQ(indices(bracketingSamples(samples, kStartNs + 10'000'000, kStartNs + 45'000'000)), std::pair(2L, 9L));
  // Frame times outside the stream keep the nearest end, so the check reports kNotCovered.
  EXPECT_EQ(indices(bracketingSamples(samples, kStartNs - 1, kStartNs + 100'000'001)), std::pair(0L, 20L));
  const std::span<const ImuSample> late = bracketingSamples(samples, kStartNs + 200'000'000, kStartNs + 300'000'000);
  EXPECT_EQ(indices(late), std::pair(20L, 20L));
  SampleRange range;
  const auto issue = check(std::vector<ImuSample>(late.begin(), late.end()), kStartNs + 200'000'000,
                           kStartNs + 300'000'000, range);
  ASSERT_TRUE(issue.has_value());
  EXPECT_EQ(issue->problem, ImuSampleProblem::kNotCovered);
  EXPECT_TRUE(bracketingSamples({}, 0, 1).empty());
}

TEST(SampleWindow, ReportsOutOfOrderSamplesWithTheirTime) {
  std::vector<ImuSample> samples = cleanSamples();
  std::swap(samples[4], samples[5]);  // 1.025 s now comes before 1.020 s
  SampleRange range;
  expectIssue(check(samples, kStartNs + 50'000'000, kStartNs + 90'000'000, range), ImuSampleProblem::kOutOfOrder,
              1'020'000'000, "goes backwards by 5.000 ms (previous sample at t_ns=1025000000)");
}

TEST(SampleWindow, ReportsDuplicateTimestamps) {
  std::vector<ImuSample> samples = cleanSamples();
  samples[8].t_ns = samples[7].t_ns;
  SampleRange range;
  expectIssue(check(samples, kStartNs + 10'000'000, kStartNs + 50'000'000, range), ImuSampleProblem::kDuplicate,
              1'035'000'000, "duplicate timestamp");
}

TEST(SampleWindow, ReportsGapsInTheIntegratedStretchOnly) {
  std::vector<ImuSample> samples = cleanSamples();
  SampleRange range;
  // One dropped sample (10 ms) is within 2.5 periods.
  std::vector<ImuSample> one_dropped = samples;
  one_dropped.erase(one_dropped.begin() + 6);
  EXPECT_FALSE(check(one_dropped, kStartNs + 12'000'000, kStartNs + 60'000'000, range));
  // Two dropped samples (15 ms) are a gap, named by the sample after it.
  std::vector<ImuSample> two_dropped = samples;
  two_dropped.erase(two_dropped.begin() + 6, two_dropped.begin() + 8);
  expectIssue(check(two_dropped, kStartNs + 12'000'000, kStartNs + 60'000'000, range), ImuSampleProblem::kGap,
              1'040'000'000, "gap of 15.000 ms since the previous sample at t_ns=1025000000 (at most 12.500 ms");
  // A gap inside the bracketing pair (t0 falls in it) is reported too ...
  expectIssue(check(two_dropped, kStartNs + 30'000'000, kStartNs + 60'000'000, range), ImuSampleProblem::kGap,
              1'040'000'000, "gap of 15.000 ms");
  // ... but not one outside the frame interval.
  EXPECT_FALSE(check(two_dropped, kStartNs + 40'000'000, kStartNs + 90'000'000, range));
  EXPECT_EQ(range.first, 6u);
}

TEST(SampleWindow, ReportsFrameTimesTheSamplesDoNotCover) {
  const std::vector<ImuSample> samples = cleanSamples();
  SampleRange range;
  expectIssue(check(samples, kStartNs - 1, kStartNs + 50'000'000, range), ImuSampleProblem::kNotCovered, kStartNs - 1,
              "no IMU sample at or before it (first sample at t_ns=1000000000)");
  expectIssue(check(samples, kStartNs + 50'000'000, kStartNs + 100'000'001, range), ImuSampleProblem::kNotCovered,
              kStartNs + 100'000'001, "no IMU sample at or after it (last sample at t_ns=1100000000)");
  expectIssue(check({}, kStartNs, kStartNs + 10, range), ImuSampleProblem::kNoSamples, kStartNs,
              "no IMU samples for the frame interval");
  expectIssue(check(samples, kStartNs + 50'000'000, kStartNs + 50'000'000, range), ImuSampleProblem::kEmptyInterval,
              kStartNs + 50'000'000, "not after its start");
}

TEST(SampleWindow, ReportsNonFiniteReadings) {
  std::vector<ImuSample> samples = cleanSamples();
  samples[5].accel_mps2.y() = std::numeric_limits<double>::quiet_NaN();
  SampleRange range;
  expectIssue(check(samples, kStartNs + 12'000'000, kStartNs + 40'000'000, range), ImuSampleProblem::kNonFinite,
              1'025'000'000, "not finite");
  EXPECT_FALSE(check(samples, kStartNs + 30'000'000, kStartNs + 60'000'000, range));  // not integrated there
}

TEST(SampleWindow, PreintegratorReturnsTheIssueAndLeavesItsOutputAlone) {
  std::vector<ImuSample> samples = cleanSamples();
  samples[9].t_ns = samples[8].t_ns - kPeriodNs;
  const ImuPreintegrator integrator{ImuOptions{}};
  PreintegratedImu pre;
  pre.t0_ns = 123;
  const auto issue = integrator.integrate(samples, kStartNs + 10'000'000, kStartNs + 60'000'000,
                                          Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), pre);
  expectIssue(issue, ImuSampleProblem::kOutOfOrder, 1'035'000'000, "goes backwards by 5.000 ms");
  EXPECT_EQ(pre.t0_ns, 123);
  EXPECT_TRUE(pre.covariance.isZero());
}

}  // namespace
}  // namespace vifusion::imu
