#pragma once
// Reproducible random inputs for the core tests (fixed seeds, so a failure replays exactly).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>

#include "vifusion/core/so3.hpp"

namespace vifusion::test {

class RandomInputs {
 public:
  explicit RandomInputs(unsigned seed) : engine_(seed) {}

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(engine_); }

  template <int N>
  Eigen::Matrix<double, N, 1> vector(double scale = 1.0) {
    Eigen::Matrix<double, N, 1> v;
    for (int i = 0; i < N; ++i) v[i] = uniform(-scale, scale);
    return v;
  }

  /// Uniformly distributed direction.
  Eigen::Vector3d unitVector() {
    std::normal_distribution<double> normal(0.0, 1.0);
    Eigen::Vector3d v(normal(engine_), normal(engine_), normal(engine_));
    return v.normalized();
  }

  /// Rotation vector with angle uniform in [0, max_angle_rad].
  Eigen::Vector3d rotationVector(double max_angle_rad) { return uniform(0.0, max_angle_rad) * unitVector(); }

  Eigen::Quaterniond rotation() { return expSO3(rotationVector(std::numbers::pi)); }

 private:
  std::mt19937 engine_;
};

}  // namespace vifusion::test
