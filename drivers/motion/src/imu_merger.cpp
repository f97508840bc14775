#include "vifusion/motion/imu_merger.hpp"

#include <cinttypes>
#include <numeric>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::motion {
namespace {

constexpr std::size_t kMinAccelCapacity = 2;  // a bracket needs two samples
constexpr std::size_t kMinGyroCapacity = 1;

std::size_t index(ImuStream stream) { return static_cast<std::size_t>(stream); }

/// Validates before any buffer is sized from the options.
const ImuMergerOptions& validated(const ImuMergerOptions& options) {
  options.validate();
  return options;
}

const char* streamName(ImuStream stream) { return stream == ImuStream::kAccelerometer ? "accelerometer" : "gyroscope"; }

}  // namespace

void ImuMergerOptions::validate() const {
  if (accel_capacity < kMinAccelCapacity) {
    throw Error("imu merger option 'accel_capacity' = " + std::to_string(accel_capacity) +
                " must be >= " + std::to_string(kMinAccelCapacity));
  }
  if (gyro_capacity < kMinGyroCapacity) {
    throw Error("imu merger option 'gyro_capacity' = " + std::to_string(gyro_capacity) +
                " must be >= " + std::to_string(kMinGyroCapacity));
  }
  if (max_accel_gap_ns <= 0) {
    throw Error("imu merger option 'max_accel_gap_ns' = " + std::to_string(max_accel_gap_ns) + " must be > 0");
  }
}

std::string_view mergeDropReasonName(MergeDropReason reason) {
  switch (reason) {
    case MergeDropReason::kNonFiniteValue:
      return "non_finite_value";
    case MergeDropReason::kDuplicateTime:
      return "duplicate_time";
    case MergeDropReason::kOutOfOrderTime:
      return "out_of_order_time";
    case MergeDropReason::kGyroBeforeAccel:
      return "gyro_before_accel";
    case MergeDropReason::kAccelGap:
      return "accel_gap";
    case MergeDropReason::kBufferFull:
      return "buffer_full";
  }
  return "unknown_reason";
}

ProblemText describe(const MergeProblem& problem) {
  ProblemText text;
  const char* stream = streamName(problem.stream);
  const std::int64_t t_ns = problem.t_ns;
  const std::int64_t reference_ns = problem.reference_ns;
  switch (problem.reason) {
    case MergeDropReason::kNonFiniteValue:
      text.append("%s sample t_ns %" PRId64 " has a NaN or infinite axis value: dropped", stream, t_ns);
      break;
    case MergeDropReason::kDuplicateTime:
      text.append("%s sample t_ns %" PRId64 " is not after the previous %s sample at %" PRId64
                  " (duplicate time): dropped",
                  stream, t_ns, stream, reference_ns);
      break;
    case MergeDropReason::kOutOfOrderTime:
      text.append("%s sample t_ns %" PRId64 " goes back by %" PRId64 " ns from the previous %s sample at %" PRId64
                  " (out of order): dropped",
                  stream, t_ns, reference_ns - t_ns, stream, reference_ns);
      break;
    case MergeDropReason::kGyroBeforeAccel:
      text.append("gyroscope sample t_ns %" PRId64 " precedes the oldest buffered accelerometer sample at %" PRId64
                  ": no bracket without extrapolating, dropped",
                  t_ns, reference_ns);
      break;
    case MergeDropReason::kAccelGap:
      text.append("gyroscope sample t_ns %" PRId64 " falls in an accelerometer gap of %" PRId64
                  " ns, above max_accel_gap_ns %" PRId64 ": dropped",
                  t_ns, reference_ns, problem.limit_ns);
      break;
    case MergeDropReason::kBufferFull:
      text.append("%s buffer full: its oldest sample t_ns %" PRId64
                  " dropped (merged samples not popped, or the "
                  "other stream stalled)",
                  stream, t_ns);
      break;
  }
  return text;
}

std::uint64_t ImuMergerStats::totalDrops() const {
  std::uint64_t total = 0;
  for (const auto& per_stream : drop_counts) total = std::accumulate(per_stream.begin(), per_stream.end(), total);
  return total;
}

ImuMerger::ImuMerger(const ImuMergerOptions& options)
    : options_(validated(options)), accel_(options.accel_capacity), gyro_(options.gyro_capacity) {}

