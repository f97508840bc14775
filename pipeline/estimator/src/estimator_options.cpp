#include "vifusion/estimator/estimator_options.hpp"

#include <cmath>

#include "vifusion/core/error.hpp"

namespace vifusion::estimator {

InertialMode inertialModeFromName(const std::string& name) {
  if (name == "rgbdi") return InertialMode::kRgbdInertial;
  if (name == "gyro") return InertialMode::kGyro;
  throw Error("inertial mode '" + name + "' is not one of: rgbdi, gyro");
}

const char* inertialModeName(InertialMode mode) { return mode == InertialMode::kGyro ? "gyro" : "rgbdi"; }

void EstimatorOptions::validate() const {
  for (int l = 0; l < 3; ++l) {
    if (iterations[l] < 0 || iterations[l] > 100) throw Error("estimator option 'iterations' must be 0..100 per level");
  }
  if (!(converged_step_chi2 > 0.0)) throw Error("estimator option 'converged_step_chi2' must be > 0");
  if (inertial_only_iterations < 1 || inertial_only_iterations > 100) {
    throw Error("estimator option 'inertial_only_iterations' must be 1..100");
  }
  if (!(max_inlier_loss > 0.0 && max_inlier_loss <= 1.0))
    throw Error("estimator option 'max_inlier_loss' must be in (0, 1]");
  if (!(vision_gate_chi2 > 0.0)) throw Error("estimator option 'vision_gate_chi2' must be > 0");
  const auto positive = [](double value, const char* name) {
    if (!(value > 0.0) || !std::isfinite(value))
      throw Error(std::string("estimator option '") + name + "' must be > 0");
  };
  positive(initial_pose_sigma, "initial_pose_sigma");
  positive(initial_velocity_sigma_mps, "initial_velocity_sigma_mps");
  positive(initial_gravity_sigma_rad, "initial_gravity_sigma_rad");
  positive(vision_gate_min_step_m, "vision_gate_min_step_m");
  positive(vision_gate_min_step_rad, "vision_gate_min_step_rad");
  if (gravity_window_ns <= 0) throw Error("estimator option 'gravity_window_ns' must be > 0");
}

}  // namespace vifusion::estimator
