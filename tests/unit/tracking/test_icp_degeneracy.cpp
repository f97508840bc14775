#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "vifusion/tracking/icp_degeneracy.hpp"

namespace vifusion::tracking {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;

struct Surface {
  Eigen::Vector3d point;   ///< a point on the plane, reference camera frame [m]
  Eigen::Vector3d normal;  ///< unit normal
  Eigen::Vector3d u, v;    ///< two unit directions in the plane
};

/// Point-to-plane rows J = [n; p × n] (left twist [ρ; φ] of the reference camera) for a 20×20 grid on
/// each surface, normals tilted by N(0, normal_noise²) per axis as noisy depth tilts them, residuals
/// N(0, 1 mm²).
NormalEquations6 icpRows(const std::vector<Surface>& surfaces, double normal_noise_rad, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  NormalEquations6 icp;
  for (const Surface& s : surfaces) {
    for (int i = 0; i < 20; ++i) {
      for (int j = 0; j < 20; ++j) {
        const Eigen::Vector3d p = s.point + (i - 9.5) * 0.05 * s.u + (j - 9.5) * 0.05 * s.v;
        // Named draws: the order in which function arguments are evaluated is unspecified, and GCC's differs
        // between x86-64 and aarch64, which would give each architecture other data.
        const double tilt_x = noise(rng);
        const double tilt_y = noise(rng);
        const double tilt_z = noise(rng);
        const Eigen::Vector3d n = (s.normal + normal_noise_rad * Eigen::Vector3d(tilt_x, tilt_y, tilt_z)).normalized();
        Vector6 J;
        J << n, p.cross(n);
        icp.addRow(J, 0.001 * noise(rng), 1.0 / (0.002 * 0.002));
      }
    }
  }
  return icp;
}

const Surface kWall{{0.0, 0.0, 1.6}, {0.0, 0.0, -1.0}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}};
const Surface kCeiling{{0.0, -1.0, 1.6}, {0.0, 1.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}};
const Surface kSideWall{{-1.0, 0.0, 1.6}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};

Vector6 twist(const Eigen::Vector3d& rho, const Eigen::Vector3d& phi) {
  Vector6 xi;
  xi << rho, phi;
  return xi;
}

/// Information along a unit direction: ξᵀ H ξ.
double information(const NormalEquations6& system, const Vector6& xi) { return xi.dot(system.H * xi); }

TEST(IcpDegeneracy, ABlankWallLeavesItsPlaneAndTheTwistAboutItsNormalFree) {
  const NormalEquations6 icp = icpRows({kWall}, 0.03, 1);
  NormalEquations6 photometric;  // another term, untouched
  photometric.H = 5.0 * Eigen::Matrix<double, 6, 6>::Identity();
  NormalEquations6 system = icp;
  system += photometric;
  const double along_x_before = information(system, twist({1, 0, 0}, {0, 0, 0}));
  EXPECT_GT(along_x_before, 1e3) << "noisy normals give the free direction a formal information";
  EXPECT_EQ(removeUnconstrainedIcpDirections(icp, 0.02, system), 3);
  for (const Vector6& free : {twist({1, 0, 0}, {0, 0, 0}), twist({0, 1, 0}, {0, 0, 0}), twist({0, 0, 0}, {0, 0, 1})}) {
    // Only the other term is left, up to the estimated normal's tilt times the depth information.
    EXPECT_NEAR(information(system, free), 5.0, 1e-5 * icp.H.norm()) << free.transpose();
  }
  // What the wall does constrain keeps ICP's information: depth and the two tilts.
  EXPECT_NEAR(information(system, twist({0, 0, 1}, {0, 0, 0})), information(icp, twist({0, 0, 1}, {0, 0, 0})) + 5.0,
              1e-6 * information(icp, twist({0, 0, 1}, {0, 0, 0})));
  EXPECT_GT(information(system, twist({0, 0, 0}, {1, 0, 0})), 1e5);
}

TEST(IcpDegeneracy, AWallAndCeilingLeaveOnlyTheirEdge) {
  const double normal_noise_rad = 0.03;
  const NormalEquations6 icp = icpRows({kWall, kCeiling}, normal_noise_rad, 2);
  NormalEquations6 system = icp;
  EXPECT_EQ(removeUnconstrainedIcpDirections(icp, 0.02, system), 1);
  // The direction removed is the least-informed translation of ICP's own rows: the edge (x), tilted by the
  // normals' noise averaged over the 800 rows (σ ≈ 0.03 rad / √800 ≈ 1 mrad per axis; bound: 10σ), and
  // nothing of ICP is left along it but rounding. Along x exactly, the tilt leaves tilt² of the constrained
  // information, which depends on the draw: it is not asserted.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(icp.H.topLeftCorner<3, 3>());
  const Eigen::Vector3d removed = eigen.eigenvectors().col(0);
  const double tilt_bound_rad = 10.0 * normal_noise_rad / std::sqrt(800.0);
  EXPECT_GT(std::abs(removed.x()), std::cos(tilt_bound_rad)) << removed.transpose();
  EXPECT_NEAR(information(system, twist(removed, {0, 0, 0})), 0.0, 1e-12 * system.H.norm());
  EXPECT_GT(information(system, twist({0, 1, 0}, {0, 0, 0})), 1e7);
  EXPECT_GT(information(system, twist({0, 0, 0}, {0, 0, 1})), 1e5) << "the rotation stays: two planes fix it";
}

TEST(IcpDegeneracy, ACornerConstrainsEverything) {
  const NormalEquations6 icp = icpRows({kWall, kCeiling, kSideWall}, 0.03, 3);
  NormalEquations6 system = icp;
  EXPECT_EQ(removeUnconstrainedIcpDirections(icp, 0.02, system), 0);
  EXPECT_EQ(system.H, icp.H);
  EXPECT_EQ(system.b, icp.b);
  NormalEquations6 empty;
  EXPECT_EQ(removeUnconstrainedIcpDirections(empty, 0.02, system), 0);
}

}  // namespace
}  // namespace vifusion::tracking
