#include "vifusion/core/state.hpp"

#include "vifusion/core/so3.hpp"

namespace vifusion {

NavState boxPlus(const NavState& x, const Vector18d& delta) {
  NavState y;
  y.r_W_C = x.r_W_C + delta.segment<3>(kIdxR);
  y.q_W_C = (expSO3(delta.segment<3>(kIdxAlpha)) * x.q_W_C).normalized();
  y.v_I_S = x.v_I_S + delta.segment<3>(kIdxV);
  y.b_g = x.b_g + delta.segment<3>(kIdxBg);
  y.b_a = x.b_a + delta.segment<3>(kIdxBa);
  y.q_I_W = (expSO3(delta.segment<3>(kIdxG)) * x.q_I_W).normalized();
  return y;
}

Vector18d boxMinus(const NavState& a, const NavState& b, Matrix18d* J_a, Matrix18d* J_b) {
  Vector18d d;
  d.segment<3>(kIdxR) = a.r_W_C - b.r_W_C;
  d.segment<3>(kIdxAlpha) = logSO3(a.q_W_C * b.q_W_C.conjugate());
  d.segment<3>(kIdxV) = a.v_I_S - b.v_I_S;
  d.segment<3>(kIdxBg) = a.b_g - b.b_g;
  d.segment<3>(kIdxBa) = a.b_a - b.b_a;
  d.segment<3>(kIdxG) = logSO3(a.q_I_W * b.q_I_W.conjugate());

  // log(exp(δ)·exp(φ)) = φ + J_l⁻¹(φ)·δ for a, and log(exp(φ)·exp(−δ)) = φ − J_r⁻¹(φ)·δ for b.
  const Eigen::Vector3d phi_alpha = d.segment<3>(kIdxAlpha);
  const Eigen::Vector3d phi_g = d.segment<3>(kIdxG);
  if (J_a != nullptr) {
    J_a->setIdentity();
    J_a->block<3, 3>(kIdxAlpha, kIdxAlpha) = leftJacobianInvSO3(phi_alpha);
    J_a->block<3, 3>(kIdxG, kIdxG) = leftJacobianInvSO3(phi_g);
  }
  if (J_b != nullptr) {
    *J_b = -Matrix18d::Identity();
    J_b->block<3, 3>(kIdxAlpha, kIdxAlpha) = -rightJacobianInvSO3(phi_alpha);
    J_b->block<3, 3>(kIdxG, kIdxG) = -rightJacobianInvSO3(phi_g);
  }
  return d;
}

}  // namespace vifusion
