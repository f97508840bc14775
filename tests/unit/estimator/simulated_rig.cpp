#include "simulated_rig.hpp"

#include <cmath>

#include <algorithm>
#include <numbers>

#include "vifusion/core/so3.hpp"
#include "vifusion/estimator/gravity_initialisation.hpp"
#include "vifusion/imu/sample_window.hpp"
#include "vifusion/sim/presets.hpp"

namespace vifusion::estimator::test {

SE3d rigT_S_C() { return SE3d(expSO3(Eigen::Vector3d(0.02, -0.045, 0.01)), Eigen::Vector3d(0.045, -0.012, 0.008)); }

Eigen::Quaterniond trueQ_I_W() {
  return Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(std::numbers::pi / 2.0, Eigen::Vector3d::UnitX()));
}

SimulatedRig::SimulatedRig(const std::string& preset, std::uint64_t seed, bool realistic)
    : T_S_C(rigT_S_C()), fit(sim::fitTrajectory(sim::presetCameraPoses(preset), T_S_C)) {
  sim::ImuSimOptions options;
  options.seed = seed;
  options.add_noise = realistic;
  options.add_biases = realistic;
  imu = sim::simulateImu(fit.spline_W_S, options);
  constexpr std::int64_t kFramePeriodNs = 33'333'333;
  for (std::int64_t t_ns = imu.samples.front().t_ns + 12'300'000; t_ns < imu.samples.back().t_ns;
       t_ns += kFramePeriodNs) {
    frame_times_ns.push_back(t_ns);
  }
}

NavState SimulatedRig::trueState(std::int64_t t_ns) const {
  const sim::Se3Spline::Kinematics kin = fit.spline_W_S.kinematics(t_ns);
  const SE3d T_W_C = kin.T_W_S * T_S_C;
  const auto nearest = std::lower_bound(imu.states.begin(), imu.states.end(), t_ns,
                                        [](const GroundTruthState& s, std::int64_t t) { return s.t_ns < t; });
  const GroundTruthState& biases = nearest == imu.states.end() ? imu.states.back() : *nearest;
  NavState x;
  x.r_W_C = T_W_C.translation();
  x.q_W_C = T_W_C.quaternion();
  x.q_I_W = trueQ_I_W();
  x.v_I_S = x.q_I_W * kin.v_W_mps;
  x.b_g = biases.b_g;
  x.b_a = biases.b_a;
  return x;
}

NavState SimulatedRig::initialState() const {
  const std::int64_t t0_ns = frame_times_ns.front();
  NavState x = trueState(t0_ns);
  x.v_I_S.setZero();
  x.b_g.setZero();
  x.b_a.setZero();
  const auto window = imu::bracketingSamples(imu.samples, t0_ns - 200'000'000, t0_ns);
  x.q_I_W = initialGravity(window, SE3d(x.q_W_C, x.r_W_C), T_S_C).value().q_I_W;
  return x;
}

SimulatedVision::SimulatedVision(double sigma_m, double sigma_rad, std::uint64_t seed)
    : sigma_m_(sigma_m), sigma_rad_(sigma_rad), rng_(seed) {}

void SimulatedVision::observe(const SE3d& T_W_C_true) {
  const Eigen::Vector3d dr(rng_() * sigma_m_, rng_() * sigma_m_, rng_() * sigma_m_);
  const Eigen::Vector3d da(rng_() * sigma_rad_, rng_() * sigma_rad_, rng_() * sigma_rad_);
  measured_T_W_C_ = SE3d(expSO3(da) * T_W_C_true.quaternion(), T_W_C_true.translation() + dr);
}

bool SimulatedVision::evaluate(int, const SE3d& T_W_C, PoseSystem& system) {
  ++evaluations_;
  Vector6d r;
  r.head<3>() = T_W_C.translation() - measured_T_W_C_.translation();
  r.tail<3>() = logSO3(T_W_C.quaternion() * measured_T_W_C_.quaternion().conjugate());
  Matrix6d J = Matrix6d::Identity();
  J.bottomRightCorner<3, 3>() = leftJacobianInvSO3(r.tail<3>());
  Vector6d information;
  information << Eigen::Vector3d::Constant(1.0 / (sigma_m_ * sigma_m_)),
      Eigen::Vector3d::Constant(1.0 / (sigma_rad_ * sigma_rad_));
  system.H = J.transpose() * information.asDiagonal() * J / overshoot_;
  system.b = J.transpose() * information.asDiagonal() * r;
  constexpr double kInliers = 1000.0, kBasin_m = 0.05;
  system.inliers = overshoot_ == 1.0 ? kInliers
                                     : kInliers * std::exp(-0.5 * r.head<3>().squaredNorm() / (kBasin_m * kBasin_m));
  return true;
}

}  // namespace vifusion::estimator::test
