#include "health_rules.hpp"

#include <cstdarg>
#include <cstdio>

#include "vifusion/core/time.hpp"

namespace vifusion::health {
namespace {

// Overruns (or frames without IMU) that increased this recently keep the rule at WARN, so a one-off
// drop is seen [ns].
constexpr std::int64_t kOverrunHoldNs = 2 * kNsPerSecond;

void set(RuleResult& result, Level level, const char* format, ...) __attribute__((format(printf, 3, 4)));
void set(RuleResult& result, Level level, const char* format, ...) {
  result.level = level;
  va_list args;
  va_start(args, format);
  std::vsnprintf(result.message, sizeof(result.message), format, args);
  va_end(args);
}

void value(RuleResult& result, const char* key, const char* format, double number) {
  if (result.value_count >= RuleResult::kMaxValues) return;
  result.keys[result.value_count] = key;
  std::snprintf(result.values[result.value_count], sizeof(result.values[0]), format, number);
  ++result.value_count;
}

}  // namespace

void HealthRules::onStatus(const dds::msg::Status& status, std::int64_t now_ns) {
  const std::uint64_t overruns = status.camera_ring.overruns + status.output_ring.overruns;
  if (have_status_ && overruns > overruns_) overrun_increase_ns_ = now_ns;
  overruns_ = overruns;
  if (have_status_ && status.imu_issue_frames > imu_issues_) imu_issue_increase_ns_ = now_ns;
  imu_issues_ = status.imu_issue_frames;
  const auto since = [&](dds::msg::TrackingState state, std::int64_t& since_ns) {
    if (status.tracking_state != static_cast<std::uint8_t>(state)) {
      since_ns = -1;
    } else if (since_ns < 0) {
      since_ns = now_ns;
    }
  };
  since(dds::msg::TrackingState::Lost, lost_since_ns_);
  since(dds::msg::TrackingState::ImuCarried, carried_since_ns_);
  since(dds::msg::TrackingState::Relocalising, relocalising_since_ns_);
  last_ = status;
  received_ns_ = now_ns;
  have_status_ = true;
}

void HealthRules::judge(std::int64_t now_ns, std::array<RuleResult, kRuleCount>& results) const {
  results = {};
  RuleResult& heartbeat = results[0];
  RuleResult& rate = results[1];
  RuleResult& tracking = results[2];
  RuleResult& overruns = results[3];
  RuleResult& imu = results[4];
  heartbeat.name = "vifusion: heartbeat";
  rate.name = "vifusion: frame rate";
  tracking.name = "vifusion: tracking";
  overruns.name = "vifusion: ring overruns";
  imu.name = "vifusion: imu";
  if (!inertial_) set(imu, Level::Ok, "no IMU in rgbd mode");

  const double age_s = nsToSeconds(now_ns - received_ns_);
  if (!have_status_ || age_s > thresholds_.heartbeat_stale_s) {
    if (have_status_) {
      set(heartbeat, Level::Stale, "no status from vifusiond for %.1f s (stalled, stopped or unreachable)", age_s);
      value(heartbeat, "age_s", "%.2f", age_s);
    } else {
      set(heartbeat, Level::Stale, "no status from vifusiond yet");
    }
    for (RuleResult* rule : {&rate, &tracking, &overruns}) set(*rule, Level::Stale, "no recent status");
    if (inertial_) set(imu, Level::Stale, "no recent status");
    return;
  }
  set(heartbeat, Level::Ok, "status %.2f s ago", age_s);
  value(heartbeat, "age_s", "%.2f", age_s);
  value(heartbeat, "heartbeat", "%.0f", static_cast<double>(last_.heartbeat));

  const double rate_hz = last_.frame_rate_hz;
  value(rate, "frame_rate_hz", "%.1f", rate_hz);
  value(rate, "latency_ms", "%.1f", last_.latency_ms);
  value(rate, "frames_processed", "%.0f", static_cast<double>(last_.frames_processed));
  if (!last_.source_present) {
    set(rate, Level::Error, "camera absent (unplugged): waiting for it to come back; the map is kept");
  } else if (last_.tracking_state == static_cast<std::uint8_t>(dds::msg::TrackingState::Initialising)) {
    set(rate, Level::Ok, "initialising: waiting for the first frame");
  } else if (rate_hz <= 0.0) {
    set(rate, Level::Error, "no frames processed in the last second (source or pipeline stalled)");
  } else if (rate_hz < thresholds_.min_frame_rate_hz) {
    set(rate, Level::Warn, "%.1f frames/s, below %.1f", rate_hz, thresholds_.min_frame_rate_hz);
  } else {
    set(rate, Level::Ok, "%.1f frames/s", rate_hz);
  }

  value(tracking, "lost_frames", "%.0f", static_cast<double>(last_.lost_frames));
  if (lost_since_ns_ >= 0) {
    const double lost_s = nsToSeconds(now_ns - lost_since_ns_);
    value(tracking, "lost_for_s", "%.2f", lost_s);
    // Single lost frames are normal (fast motion, blur); only a long loss is an error.
    set(tracking, lost_s > thresholds_.lost_error_s ? Level::Error : Level::Ok,
        lost_s > thresholds_.lost_error_s ? "tracking lost for %.1f s" : "recovering: lost for %.1f s", lost_s);
  } else if (carried_since_ns_ >= 0) {
    // The pose is dead-reckoned: still published, with a covariance that grows; the map keeps growing.
    const double carried_s = nsToSeconds(now_ns - carried_since_ns_);
    value(tracking, "imu_carried_for_s", "%.2f", carried_s);
    set(tracking, Level::Warn, "IMU-carried for %.1f s: no visual constraint, pose covariance growing", carried_s);
  } else if (relocalising_since_ns_ >= 0) {
    // A loaded map, the camera not located in it yet: no pose is published. Not an error by itself (the robot may
    // start where the map has no keyframe); the rate rule still catches a stalled pipeline.
    const double relocalising_s = nsToSeconds(now_ns - relocalising_since_ns_);
    value(tracking, "relocalising_for_s", "%.2f", relocalising_s);
    set(tracking, Level::Warn, "relocalising into the loaded map for %.1f s: no pose published yet", relocalising_s);
  } else {
    set(tracking, Level::Ok, "tracking");
  }

  value(overruns, "camera_ring_overruns", "%.0f", static_cast<double>(last_.camera_ring.overruns));
  value(overruns, "output_ring_overruns", "%.0f", static_cast<double>(last_.output_ring.overruns));
  if (overrun_increase_ns_ >= 0 && now_ns - overrun_increase_ns_ < kOverrunHoldNs) {
    set(overruns, Level::Warn, "ring overruns increasing: the SLAM thread is slower than the source");
  } else {
    set(overruns, Level::Ok, "no new overruns");
  }

  if (!inertial_) return;
  value(imu, "imu_issue_frames", "%.0f", static_cast<double>(last_.imu_issue_frames));
  if (imu_issue_increase_ns_ >= 0 && now_ns - imu_issue_increase_ns_ < kOverrunHoldNs) {
    set(imu, Level::Warn, "frames tracked without IMU (samples refused: gap, disorder or not covered); see the log");
  } else {
    set(imu, Level::Ok, "IMU samples used on every recent frame");
  }
}

}  // namespace vifusion::health
