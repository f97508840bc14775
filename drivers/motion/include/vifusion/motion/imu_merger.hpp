#pragma once
// Merges the motion module's two IMU streams into vifusion::ImuSample: one sample per gyroscope sample,
// with the accelerometer linearly interpolated to the gyro's time. Inputs are already in SI units and on
// host time (int64 ns after clock mapping); each stream must arrive in time order of its own, the two
// streams in any interleaving.
//
// Why the accelerometer is the interpolated stream: the gyro carries the rotation, the term whose errors
// grow fastest when integrated (a rotation error tilts gravity into the velocity), so its samples pass
// through unaltered; the accelerometer is sampled more densely (≈250 Hz against ≈200 Hz, unconfirmed), so
// the interpolation spans a shorter interval. A straight line between samples Δt apart errs by at most
// Δt²/8·|d²a/dt²|, which for Δt ≤ 4 ms stays below one 12-bit count at ±4 g even at a violent 1000 m/s⁴.
// Interpolation is linear in time, a0 + (t − t0)/(t1 − t0)·(a1 − a0), exact for a linear signal.
//
// Never extrapolates: a gyro sample is emitted only once an accelerometer sample at or after its time
// exists (and one at or before it). Dropped and counted, with a message (describe(MergeProblem)):
//  - a non-finite value; a time equal to (duplicate) or before (out of order) the stream's previous one;
//  - a gyro sample older than every buffered accelerometer sample (it cannot be bracketed);
//  - a gyro sample whose bracketing accelerometer samples are more than max_accel_gap_ns apart (samples
//    lost upstream: a straight line over the gap would invent motion);
//  - the oldest item of a full buffer (the caller stopped popping, or one stream stalled).
//
// No allocation after construction (fixed-capacity buffers). One thread: the IMU driver's.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "vifusion/core/sensor_data.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/motion/fixed_fifo.hpp"
#include "vifusion/motion/problem_text.hpp"

namespace vifusion::motion {

struct ImuMergerOptions {
  /// Accelerometer samples buffered while waiting for gyro samples to bracket [samples], ≥ 2.
  /// 64 at 250 Hz is 256 ms, far more than the two streams' skew (they arrive in the same transfers).
  std::size_t accel_capacity = 64;
  /// Gyro samples waiting for an accelerometer sample at or after their time [samples], ≥ 1.
  std::size_t gyro_capacity = 64;
  /// Largest interval between the two accelerometer samples bracketing a gyro sample [ns], > 0.
  /// 5 nominal periods at 250 Hz: one or two lost samples are bridged, a stall is not.
  std::int64_t max_accel_gap_ns = 20 * kNsPerMillisecond;
  /// @throws vifusion::Error naming the field if a capacity or the gap is out of range.
  void validate() const;
};

enum class ImuStream : std::uint8_t { kAccelerometer, kGyroscope };

enum class MergeDropReason : std::uint8_t {
  kNonFiniteValue,   ///< NaN or infinite axis value
  kDuplicateTime,    ///< same t_ns as the stream's previous sample
  kOutOfOrderTime,   ///< t_ns before the stream's previous sample
  kGyroBeforeAccel,  ///< gyro sample older than the oldest buffered accelerometer sample
  kAccelGap,         ///< bracketing accelerometer samples further apart than max_accel_gap_ns
  kBufferFull,       ///< the stream's buffer was full: its oldest sample was dropped
};
inline constexpr std::size_t kMergeDropReasonCount = static_cast<std::size_t>(MergeDropReason::kBufferFull) + 1;

std::string_view mergeDropReasonName(MergeDropReason reason);

struct MergeProblem {
  MergeDropReason reason = MergeDropReason::kNonFiniteValue;
  ImuStream stream = ImuStream::kGyroscope;  ///< the stream whose sample was dropped
  std::int64_t t_ns = 0;                     ///< time of the dropped sample
  /// What it was checked against: the stream's previous time (duplicate, out of order), the oldest
  /// accelerometer time (kGyroBeforeAccel), the gap [ns] (kAccelGap); unused otherwise.
  std::int64_t reference_ns = 0;
  std::int64_t limit_ns = 0;  ///< max_accel_gap_ns, for kAccelGap
};

/// The problem in words, naming the stream and field, e.g. "gyroscope sample t_ns 5000000 is not after the
/// previous gyroscope sample at 5000000 (duplicate time): dropped". Never allocates.
ProblemText describe(const MergeProblem& problem);

struct ImuMergerStats {
  std::uint64_t accel_in = 0;  ///< accelerometer samples accepted into the buffer
  std::uint64_t gyro_in = 0;   ///< gyro samples accepted into the buffer
  std::uint64_t merged = 0;    ///< ImuSamples emitted
  /// Per stream and reason: samples dropped.
  std::array<std::array<std::uint64_t, kMergeDropReasonCount>, 2> drop_counts{};

  std::uint64_t dropCount(ImuStream stream, MergeDropReason reason) const {
    return drop_counts[static_cast<std::size_t>(stream)][static_cast<std::size_t>(reason)];
  }
  std::uint64_t totalDrops() const;
};

class ImuMerger {
 public:
  /// @throws vifusion::Error if options.validate() does.
  explicit ImuMerger(const ImuMergerOptions& options = {});

  /// Adds an accelerometer sample (specific force in S [m/s²]) at host time t_ns; false if dropped.
  bool pushAccel(std::int64_t t_ns, const Eigen::Vector3d& accel_mps2);
  /// Adds a gyro sample (angular rate of S [rad/s]) at host time t_ns; false if dropped.
  bool pushGyro(std::int64_t t_ns, const Eigen::Vector3d& gyro_rad_s);

  /// The next merged sample, oldest first, once the accelerometer brackets its time; false when none is
  /// ready yet. Call until false after each push (gyro samples that cannot be merged are dropped here).
  bool popMerged(ImuSample& out);

  const ImuMergerStats& stats() const { return stats_; }
  /// The most recent problem; meaningful once stats().totalDrops() > 0.
  const MergeProblem& lastProblem() const { return last_problem_; }

  /// Forgets buffered samples, times and statistics (e.g. after the device was re-opened).
  void reset();

 private:
  struct TimedVector {
    std::int64_t t_ns = 0;
    Eigen::Vector3d value = Eigen::Vector3d::Zero();
  };
  struct StreamState {
    std::int64_t last_t_ns = 0;
    bool has_last = false;
  };

  bool admit(ImuStream stream, std::int64_t t_ns, const Eigen::Vector3d& value);
  /// Drops accelerometer samples no future gyro sample can need: all but the newest at or before t_ns.
  void pruneAccelBefore(std::int64_t t_ns);
  void report(const MergeProblem& problem);

  ImuMergerOptions options_;
  FixedFifo<TimedVector> accel_;
  FixedFifo<TimedVector> gyro_;
  std::array<StreamState, 2> streams_{};
  ImuMergerStats stats_;
  MergeProblem last_problem_;
};

}  // namespace vifusion::motion
