#pragma once
// Least-squares fit of a residual variance model with non-negative terms: var(r)/2 = Σ_k c_k·f_k, c_k ≥ 0,
// from samples (r, f). Each residual is a difference of two independent measurements, hence the half.
// r² has mean 2·Σ c_k f_k and, for Gaussian noise, variance 2·(2·Σ c_k f_k)², so each sample is weighted by
// 1 / (Σ c_k f_k)² of the previous fit (iteratively reweighted least squares). A term that comes out negative
// is removed and the rest refitted, so every coefficient is a variance.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <array>

namespace vifusion::calib {

template <int N>
class VarianceFit {
 public:
  using Features = Eigen::Matrix<double, N, 1>;
  using Coefficients = Eigen::Matrix<double, N, 1>;

  void add(double residual, const Features& features, double weight) {
    normal_ += weight * features * features.transpose();
    rhs_ += weight * features * (0.5 * residual * residual);
    ++samples_;
  }

  /// The fitted coefficients, each ≥ 0 (all zero when nothing was added).
  Coefficients solve() const {
    std::array<bool, N> active;
    active.fill(true);
    for (int round = 0; round < N; ++round) {
      Eigen::Matrix<double, N, N> normal = normal_;
      Eigen::Matrix<double, N, 1> rhs = rhs_;
      for (int k = 0; k < N; ++k) {
        if (active[static_cast<std::size_t>(k)]) continue;
        normal.row(k).setZero();
        normal.col(k).setZero();
        normal(k, k) = 1.0;
        rhs(k) = 0.0;
      }
      const Coefficients c = normal.ldlt().solve(rhs);
      int most_negative = -1;
      for (int k = 0; k < N; ++k) {
        if (c(k) < 0.0 && (most_negative < 0 || c(k) < c(most_negative))) most_negative = k;
      }
      if (most_negative < 0) return c;
      active[static_cast<std::size_t>(most_negative)] = false;
    }
    return Coefficients::Zero();
  }

  long samples() const { return samples_; }

 private:
  Eigen::Matrix<double, N, N> normal_ = Eigen::Matrix<double, N, N>::Zero();
  Eigen::Matrix<double, N, 1> rhs_ = Eigen::Matrix<double, N, 1>::Zero();
  long samples_ = 0;
};

}  // namespace vifusion::calib
