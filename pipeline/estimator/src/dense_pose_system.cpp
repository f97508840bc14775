#include "vifusion/estimator/dense_pose_system.hpp"

#include "vifusion/core/so3.hpp"

namespace vifusion::estimator {

Matrix6d referenceTwistPerStatePose(const SE3d& T_W_ref, const SE3d& T_W_C) {
  // [δr; δα] → the left twist in W: ρ_W = δr + hat(r)·δα (a rotation about W's origin moves the
  // camera centre by δα × r, which the translation part must undo), φ_W = δα.
  Matrix6d to_world = Matrix6d::Identity();
  to_world.topRightCorner<3, 3>() = hat(T_W_C.translation());
  return T_W_ref.inverse().adjoint() * to_world;
}

PoseSystem toStatePose(const Matrix6d& H_ref, const Vector6d& b_ref, const SE3d& T_W_ref, const SE3d& T_W_C) {
  const Matrix6d A = referenceTwistPerStatePose(T_W_ref, T_W_C);
  PoseSystem system;
  system.H = A.transpose() * H_ref * A;
  system.b = A.transpose() * b_ref;
  return system;
}

}  // namespace vifusion::estimator
