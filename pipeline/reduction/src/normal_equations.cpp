#include "vifusion/reduction/normal_equations.hpp"

#include <cassert>

namespace vifusion {

NormalEquations6& NormalEquations6::operator+=(const NormalEquations6& other) {
  H += other.H;
  b += other.b;
  weighted_squared_residual += other.weighted_squared_residual;
  inliers += other.inliers;
  candidates += other.candidates;
  weighted_squared_bound += other.weighted_squared_bound;
  return *this;
}

void NormalEquations6::addRow(const Eigen::Matrix<double, 6, 1>& J, double r, double w, double e) {
  if (!(w > 0.0)) return;
  H.noalias() += w * J * J.transpose();
  b += w * r * J;
  weighted_squared_residual += w * r * r;
  inliers += 1.0;
  weighted_squared_bound += w * e * e;
}

void NormalEquations6::addPartials(std::span<const float> partials, uint32_t groups) {
  assert(partials.size() >= std::size_t{groups} * kStride);
  double sums[kTerms] = {};
  for (uint32_t group = 0; group < groups; ++group) {
    const float* partial = partials.data() + std::size_t{group} * kStride;
    for (int k = 0; k < kTerms; ++k) sums[k] += partial[k];
  }
  int k = 0;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j, ++k) {
      H(i, j) += sums[k];
      if (j != i) H(j, i) += sums[k];
    }
  }
  for (int i = 0; i < 6; ++i) b(i) += sums[21 + i];
  weighted_squared_residual += sums[27];
  inliers += sums[28];
  candidates += sums[29];
  weighted_squared_bound += sums[30];
}

}  // namespace vifusion
