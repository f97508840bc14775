#pragma once
// Faults injected into a recorded source on replay (`vifusion run --inject`, vifusiond's `inject` key), so each
// fault a robot meets can be reproduced and its documented outcome tested (tests/cli, README "Bad input and
// faults"). A plan is a comma-separated list of NAME@FRAME[:VALUE], FRAME being the 0-based index of a frame of
// the source as recorded:
//   imu-gap@K[:S]        the IMU samples of the S s (default 0.1) from the middle of frames K−1..K are removed
//   imu-duplicate@K      the first IMU sample from that middle on is repeated (same time, same values)
//   imu-reorder@K        that sample and the next one swap places
//   imu-nan@K, imu-inf@K that sample's acceleration x becomes NaN, or its angular rate z +∞
//   frame-drop@K[:N]     frames K … K+N−1 (default N = 1) never arrive
//   frame-duplicate@K    frame K arrives twice
//   frame-blank@K[:N]    frames K … K+N−1 (default N = 1) arrive at their times with no depth and black colour: a
//                        covered lens, the lights out (the IMU goes on)
//   time-backwards@K[:S] frame K's time goes back S s (default 0.1, earlier than the frame before it)
//   clock-jump@K:±S      the source's clock jumps by ±S s between frames K−1 and K: every later frame and IMU sample
//   stall@K[:S]          the source delivers nothing for S s (default 2) before frame K
//   device-lost@K        the GPU is lost before frame K is processed (VK_ERROR_DEVICE_LOST at the next submit);
//                        this one is for the caller, which owns the GPU (gpu::GpuContext::simulateDeviceLoss)
// Ground truth is left as recorded: it comes from another clock (motion capture, the simulator).

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vifusion/datasets/dataset_reader.hpp"

namespace vifusion::datasets {

enum class FaultKind {
  kImuGap,
  kImuDuplicate,
  kImuReorder,
  kImuNan,
  kImuInf,
  kFrameDrop,
  kFrameDuplicate,
  kFrameBlank,
  kTimeBackwards,
  kClockJump,
  kStall,
  kDeviceLost,
};

/// The IMU faults and the clock jump happen between frames K−1 and K (at the middle of their recorded times).
constexpr bool happensBetweenFrames(FaultKind kind) {
  return kind == FaultKind::kImuGap || kind == FaultKind::kImuDuplicate || kind == FaultKind::kImuReorder ||
         kind == FaultKind::kImuNan || kind == FaultKind::kImuInf || kind == FaultKind::kClockJump;
}

struct Fault {
  FaultKind kind = FaultKind::kFrameDrop;
  std::size_t frame = 0;  ///< K: the source frame it happens at (0-based, in recorded order)
  /// [s] for imu-gap, time-backwards, clock-jump (signed) and stall; a frame count for frame-drop and frame-blank;
  /// unused otherwise.
  double value = 0.0;
};

struct FaultPlan {
  std::vector<Fault> faults;

  bool empty() const { return faults.empty(); }
  /// The frame before which the GPU is lost, if the plan loses it.
  std::optional<std::size_t> deviceLostFrame() const;
  /// The plan as parseFaultPlan reads it (defaults written out), for logs and reports.
  std::string describe() const;
};

/// Reads a plan (grammar above). `where` names its origin in errors ("--inject", "vifusiond.yaml: inject").
/// @throws vifusion::Error naming `where`, the entry and what is wrong: an unknown fault (listing the known
/// ones), a missing or non-numeric frame, a value where the fault takes none, a value out of range.
FaultPlan parseFaultPlan(const std::string& spec, const std::string& where);

/// `recording` with the plan's source faults applied (device-lost is left to the caller). The faulty stream is
/// what the source would have delivered: imu() may then break its strictly-increasing promise, as a faulty
/// driver would; the pipeline's own checks must catch it.
/// @throws vifusion::Error when the recording is live, lists no frame times (IMU faults and clock jumps need
/// them), or a fault's frame is beyond its last frame.
std::unique_ptr<DatasetReader> withFaults(std::unique_ptr<DatasetReader> recording, const FaultPlan& plan);

/// `recording` with its time order kept, whatever it delivers (a faulty driver, injected faults): nextFrame() throws
/// a vifusion::Error naming a frame whose time is not after the last frame delivered, having moved past it, so
/// callers skip and count it like an unreadable frame (a duplicated frame, time going backwards, the first second
/// after the clock jumped back); an IMU sample whose time is not after the last one kept, or with a reading that is
/// not finite, is left out of imu() and named in skippedImuRows() like an unreadable row (the estimator sees the
/// hole as a gap). A reader of a well-formed recording passes through unchanged. Copies the IMU stream once.
/// @throws vifusion::Error for a live source.
std::unique_ptr<DatasetReader> withIncreasingTimes(std::unique_ptr<DatasetReader> recording);

}  // namespace vifusion::datasets
