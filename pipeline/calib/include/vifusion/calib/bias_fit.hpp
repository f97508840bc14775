#pragma once
// Weighted least squares for the inverse-depth bias b [1/m] a depth image carries as a whole, from pair
// residuals r ≈ k·b (pair_residuals.hpp): b = Σ w k r / Σ w k², w = 1/var(r).
//
// Variance. A pair's residuals share errors across the whole image (a depth staircase, the dot pattern), so
// pixels are far from independent for this one number. The variance is the cluster-robust (sandwich) one with
// each pair a cluster: P/(P − 1)·Σ_p g_p² / (Σ w k²)², g_p = Σ_{i∈p} w_i k_i (r_i − k_i·b), which holds whatever
// the pixels of one pair share, as long as different pairs' errors are independent. Errors every pair shares
// (the same room seen from every pair) it cannot see.

#include <cmath>
#include <vector>

namespace vifusion::calib {

struct BiasEstimate {
  double bias_per_m = 0.0;
  double sigma_per_m = 0.0;  ///< 0 with fewer than two pairs
};

class BiasFit {
 public:
  /// Starts a new cluster; add() goes to the latest one.
  void beginPair() { pairs_.push_back({}); }

  /// One residual r [1/m] with its sensitivity k = ∂r/∂b and weight w = 1/var(r). Needs beginPair() first.
  void add(double sensitivity, double residual, double weight) {
    Pair& pair = pairs_.back();
    pair.normal += weight * sensitivity * sensitivity;
    pair.rhs += weight * sensitivity * residual;
  }

  /// The least-squares bias and its clustered σ; 0 and 0 when no residual constrains it.
  BiasEstimate solve() const {
    double normal = 0.0;
    double rhs = 0.0;
    for (const Pair& pair : pairs_) {
      normal += pair.normal;
      rhs += pair.rhs;
    }
    BiasEstimate out;
    if (!(normal > 0.0)) return out;
    out.bias_per_m = rhs / normal;
    if (pairs_.size() < 2) return out;
    double meat = 0.0;
    for (const Pair& pair : pairs_) {
      const double score = pair.rhs - pair.normal * out.bias_per_m;
      meat += score * score;
    }
    const double count = static_cast<double>(pairs_.size());
    out.sigma_per_m = std::sqrt(count / (count - 1.0) * meat) / normal;
    return out;
  }

 private:
  struct Pair {
    double normal = 0.0;  ///< Σ w k²
    double rhs = 0.0;     ///< Σ w k r
  };
  std::vector<Pair> pairs_;
};

}  // namespace vifusion::calib
