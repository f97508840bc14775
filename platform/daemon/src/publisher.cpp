#include "vifusion/daemon/publisher.hpp"

#include <thread>

#include "vifusion/core/time.hpp"
#include "vifusion/core/version.hpp"
#include "vifusion/service/log.hpp"

namespace vifusion::daemon {
namespace {

dds::msg::RingCounters counters(std::size_t fill, std::size_t capacity, std::uint64_t overruns) {
  return {static_cast<std::uint32_t>(fill), static_cast<std::uint32_t>(capacity), overruns};
}

}  // namespace

Publisher::Publisher(const dds::Participant& participant, const config::DaemonConfig& config,
                     float map_confidence_threshold, const SE3d& T_S_C, SharedState& state)
    : config_(config),
      map_confidence_threshold_(map_confidence_threshold),
      T_S_C_(T_S_C),
      velocity_estimated_(config.mode == "rgbdi"),
      state_(state),
      odometry_(participant, dds::topics::kOdometry),
      pose_(participant, dds::topics::kPose),
      tf_(participant, dds::topics::kTf),
      imu_state_(participant, dds::topics::kImuState),
      status_(participant, dds::topics::kStatus),
      map_(participant, dds::topics::kMap) {}

void Publisher::run() {
  const std::int64_t status_period_ns = secondsToNs(config_.status_period_s);
  std::int64_t next_status_ns = monotonicNowNs();
  PoseResult result;
  try {
    for (;;) {
      const bool finished = state_.slam_done.load();  // read before draining: nothing arrives after it
      while (state_.results.tryPop(result)) publishPose(result);
      std::int64_t map_t_ns = 0;
      if (state_.map.take(surfels_, map_t_ns)) publishMap(map_t_ns);
      const std::int64_t now_ns = monotonicNowNs();
      if (now_ns >= next_status_ns || finished) {
        publishStatus(now_ns);
        next_status_ns = now_ns + status_period_ns;
      }
      if (finished) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  } catch (const std::exception& error) {
    service::logLine(service::LogLevel::Error, "publishing failed: %s", error.what());
    state_.fail(config::kExitDds);
  }
}

void Publisher::publishPose(const PoseResult& result) {
  relocalising_ = result.relocalising;
  if (result.relocalising) {  // no pose in the loaded map yet: only the status tells
    relocalising_surfels_ = result.surfels;
    return;
  }
  const char* world = config_.dds.world_frame.c_str();
  const char* odom = config_.dds.odom_frame.c_str();
  const char* camera = config_.dds.camera_frame.c_str();
  // Odometry is differentiated and published in O, where a loop closure does not make the camera jump.
  const SE3d T_O_W = result.T_W_O.inverse();
  const SE3d T_O_C = T_O_W * result.T_W_C;
  Eigen::Vector3d v_O_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d omega_C_radps = Eigen::Vector3d::Zero();
  if (have_last_ && result.t_ns > last_.t_ns) {
    const double dt_s = nsToSeconds(result.t_ns - last_.t_ns);
    v_O_mps = (T_O_C.translation() - last_T_O_C_.translation()) / dt_s;
    // Rotation of the previous camera to this one, expressed in this camera: R_Cprev_C.
    const Eigen::AngleAxisd delta(last_T_O_C_.quaternion().conjugate() * T_O_C.quaternion());
    omega_C_radps = T_O_C.quaternion().conjugate() * last_T_O_C_.quaternion() * (delta.axis() * delta.angle() / dt_s);
  }
  if (!result.inertial) {
    // Placeholder covariance (see publisher.hpp): (1 cm)², (0.01 rad)²; a lost frame's pose is a guess.
    constexpr double kPlaceholderVariance = 1e-4;   // [m², rad²]
    constexpr double kNoInformationVariance = 1e6;  // [m², rad²]
    const Matrix6d pose_covariance =
        Vector6d::Constant(result.tracking == slam::TrackingState::kLost ? kNoInformationVariance
                                                                         : kPlaceholderVariance)
            .asDiagonal();
    odometry_.write(
        dds::makeOdometry(result.t_ns, odom, camera, T_O_C, v_O_mps, omega_C_radps, pose_covariance, Matrix6d::Zero()));
  } else if (velocity_estimated_) {
    odometry_.write(dds::makeInertialOdometry(result.t_ns, odom, camera, T_O_W, result.state, result.state_variance,
                                              omega_C_radps, T_S_C_));
  } else {
    const Matrix6d pose_covariance =
        dds::rotatePoseCovariance(dds::odometryPoseCovariance(result.state_variance), T_O_W.rotationMatrix());
    odometry_.write(
        dds::makeOdometry(result.t_ns, odom, camera, T_O_C, v_O_mps, omega_C_radps, pose_covariance, Matrix6d::Zero()));
  }
  if (result.inertial) {
    imu_state_.write(dds::makeImuStateFromVariances(result.t_ns, world, result.state, result.state_variance));
  }
  pose_.write(dds::makePoseStamped(result.t_ns, world, result.T_W_C));
  std::array<dds::msg::TransformStamped, 2> transforms = {
      dds::makeTransformStamped(result.t_ns, world, odom, result.T_W_O),
      dds::makeTransformStamped(result.t_ns, odom, camera, T_O_C)};
  tf_.write(dds::makeTfMessage(transforms));
  latency_.add(static_cast<float>(nsToSeconds(monotonicNowNs() - result.sensor_ns) * 1e3));
  last_ = result;
  last_T_O_C_ = T_O_C;
  have_last_ = true;
}

void Publisher::publishStatus(std::int64_t now_ns) {
  const std::uint64_t frames = state_.frames_processed.load();
  rate_samples_[rate_count_ % kRateWindow] = {now_ns, frames};
  ++rate_count_;
  // Oldest sample at most ~1 s old (or the oldest kept): the processed-frame rate over that window.
  float rate_hz = 0.0f;
  for (std::size_t back = std::min(rate_count_, kRateWindow) - 1; back > 0; --back) {
    const auto& [t_ns, n] = rate_samples_[(rate_count_ - 1 - back) % kRateWindow];
    if (now_ns - t_ns <= kNsPerSecond + kNsPerSecond / 10 || back == 1) {
      rate_hz = static_cast<float>(static_cast<double>(frames - n) / nsToSeconds(now_ns - t_ns));
      break;
    }
  }
  dds::msg::Status status{};
  status.header = dds::makeHeader(last_.t_ns, config_.dds.camera_frame.c_str());
  status.heartbeat = ++heartbeat_;
  status.frame_rate_hz = rate_hz;
  const LatencySummary latency = latency_.summary();
  status.latency_ms = latency.last_ms;
  status.latency_p50_ms = latency.p50_ms;
  status.latency_p99_ms = latency.p99_ms;
  status.latency_max_ms = latency.max_ms;
  status.camera_ring = counters(state_.frames.size(), state_.frames.capacity(), state_.frames.overruns());
  // The live camera's motion-module ring; recorded sources have none (they hand over their whole stream).
  status.imu_ring =
      counters(state_.imu_ring_fill.load(), state_.imu_ring_capacity.load(), state_.imu_ring_overruns.load());
  status.output_ring = counters(state_.results.size(), state_.results.capacity(), state_.results.overruns());
  auto tracking = dds::msg::TrackingState::Initialising;
  if (relocalising_) {
    tracking = dds::msg::TrackingState::Relocalising;
  } else if (have_last_) {
    switch (last_.tracking) {
      case slam::TrackingState::kTracked:
        tracking = dds::msg::TrackingState::Ok;
        break;
      case slam::TrackingState::kImuCarried:
        tracking = dds::msg::TrackingState::ImuCarried;
        break;
      case slam::TrackingState::kLost:
        tracking = dds::msg::TrackingState::Lost;
        break;
    }
  }
  status.tracking_state = static_cast<std::uint8_t>(tracking);
  status.surfel_count = relocalising_ ? relocalising_surfels_ : last_.surfels;
  status.frames_processed = frames;
  status.frames_skipped = state_.frames_skipped.load();
  status.frames_unreadable = state_.frames_unreadable.load();
  status.imu_samples_unreadable = state_.imu_samples_unreadable.load();
  status.lost_frames = state_.lost_frames.load();
  status.imu_issue_frames = state_.imu_issue_frames.load();
  status.imu_carried_frames = state_.imu_carried_frames.load();
  status.closures_accepted = state_.closures_accepted.load();
  status.closures_refused = state_.closures_refused.load();
  status.closures_agreed = state_.closures_agreed.load();
  status.relocalisations = state_.relocalisations.load();
  status.source_present = state_.source_present.load();
  status.source_reopens = state_.source_reopens.load();
  status.clock_offset_ns = state_.clock_offset_ns.load();
  status.clock_skew_ppm = static_cast<float>(state_.clock_skew_ppm.load());
  status.sync_edge_rate_hz = static_cast<float>(state_.sync_edge_rate_hz.load());
  status.sync_edges = state_.sync_edges.load();
  status.map_saves = state_.map_saves.load();
  status.map_save_failures = state_.map_save_failures.load();
  status.map_save_request_done = state_.map_save_request_done.load();
  status.map_file_bytes = state_.map_file_bytes.load();
  status.map_capture_ms = static_cast<float>(state_.map_capture_ms.load());
  status.map_write_ms = static_cast<float>(state_.map_write_ms.load());
  status.vifusion_version = const_cast<char*>(versionString());  // the C type's string is char*; only read
  status_.write(status);
}

void Publisher::publishMap(std::int64_t t_ns) {
  points_.clear();
  for (const map::Surfel& surfel : surfels_) {
    if (surfel.position_confidence.w() < map_confidence_threshold_) continue;  // stable surfels, as map.ply
    const std::uint32_t packed = surfel.packedColour();                        // r | g << 8 | b << 16
    dds::MapPoint point;
    point.x = surfel.position_confidence.x();
    point.y = surfel.position_confidence.y();
    point.z = surfel.position_confidence.z();
    point.rgb = dds::MapPoint::packRgb(packed & 0xff, (packed >> 8) & 0xff, (packed >> 16) & 0xff);
    point.normal_x = surfel.normal_radius.x();
    point.normal_y = surfel.normal_radius.y();
    point.normal_z = surfel.normal_radius.z();
    point.radius = surfel.normal_radius.w();
    point.confidence = surfel.position_confidence.w();
    points_.push_back(point);
  }
  map_.write(dds::makePointCloud2(t_ns, config_.dds.world_frame.c_str(), points_));
}

}  // namespace vifusion::daemon
