#include "vifusion/core/binomial_test.hpp"

#include <algorithm>
#include <cmath>

namespace vifusion {
namespace {

/// Terms smaller than this share of the running sum end a tail's summation (below double's resolution of it).
constexpr double kNegligibleTermShare = 1e-17;

/// log P(X = i) for X ~ Binomial(n, p), 0 < p < 1.
double logPmf(std::uint64_t i, std::uint64_t n, double p) {
  const double ni = static_cast<double>(n), ii = static_cast<double>(i);
  return std::lgamma(ni + 1.0) - std::lgamma(ii + 1.0) - std::lgamma(ni - ii + 1.0) + ii * std::log(p) +
         (ni - ii) * std::log1p(-p);
}

/// Σ P(X = j) over j from `first` away from the mode (downward when `down`, else upward), first being on the
/// far side of the mode so that the terms only shrink: each term is the previous one times the pmf ratio.
double tailFrom(std::uint64_t first, std::uint64_t n, double p, bool down) {
  const double odds = p / (1.0 - p);
  double term = std::exp(logPmf(first, n, p));
  double sum = term;
  std::uint64_t i = first;
  while (down ? i > 0 : i < n) {
    const double ni = static_cast<double>(n), ii = static_cast<double>(i);
    term *= down ? ii / ((ni - ii + 1.0) * odds) : (ni - ii) / (ii + 1.0) * odds;
    i = down ? i - 1 : i + 1;
    sum += term;
    if (term < kNegligibleTermShare * sum) break;
  }
  return sum;
}

}  // namespace

double binomialLowerTail(std::uint64_t k, std::uint64_t n, double p) {
  if (k >= n || p <= 0.0) return 1.0;
  if (p >= 1.0) return 0.0;
  // Sum whichever tail lies beyond the mean, where the terms fall off monotonically.
  if (static_cast<double>(k) < static_cast<double>(n) * p) return std::min(1.0, tailFrom(k, n, p, true));
  return std::clamp(1.0 - tailFrom(k + 1, n, p, false), 0.0, 1.0);
}

bool shareBelow(std::uint64_t k, std::uint64_t n, double p, double alpha) {
  if (n == 0) return false;
  return binomialLowerTail(k, n, p) < alpha;
}

}  // namespace vifusion
