#pragma once
// What vifusiond's threads share (DESIGN.md §1): the camera ring (reader → SLAM), the output ring
// (SLAM → publisher), the periodic map hand-off and a few atomic counters. No locks on the
// per-frame path; the map hand-off takes a mutex every map_publish_period_s.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <vector>

#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/core/spsc_ring.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/map/surfel.hpp"
#include "vifusion/slam/tracking_state.hpp"

namespace vifusion::daemon {

/// One camera ring slot: the frame, when the reader handed it over and its sensor time, both on the host's
/// CLOCK_MONOTONIC [ns]. Sensor time: a live camera's stamp (mid-exposure, already on the host clock), a paced
/// replay's schedule (when the frame would have been exposed), an unpaced replay's hand-over (it has none).
struct FrameSlot {
  RgbdFrame frame;
  std::int64_t read_ns = 0;
  std::int64_t sensor_ns = 0;
};

/// One output ring slot: small and fixed-size (no pointers, no heap), so the hand-off copies a few
/// hundred bytes. The estimator's state rides along in the inertial modes.
struct PoseResult {
  std::int64_t t_ns = 0;       ///< frame stamp (the source's time base) [ns]
  std::int64_t read_ns = 0;    ///< host time the reader handed the frame over [ns]
  std::int64_t sensor_ns = 0;  ///< FrameSlot::sensor_ns: the latency's start [ns]
  std::int64_t done_ns = 0;    ///< host time the SLAM thread finished it [ns]
  SE3d T_W_C;                  ///< camera pose in the map world
  SE3d T_W_O;                  ///< map → odom (slam::FrameResult::T_W_O): moves only at a loop closure
  slam::TrackingState tracking = slam::TrackingState::kTracked;  ///< slam::FrameResult::tracking
  /// A loaded map's camera not located yet (slam::FrameResult::relocalising): no pose, only the status says so.
  bool relocalising = false;
  /// Inertial modes: `state` and `state_variance` hold the estimator's state at this frame
  /// (slam::FrameResult::inertial); false in rgbd mode and while the estimator waits to start.
  bool inertial = false;
  bool imu_issue = false;                        ///< this frame's IMU samples were refused (tracked RGB-D only)
  std::uint32_t surfels = 0;                     ///< surfels in the map after this frame
  std::uint64_t frame_number = 0;                ///< processed frames so far, this one included
  NavState state;                                ///< slam::FrameResult::state (when `inertial`)
  Vector18d state_variance = Vector18d::Zero();  ///< its marginal variances in δx, 0 = held (when `inertial`)
};
// Eigen's types are not formally trivially copyable, but hold their coefficients inline: no member
// owns heap memory, so copying a slot is copying its bytes' worth of doubles.
static_assert(sizeof(PoseResult) <= 512, "the output ring slot stays a small fixed-size value");

/// The periodic map snapshot, exported on the SLAM thread (which owns the GPU) and converted and
/// published on the publisher thread. Swapping vectors keeps both sides' capacity: no allocation
/// once the map stopped growing.
class MapHandoff {
 public:
  void offer(std::vector<map::Surfel>& surfels, std::int64_t t_ns) {
    const std::lock_guard lock(mutex_);
    pending_.swap(surfels);
    t_ns_ = t_ns;
    fresh_ = true;
  }
  bool take(std::vector<map::Surfel>& surfels, std::int64_t& t_ns) {
    const std::lock_guard lock(mutex_);
    if (!fresh_) return false;
    surfels.swap(pending_);
    t_ns = t_ns_;
    fresh_ = false;
    return true;
  }

 private:
  std::mutex mutex_;
  std::vector<map::Surfel> pending_;
  std::int64_t t_ns_ = 0;
  bool fresh_ = false;
};

/// Exit codes a thread reports; the first non-zero one wins.
struct SharedState {
  SharedState(std::size_t frame_capacity, const FrameSlot& prototype, std::size_t output_capacity)
      : frames(frame_capacity, prototype), results(output_capacity) {}

