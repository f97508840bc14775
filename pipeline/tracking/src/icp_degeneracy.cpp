#include "vifusion/tracking/icp_degeneracy.hpp"

#include <Eigen/Eigenvalues>

namespace vifusion::tracking {

int removeUnconstrainedIcpDirections(const NormalEquations6& icp, double min_share, NormalEquations6& system) {
  const Eigen::Matrix3d H_tt = icp.H.topLeftCorner<3, 3>();
  const double weight = H_tt.trace();  // Σ w ‖n‖² = Σ w
  if (!(weight > 0.0)) return 0;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(H_tt);
  Eigen::Matrix<double, 6, 6> P = Eigen::Matrix<double, 6, 6>::Identity();
  int free_translations = 0;
  for (int k = 0; k < 3; ++k) {  // eigenvalues ascending
    if (eigen.eigenvalues()(k) >= min_share * weight) break;
    const Eigen::Vector3d e = eigen.eigenvectors().col(k);
    P.topLeftCorner<3, 3>() -= e * e.transpose();
    ++free_translations;
  }
  if (free_translations == 0) return 0;
  int removed = free_translations;
  if (free_translations >= 2) {
    // One plane: rotating about any axis along its normal keeps every point on it.
    const Eigen::Vector3d normal = eigen.eigenvectors().col(2);
    P.bottomRightCorner<3, 3>() -= normal * normal.transpose();
    ++removed;
  }
  system.H += P * icp.H * P - icp.H;
  system.b += P * icp.b - icp.b;
  return removed;
}

}  // namespace vifusion::tracking
