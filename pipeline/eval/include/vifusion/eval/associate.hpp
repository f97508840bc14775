#pragma once
// Timestamp association with the semantics of the TUM benchmark's associate.py.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "vifusion/core/time.hpp"

namespace vifusion::eval {

struct Match {
  std::size_t index_a = 0;  ///< Index into the first stamp list.
  std::size_t index_b = 0;  ///< Index into the second stamp list.
};

/// Pairs stamps of two strictly increasing lists as associate.py does: every (a, b) with
/// |t_a − (t_b + offset_ns)| < max_difference_ns is a candidate; candidates are taken greedily by
/// increasing |Δt| (ties broken by t_a, then t_b, as Python's tuple sort does), each stamp used at
/// most once. The result is sorted by t_a (and therefore by t_b too: greedy nearest matching of two
/// increasing sequences never crosses). An empty result is valid (no overlap); callers decide whether
/// that is an error.
/// @throws vifusion::Error if a list is not strictly increasing or max_difference_ns <= 0.
std::vector<Match> associate(std::span<const std::int64_t> stamps_a_ns,
                             std::span<const std::int64_t> stamps_b_ns,
                             std::int64_t max_difference_ns = 20 * kNsPerMillisecond,
                             std::int64_t offset_ns = 0);

}  // namespace vifusion::eval