  SpscRing<FrameSlot> frames;
  SpscRing<PoseResult> results;
  MapHandoff map;

  std::atomic<bool> stop{false};         ///< SIGTERM/SIGINT: finish the current frame and shut down
  std::atomic<bool> source_done{false};  ///< the reader delivered its last frame (or failed)
  std::atomic<bool> slam_done{false};    ///< the SLAM thread wrote its files and ended
  std::atomic<std::uint64_t> frames_processed{0};
  std::atomic<std::uint64_t> lost_frames{0};
  std::atomic<std::uint64_t> imu_issue_frames{0};    ///< inertial modes: frames whose IMU samples were refused
  std::atomic<std::uint64_t> imu_carried_frames{0};  ///< inertial modes: frames the IMU carried
  std::atomic<std::uint64_t> closures_accepted{0};   ///< loop closures that deformed the map
  std::atomic<std::uint64_t> closures_refused{0};    ///< loop-closure attempts a test refused
  std::atomic<std::uint64_t> closures_agreed{0};     ///< closures within their noise: reactivation only
  std::atomic<std::uint64_t> relocalisations{0};     ///< lost frames tracked again from a recognised place
  /// Frames the SLAM thread skipped as stale, a newer one waiting (SlamWorkerOptions::take_newest)
  std::atomic<std::uint64_t> frames_skipped{0};
  /// Recorded frames the reader could not read (a corrupt image, a damaged message) and passed over
  std::atomic<std::uint64_t> frames_unreadable{0};
  /// Recorded IMU rows or messages the reader left out (DatasetReader::skippedImuRows), set at start
  std::atomic<std::uint64_t> imu_samples_unreadable{0};
  // The live camera, as the main thread last read it from the source (recorded sources: present, zeros).
  std::atomic<bool> source_present{true};        ///< false while the camera is unplugged
  std::atomic<std::uint64_t> source_reopens{0};  ///< re-opens after an unplug
  std::atomic<std::int64_t> clock_offset_ns{0};  ///< host − device clock of the IMU [ns]
  std::atomic<double> clock_skew_ppm{0.0};       ///< host rate / device rate − 1 [ppm]
  std::atomic<std::uint64_t> imu_ring_fill{0};   ///< samples waiting in the motion module's ring
  std::atomic<std::uint64_t> imu_ring_capacity{0};
  std::atomic<std::uint64_t> imu_ring_overruns{0};
  std::atomic<std::uint64_t> kernel_timestamp_frames{0};  ///< frames stamped by the kernel, not the IMU's event
  std::atomic<double> sync_edge_rate_hz{0.0};             ///< the sync line's edge rate [Hz] (0 without one)
  std::atomic<std::uint64_t> sync_edges{0};               ///< its edges so far
  // The map file (config map_file; map_saver.hpp).
  std::atomic<bool> relocalising{false};                ///< a loaded map's camera is not located yet
  std::atomic<std::uint64_t> map_save_requested{0};     ///< newest rt/vifusion/map_save_request's id (main thread)
  std::atomic<std::uint64_t> map_save_request_done{0};  ///< id of the last request whose save ended
  std::atomic<std::uint64_t> map_saves{0};              ///< map files written
  std::atomic<std::uint64_t> map_save_failures{0};      ///< saves that failed (the file unchanged)
  std::atomic<std::uint64_t> map_file_bytes{0};         ///< the last map file's size [bytes]
  std::atomic<double> map_capture_ms{0.0};              ///< the last save's hold on the SLAM thread [ms]
  std::atomic<double> map_write_ms{0.0};                ///< the last save's write on the saver thread [ms]
  std::atomic<int> exit_code{0};

  void fail(int code) {
    int expected = 0;
    exit_code.compare_exchange_strong(expected, code);
    stop = true;
  }
};

}  // namespace vifusion::daemon
