#include "vifusion/eval/associate.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>
#include <tuple>

#include "vifusion/core/error.hpp"

namespace vifusion::eval {
namespace {

void requireStrictlyIncreasing(std::span<const std::int64_t> stamps_ns, const char* name) {
  for (std::size_t k = 1; k < stamps_ns.size(); ++k) {
    if (stamps_ns[k] <= stamps_ns[k - 1]) {
      throw Error(std::string("associate: ") + name + " stamps must strictly increase; index " +
                  std::to_string(k) + " does not");
    }
  }
}

struct Candidate {
  std::int64_t dt_abs_ns;
  std::int64_t t_a_ns;
  std::int64_t t_b_ns;
  Match match;
};

}  // namespace

std::vector<Match> associate(std::span<const std::int64_t> stamps_a_ns, std::span<const std::int64_t> stamps_b_ns,
                             std::int64_t max_difference_ns, std::int64_t offset_ns) {
  if (max_difference_ns <= 0) throw Error("associate: max_difference must be positive");
  requireStrictlyIncreasing(stamps_a_ns, "first");
  requireStrictlyIncreasing(stamps_b_ns, "second");

  // associate.py forms all |A|·|B| differences; with sorted stamps only a window of B can qualify.
  std::vector<Candidate> candidates;
  for (std::size_t ia = 0; ia < stamps_a_ns.size(); ++ia) {
    const std::int64_t t_a_ns = stamps_a_ns[ia];
    const auto first = std::upper_bound(stamps_b_ns.begin(), stamps_b_ns.end(), t_a_ns - offset_ns - max_difference_ns);
    for (auto it = first; it != stamps_b_ns.end() && *it + offset_ns - t_a_ns < max_difference_ns; ++it) {
      const auto ib = static_cast<std::size_t>(it - stamps_b_ns.begin());
      candidates.push_back({std::llabs(t_a_ns - (*it + offset_ns)), t_a_ns, *it, {ia, ib}});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& l, const Candidate& r) {
    return std::tie(l.dt_abs_ns, l.t_a_ns, l.t_b_ns) < std::tie(r.dt_abs_ns, r.t_a_ns, r.t_b_ns);
  });

  std::vector<bool> used_a(stamps_a_ns.size(), false);
  std::vector<bool> used_b(stamps_b_ns.size(), false);
  std::vector<Match> matches;
  for (const Candidate& candidate : candidates) {
    const Match& m = candidate.match;
    if (used_a[m.index_a] || used_b[m.index_b]) continue;
    used_a[m.index_a] = true;
    used_b[m.index_b] = true;
    matches.push_back(m);
  }
  std::sort(matches.begin(), matches.end(), [](const Match& l, const Match& r) { return l.index_a < r.index_a; });
  return matches;
}

}  // namespace vifusion::eval
