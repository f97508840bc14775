#include "vifusion/synccheck/sync_report.hpp"

namespace vifusion::synccheck {

const StreamStats* SyncReport::stream(std::string_view name) const {
  for (const StreamStats& s : streams) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::vector<std::string> SyncReport::failedChecks() const {
  std::vector<std::string> names;
  for (const CheckResult& check : checks) {
    if (!check.passed) names.push_back(check.name);
  }
  return names;
}

}  // namespace vifusion::synccheck