bool ImuMerger::pushAccel(std::int64_t t_ns, const Eigen::Vector3d& accel_mps2) {
  if (!admit(ImuStream::kAccelerometer, t_ns, accel_mps2)) return false;
  // Gyro samples to come are newer than the oldest waiting one (or the last one seen), so accelerometer
  // samples before that one's bracket are no longer needed.
  const StreamState& gyro_state = streams_[index(ImuStream::kGyroscope)];
  if (!gyro_.empty()) {
    pruneAccelBefore(gyro_.front().t_ns);
  } else if (gyro_state.has_last) {
    pruneAccelBefore(gyro_state.last_t_ns);
  }
  if (accel_.full()) {
    report({.reason = MergeDropReason::kBufferFull, .stream = ImuStream::kAccelerometer, .t_ns = accel_.front().t_ns});
    accel_.popFront();
  }
  accel_.pushBack({t_ns, accel_mps2});
  ++stats_.accel_in;
  return true;
}

bool ImuMerger::pushGyro(std::int64_t t_ns, const Eigen::Vector3d& gyro_rad_s) {
  if (!admit(ImuStream::kGyroscope, t_ns, gyro_rad_s)) return false;
  if (gyro_.full()) {
    report({.reason = MergeDropReason::kBufferFull, .stream = ImuStream::kGyroscope, .t_ns = gyro_.front().t_ns});
    gyro_.popFront();
  }
  gyro_.pushBack({t_ns, gyro_rad_s});
  ++stats_.gyro_in;
  return true;
}

bool ImuMerger::popMerged(ImuSample& out) {
  while (!gyro_.empty()) {
    const TimedVector gyro = gyro_.front();
    pruneAccelBefore(gyro.t_ns);  // now accel_[0] ≤ gyro < accel_[1], or accel_[0] is the only sample
    if (accel_.empty()) return false;
    const TimedVector& before = accel_[0];
    if (before.t_ns > gyro.t_ns) {
      report({.reason = MergeDropReason::kGyroBeforeAccel,
              .stream = ImuStream::kGyroscope,
              .t_ns = gyro.t_ns,
              .reference_ns = before.t_ns});
      gyro_.popFront();
      continue;
    }
    Eigen::Vector3d accel_mps2;
    if (before.t_ns == gyro.t_ns) {
      accel_mps2 = before.value;
    } else {
      if (accel_.size() < 2) return false;  // wait for a sample at or after the gyro's time
      const TimedVector& after = accel_[1];
      const std::int64_t gap_ns = after.t_ns - before.t_ns;
      if (gap_ns > options_.max_accel_gap_ns) {
        report({.reason = MergeDropReason::kAccelGap,
                .stream = ImuStream::kGyroscope,
                .t_ns = gyro.t_ns,
                .reference_ns = gap_ns,
                .limit_ns = options_.max_accel_gap_ns});
        gyro_.popFront();
        continue;
      }
      const double weight = static_cast<double>(gyro.t_ns - before.t_ns) / static_cast<double>(gap_ns);
      accel_mps2 = before.value + weight * (after.value - before.value);
    }
    out.t_ns = gyro.t_ns;
    out.gyro_rad_s = gyro.value;
    out.accel_mps2 = accel_mps2;
    gyro_.popFront();
    ++stats_.merged;
    return true;
  }
  return false;
}

void ImuMerger::reset() {
  accel_.clear();
  gyro_.clear();
  streams_ = {};
  stats_ = {};
  last_problem_ = {};
}

bool ImuMerger::admit(ImuStream stream, std::int64_t t_ns, const Eigen::Vector3d& value) {
  if (!value.allFinite()) {
    report({.reason = MergeDropReason::kNonFiniteValue, .stream = stream, .t_ns = t_ns});
    return false;
  }
  StreamState& state = streams_[index(stream)];
  if (state.has_last && t_ns <= state.last_t_ns) {
    report({.reason = t_ns == state.last_t_ns ? MergeDropReason::kDuplicateTime : MergeDropReason::kOutOfOrderTime,
            .stream = stream,
            .t_ns = t_ns,
            .reference_ns = state.last_t_ns});
    return false;
  }
  state.last_t_ns = t_ns;
  state.has_last = true;
  return true;
}

void ImuMerger::pruneAccelBefore(std::int64_t t_ns) {
  while (accel_.size() >= 2 && accel_[1].t_ns <= t_ns) accel_.popFront();
}

void ImuMerger::report(const MergeProblem& problem) {
  ++stats_.drop_counts[index(problem.stream)][static_cast<std::size_t>(problem.reason)];
  last_problem_ = problem;
}

}  // namespace vifusion::motion
