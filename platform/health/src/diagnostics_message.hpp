#pragma once
// diagnostic_msgs/DiagnosticArray over RuleResults, borrowing their text: storage for every status
// and key/value is fixed here, so publishing allocates nothing of ours.

#include <array>
#include <cstdint>

#include "health_rules.hpp"

namespace vifusion::health {

class DiagnosticsMessage {
 public:
  /// The message for `results` stamped `t_ns` [ns]; valid while this object and `results` live
  /// unchanged.
  const dds::msg::DiagnosticArray& build(std::int64_t t_ns, const std::array<RuleResult, kRuleCount>& results);

 private:
  dds::msg::DiagnosticArray array_{};
  std::array<dds::msg::DiagnosticStatus, kRuleCount> statuses_{};
  std::array<std::array<dds::msg::KeyValue, RuleResult::kMaxValues>, kRuleCount> values_{};
};

}  // namespace vifusion::health
