#include "vifusion/sim/normal_rng.hpp"

#include <cmath>
#include <numbers>

namespace vifusion::sim {

double NormalRng::uniformOpenClosed() {
  constexpr double kTwoToMinus53 = 1.0 / 9007199254740992.0;
  return static_cast<double>((engine_() >> 11) + 1) * kTwoToMinus53;
}

double NormalRng::operator()() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  const double radius = std::sqrt(-2.0 * std::log(uniformOpenClosed()));
  const double angle_rad = 2.0 * std::numbers::pi * uniformOpenClosed();
  spare_ = radius * std::sin(angle_rad);
  has_spare_ = true;
  return radius * std::cos(angle_rad);
}

}  // namespace vifusion::sim
