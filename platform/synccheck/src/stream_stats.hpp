#pragma once
// Offset, drift and jitter of one stream pair from its (time, a − b) samples.

#include <cstdint>
#include <string>
#include <vector>

#include "vifusion/synccheck/sync_report.hpp"

namespace vifusion::synccheck {

/// `t_ns` increasing or not (delivery order); `offset_ns` the same length. Fewer than two samples leave
/// the line's quantities NaN; none leaves everything NaN.
StreamStats measureStream(std::string name, std::vector<std::int64_t> t_ns, std::vector<double> offset_ns);

}  // namespace vifusion::synccheck
