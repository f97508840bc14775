#include "vifusion/loop/deformation_function.hpp"

#include <Eigen/SVD>

namespace vifusion::loop {

Eigen::Matrix3d orthonormalise(const Eigen::Matrix3d& M) {
  if (!M.allFinite()) return Eigen::Matrix3d::Identity();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  // A reflection (det < 0) is no rotation: flip the axis of the smallest singular value.
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) D(2, 2) = -1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

SE3d deformPose(const SE3d& T_W_C, const NodeBinding<double>& binding,
                std::span<const Eigen::Vector3d> node_positions_W, std::span<const double> node_params) {
  const Eigen::Matrix3d R = orthonormalise(blendedAffine(binding, node_params)) * T_W_C.rotationMatrix();
  const Eigen::Vector3d r = deformPoint<double>(T_W_C.translation(), binding, node_positions_W, node_params);
  return SE3d(Eigen::Quaterniond(R), r);
}

}  // namespace vifusion::loop
