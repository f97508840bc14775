#pragma once
// vifusion-health's rules: from the latest rt/vifusion/status (and when it arrived) to one verdict
// per rule, with diagnostic_msgs levels. Pure logic, no DDS: the caller feeds statuses and the clock.

#include <array>
#include <cstdint>

#include "vifusion/config/daemon_config.hpp"
#include "vifusion/dds/messages.hpp"

namespace vifusion::health {

/// diagnostic_msgs/DiagnosticStatus levels.
enum class Level : std::uint8_t { Ok = 0, Warn = 1, Error = 2, Stale = 3 };

struct RuleResult {
  static constexpr int kMaxValues = 3;
  Level level = Level::Ok;
  const char* name = "";  ///< "vifusion: heartbeat", static text
  char message[128] = {};
  const char* keys[kMaxValues] = {};
  char values[kMaxValues][32] = {};
  int value_count = 0;
};

inline constexpr int kRuleCount = 5;  ///< heartbeat, frame rate, tracking, ring overruns, IMU

class HealthRules {
 public:
  /// `inertial`: vifusiond runs an inertial mode (rgbdi, gyro), so the IMU rule watches the frames
  /// whose IMU samples were refused; in rgbd mode that rule is always OK.
  HealthRules(const config::HealthConfig& thresholds, bool inertial) : thresholds_(thresholds), inertial_(inertial) {}

  /// A status message arrived at host time `now_ns` [ns].
  void onStatus(const dds::msg::Status& status, std::int64_t now_ns);
  /// Judges every rule at `now_ns` into `results` (no allocation).
  void judge(std::int64_t now_ns, std::array<RuleResult, kRuleCount>& results) const;

 private:
  config::HealthConfig thresholds_;
  bool inertial_ = false;
  bool have_status_ = false;
  dds::msg::Status last_{};
  std::int64_t received_ns_ = 0;
  std::int64_t lost_since_ns_ = -1;          ///< host time tracking was first seen lost; −1: not lost
  std::int64_t carried_since_ns_ = -1;       ///< host time the IMU was first seen carrying the pose; −1: not
  std::int64_t relocalising_since_ns_ = -1;  ///< host time relocalising was first seen; −1: not relocalising
  std::uint64_t overruns_ = 0;               ///< camera + output ring overruns in the last status
  std::int64_t overrun_increase_ns_ = -1;    ///< host time they last increased; −1: never
  std::uint64_t imu_issues_ = 0;             ///< frames with refused IMU samples in the last status
  std::int64_t imu_issue_increase_ns_ = -1;  ///< host time they last increased; −1: never
};

}  // namespace vifusion::health
