#include "diagnostics_message.hpp"

#include "vifusion/dds/conversions.hpp"

namespace vifusion::health {
namespace {

const char kEmpty[] = "";
char kHardwareId[] = "vifusiond";

}  // namespace

const dds::msg::DiagnosticArray& DiagnosticsMessage::build(std::int64_t t_ns,
                                                            const std::array<RuleResult, kRuleCount>& results) {
  for (int i = 0; i < kRuleCount; ++i) {
    const RuleResult& result = results[i];
    dds::msg::DiagnosticStatus& status = statuses_[i];
    status.level = static_cast<std::uint8_t>(result.level);
    // Cyclone only reads these while serialising; the IDL's char* is not const.
    status.name = const_cast<char*>(result.name);
    status.message = const_cast<char*>(result.message);
    status.hardware_id = kHardwareId;
    for (int v = 0; v < result.value_count; ++v) {
      values_[i][v].key = const_cast<char*>(result.keys[v]);
      values_[i][v].value = const_cast<char*>(result.values[v]);
    }
    status.values._maximum = status.values._length = static_cast<std::uint32_t>(result.value_count);
    status.values._buffer = values_[i].data();
    status.values._release = false;
  }
  array_.header = dds::makeHeader(t_ns, kEmpty);
  array_.status._maximum = array_.status._length = kRuleCount;
  array_.status._buffer = statuses_.data();
  array_.status._release = false;
  return array_;
}

}  // namespace vifusion::health
