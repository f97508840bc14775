#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "vifusion/core/binomial_test.hpp"

namespace vifusion {
namespace {

// P(X ≤ k) by summing every term of the pmf from its recurrence in long double: the reference for small n.
long double bruteLowerTail(std::uint64_t k, std::uint64_t n, long double p) {
  long double term = std::pow(1.0L - p, static_cast<long double>(n));
  long double sum = 0.0L;
  for (std::uint64_t i = 0; i <= k; ++i) {
    sum += term;
    term *= static_cast<long double>(n - i) / static_cast<long double>(i + 1) * p / (1.0L - p);
  }
  return sum;
}

TEST(BinomialTest, LowerTailMatchesTheSumOfTheTerms) {
  EXPECT_NEAR(binomialLowerTail(2, 10, 0.5), 56.0 / 1024.0, 1e-15);
  EXPECT_NEAR(binomialLowerTail(0, 1, 0.2), 0.8, 1e-15);
  for (const double p : {0.01, 0.2, 0.5, 0.93}) {
    for (std::uint64_t k = 0; k <= 300; ++k) {
      const double reference = static_cast<double>(bruteLowerTail(k, 300, p));
      EXPECT_NEAR(binomialLowerTail(k, 300, p), reference, 1e-12 + 1e-9 * reference) << "k " << k << " p " << p;
    }
  }
}

TEST(BinomialTest, LowerTailOfAFullFrameMatchesEveryTermSummed) {
  // 300 000 trials (a 640 × 480 frame), 1.5 σ and 4.5 σ below the mean, against the sum of every term from
  // log-gamma (no recurrence, no early stop). The normal approximation would be 4 % off at 4.5 σ.
  const std::uint64_t n = 300000;
  const double p = 0.2, mean = static_cast<double>(n) * p, sigma = std::sqrt(mean * (1.0 - p));
  for (const double z : {1.5, 4.5}) {
    const auto k = static_cast<std::uint64_t>(mean - z * sigma);
    double reference = 0.0;
    for (std::uint64_t i = 0; i <= k; ++i) {
      const double ni = static_cast<double>(n), ii = static_cast<double>(i);
      reference += std::exp(std::lgamma(ni + 1.0) - std::lgamma(ii + 1.0) - std::lgamma(ni - ii + 1.0) +
                            ii * std::log(p) + (ni - ii) * std::log1p(-p));
    }
    EXPECT_NEAR(binomialLowerTail(k, n, p), reference, 1e-9 * reference) << "z " << z;
  }
  EXPECT_DOUBLE_EQ(binomialLowerTail(n, n, p), 1.0);
  EXPECT_NEAR(binomialLowerTail(n - 1, n, p), 1.0, 1e-15);
}

TEST(BinomialTest, AShareIsShownBelowABoundOnlyByEnoughTrials) {
  const double alpha = 0.01;
  EXPECT_FALSE(shareBelow(0, 0, 0.2, alpha)) << "no trial shows nothing";
  EXPECT_FALSE(shareBelow(0, 1, 0.2, alpha)) << "one failed trial in five is what a share of 0.2 gives";
  EXPECT_FALSE(shareBelow(0, 20, 0.2, alpha)) << "0.8^20 = 0.0115";
  EXPECT_TRUE(shareBelow(0, 21, 0.2, alpha)) << "0.8^21 = 0.0092";
  EXPECT_TRUE(shareBelow(19000, 100000, 0.2, alpha)) << "0.19 of 100 000 is 7.9 σ below 0.2";
  EXPECT_FALSE(shareBelow(19900, 100000, 0.2, alpha)) << "0.199 is 0.8 σ below";
  EXPECT_FALSE(shareBelow(30000, 100000, 0.2, alpha));
}

}  // namespace
}  // namespace vifusion
