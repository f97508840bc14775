#include "vifusion/estimator/gravity_initialisation.hpp"

namespace vifusion::estimator {

std::optional<GravityInitialisation> initialGravity(std::span<const ImuSample> samples, const SE3d& T_W_C,
                                                    const SE3d& T_S_C, const Eigen::Vector3d& accel_bias_S) {
  if (samples.empty()) return std::nullopt;
  GravityInitialisation result;
  for (const ImuSample& sample : samples) result.mean_specific_force_S_mps2 += sample.accel_mps2;
  result.samples = static_cast<int>(samples.size());
  result.mean_specific_force_S_mps2 /= static_cast<double>(samples.size());
  result.mean_specific_force_S_mps2 -= accel_bias_S;
  if (!(result.mean_specific_force_S_mps2.norm() >= 1.0)) return std::nullopt;
  const Eigen::Matrix3d R_W_S = T_W_C.rotationMatrix() * T_S_C.inverse().rotationMatrix();
  const Eigen::Vector3d up_W = R_W_S * result.mean_specific_force_S_mps2;
  result.q_I_W = Eigen::Quaterniond::FromTwoVectors(up_W, Eigen::Vector3d::UnitZ()).normalized();
  return result;
}

}  // namespace vifusion::estimator
