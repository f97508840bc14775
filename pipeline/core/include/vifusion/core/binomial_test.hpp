#pragma once
// Whether a count of successes shows, beyond chance, that their share is below a bound.
//
// A health test "at least a share p of n trials pass" read as a hard ratio k < p·n judges a handful of trials
// as firmly as a million: one ICP candidate that fails makes a frame lost while the same frame with none is
// not judged at all. Read as a one-sided binomial test it weighs the evidence: the trials show the share below
// p when a share of exactly p would give k or fewer successes with probability below α,
// P(X ≤ k | n, p) < α. For large n the bound approaches the ratio (k < p·n − z_α·√(n·p·(1 − p))), for a few
// trials nothing is shown either way.

#include <cstdint>

namespace vifusion {

/// P(X ≤ k) for X ~ Binomial(n, p), p in [0, 1]; 1 when k ≥ n. Summed in log space (no underflow for large n).
double binomialLowerTail(std::uint64_t k, std::uint64_t n, double p);

/// True when k successes of n trials show their share below p at significance α, i.e. P(X ≤ k | n, p) < α.
/// Never for n = 0.
bool shareBelow(std::uint64_t k, std::uint64_t n, double p, double alpha);

}  // namespace vifusion
