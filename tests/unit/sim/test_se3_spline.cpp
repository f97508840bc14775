#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "vifusion/core/error.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/sim/se3_spline.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion::sim {
namespace {

constexpr int kK = Se3Spline::kOrder;
constexpr std::int64_t kT0_ns = 1'000'000'000;
constexpr std::int64_t kDt_ns = 100'000'000;  // 0.1 s knots

/// A spline with lively random control points: position steps of ±0.1 m and rotation steps up to 0.3 rad
/// per 0.1 s knot (peaks of several m/s² and rad/s).
Se3Spline randomSpline(unsigned seed, int control_points = 14) {
  std::mt19937 engine(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Vector3d> p_W_m;
  std::vector<Eigen::Quaterniond> q_W_S;
  Eigen::Vector3d p(1.0, 1.2, -0.3);
  Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, -1.0).normalized()));
  for (int i = 0; i < control_points; ++i) {
    p += 0.1 * Eigen::Vector3d(uniform(engine), uniform(engine), uniform(engine));
    q = q * expSO3(0.17 * Eigen::Vector3d(uniform(engine), uniform(engine), uniform(engine)));
    p_W_m.push_back(p);
    q_W_S.push_back(q);
  }
  return Se3Spline(kT0_ns, kDt_ns, p_W_m, q_W_S);
}

/// Sample times across the range, avoiding knots so central differences stay inside one segment.
std::vector<std::int64_t> interiorTimes(const Se3Spline& spline, std::int64_t margin_ns) {
  std::vector<std::int64_t> times;
  for (std::int64_t t = spline.startTimeNs() + margin_ns; t < spline.endTimeNs() - margin_ns; t += 37'123'457) {
    const std::int64_t into_segment_ns = (t - spline.startTimeNs()) % kDt_ns;
    if (into_segment_ns > margin_ns && into_segment_ns < kDt_ns - margin_ns) times.push_back(t);
  }
  return times;
}

TEST(Se3Spline, BasisIsAPartitionOfUnityWithQuinticKnotValues) {
  const Se3Spline spline = randomSpline(1);
  // At a knot the quintic uniform B-spline weights are (1, 26, 66, 26, 1, 0)/120.
  const Se3Spline::SegmentWeights at_knot = spline.basisWeights(kT0_ns + 3 * kDt_ns);
  EXPECT_EQ(at_knot.first_control, 3);
  Se3Spline::BasisVector expected;
  expected << 1.0, 26.0, 66.0, 26.0, 1.0, 0.0;
  EXPECT_MATRIX_NEAR(at_knot.weights, expected / 120.0, 1e-15);
  for (std::int64_t t = spline.startTimeNs(); t <= spline.endTimeNs(); t += 7'000'001) {
    const Se3Spline::BasisVector w = spline.basisWeights(t).weights;
    EXPECT_NEAR(w.sum(), 1.0, 1e-14);
    EXPECT_GE(w.minCoeff(), 0.0);
  }
}

TEST(Se3Spline, RangeAndControlCentres) {
  const Se3Spline spline = randomSpline(2, 14);
  EXPECT_EQ(spline.numSegments(), 14 - kK + 1);
  EXPECT_EQ(spline.startTimeNs(), kT0_ns);
  EXPECT_EQ(spline.endTimeNs(), kT0_ns + 9 * kDt_ns);
  EXPECT_EQ(spline.controlCentreTimeNs(2), kT0_ns);  // (k − 2)/2 = 2 knots before the first knot's control
  EXPECT_NO_THROW(spline.pose(spline.endTimeNs()));
  EXPECT_THROW(spline.pose(spline.startTimeNs() - 1), Error);
  EXPECT_THROW(spline.pose(spline.endTimeNs() + 1), Error);
  EXPECT_THROW(Se3Spline(0, 0, {6, Eigen::Vector3d::Zero()}, {6, Eigen::Quaterniond::Identity()}), Error);
  EXPECT_THROW(Se3Spline(0, 1, {5, Eigen::Vector3d::Zero()}, {5, Eigen::Quaterniond::Identity()}), Error);
  EXPECT_THROW(Se3Spline(0, 1, {6, Eigen::Vector3d::Zero()}, {7, Eigen::Quaterniond::Identity()}), Error);
}

TEST(Se3Spline, KinematicsAgreeWithPoseAndNumericDerivatives) {
  const Se3Spline spline = randomSpline(3);
  constexpr std::int64_t kH_ns = 20'000;  // 20 µs central differences: truncation ~h²·|f'''| ≈ 1e-7
  const double h_s = nsToSeconds(kH_ns);
  for (const std::int64_t t : interiorTimes(spline, 2 * kH_ns)) {
    const Se3Spline::Kinematics k = spline.kinematics(t);
    const Se3Spline::Kinematics before = spline.kinematics(t - kH_ns);
    const Se3Spline::Kinematics after = spline.kinematics(t + kH_ns);
    const SE3d T = spline.pose(t);
    EXPECT_MATRIX_NEAR(k.T_W_S.translation(), T.translation(), 1e-14);
    EXPECT_ROTATION_NEAR(k.T_W_S.quaternion(), T.quaternion(), 1e-14);

    const Eigen::Vector3d v_numeric = (spline.position(t + kH_ns) - spline.position(t - kH_ns)) / (2.0 * h_s);
    EXPECT_MATRIX_NEAR(k.v_W_mps, v_numeric, 1e-6);
    EXPECT_MATRIX_NEAR(k.a_W_mps2, (after.v_W_mps - before.v_W_mps) / (2.0 * h_s), 1e-5);
    // Body rate: R(t − h)ᵀR(t + h) = Exp(2h·ω + O(h³)).
    const Eigen::Vector3d omega_numeric =
        logSO3(spline.orientation(t - kH_ns).conjugate() * spline.orientation(t + kH_ns)) / (2.0 * h_s);
    EXPECT_MATRIX_NEAR(k.omega_S_rad_s, omega_numeric, 1e-6);
    EXPECT_MATRIX_NEAR(k.alpha_S_rad_s2, (after.omega_S_rad_s - before.omega_S_rad_s) / (2.0 * h_s), 1e-5);
  }
}

TEST(Se3Spline, RotationJacobiansMatchNumericDifferentiation) {
  const Se3Spline spline = randomSpline(4);
  constexpr double kStep = 1e-6;
  for (const std::int64_t t : {kT0_ns, kT0_ns + 123'456'789, kT0_ns + 5 * kDt_ns + 77'777'777, spline.endTimeNs()}) {
    Se3Spline::RotationJacobians J;
    const Eigen::Quaterniond q = spline.orientation(t, &J);
    for (int m = 0; m < kK; ++m) {
      Eigen::Matrix3d J_numeric;
      for (int axis = 0; axis < 3; ++axis) {
        const auto perturbed = [&](double step) {
          std::vector<Eigen::Quaterniond> rotations = spline.controlRotations();
          rotations[static_cast<std::size_t>(J.first_control + m)] *= expSO3(step * Eigen::Vector3d::Unit(axis));
          const Se3Spline moved(spline.startTimeNs(), spline.knotSpacingNs(), spline.controlPositions(), rotations);
          return logSO3(q.conjugate() * moved.orientation(t));
        };
        J_numeric.col(axis) = (perturbed(kStep) - perturbed(-kStep)) / (2.0 * kStep);
      }
      EXPECT_MATRIX_NEAR(J.d_R_d_control[static_cast<std::size_t>(m)], J_numeric, 1e-8) << "control " << m;
    }
  }
}

TEST(Se3Spline, ContinuousUpToJerkAcrossKnots) {
  const Se3Spline spline = randomSpline(5);
  // Left and right limits at each inner knot: the segments meet at t_knot, evaluated 1 ns either side
  // (values change by |next derivative|·1 ns there: ≈ 2e-9 for the pose, ≈ 1e-7 for the rates).
  constexpr std::int64_t kH_ns = 1'000;  // 1 µs for the one-sided jerk differences
  for (int knot = 1; knot < spline.numSegments(); ++knot) {
    const std::int64_t t = kT0_ns + knot * kDt_ns;
    const Se3Spline::Kinematics left = spline.kinematics(t - 1);
    const Se3Spline::Kinematics right = spline.kinematics(t);
    EXPECT_MATRIX_NEAR(left.T_W_S.translation(), right.T_W_S.translation(), 1e-8);
    EXPECT_ROTATION_NEAR(left.T_W_S.quaternion(), right.T_W_S.quaternion(), 1e-8);
    EXPECT_MATRIX_NEAR(left.v_W_mps, right.v_W_mps, 1e-7);
    EXPECT_MATRIX_NEAR(left.a_W_mps2, right.a_W_mps2, 1e-6);
    EXPECT_MATRIX_NEAR(left.omega_S_rad_s, right.omega_S_rad_s, 1e-7);
    EXPECT_MATRIX_NEAR(left.alpha_S_rad_s2, right.alpha_S_rad_s2, 1e-6);
    // Quintic: the jerk (derivative of the accelerometer signal) is continuous as well.
    const Eigen::Vector3d jerk_left = (right.a_W_mps2 - spline.kinematics(t - kH_ns).a_W_mps2) / nsToSeconds(kH_ns);
    const Eigen::Vector3d jerk_right = (spline.kinematics(t + kH_ns).a_W_mps2 - right.a_W_mps2) / nsToSeconds(kH_ns);
    EXPECT_MATRIX_NEAR(jerk_left, jerk_right, 1e-2 * (1.0 + jerk_left.norm()));
  }
}

TEST(Se3Spline, EqualIncrementsGiveConstantVelocityAndRate) {
  // Linear precision: equally spaced control points make a straight line at constant speed, equal rotation
  // increments a constant body rate.
  const Eigen::Vector3d step_m(0.02, -0.01, 0.03);
  const Eigen::Vector3d step_rad(0.1, 0.05, -0.2);
  std::vector<Eigen::Vector3d> p_W_m;
  std::vector<Eigen::Quaterniond> q_W_S;
  for (int i = 0; i < 10; ++i) {
    p_W_m.emplace_back(i * step_m);
    q_W_S.push_back(i == 0 ? Eigen::Quaterniond::Identity() : q_W_S.back() * expSO3(step_rad));
  }
  const Se3Spline spline(0, kDt_ns, p_W_m, q_W_S);
  for (std::int64_t t = 0; t <= spline.endTimeNs(); t += 13'000'000) {
    const Se3Spline::Kinematics k = spline.kinematics(t);
    EXPECT_MATRIX_NEAR(k.v_W_mps, step_m / nsToSeconds(kDt_ns), 1e-12);
    EXPECT_MATRIX_NEAR(k.a_W_mps2, Eigen::Vector3d::Zero(), 1e-10);
    EXPECT_MATRIX_NEAR(k.omega_S_rad_s, step_rad / nsToSeconds(kDt_ns), 1e-12);
    EXPECT_MATRIX_NEAR(k.alpha_S_rad_s2, Eigen::Vector3d::Zero(), 1e-10);
  }
}

TEST(Se3Spline, RoughnessMatrixIntegratesTheSquaredDerivative) {
  const Se3Spline spline = randomSpline(6);
  // ∫|p̈|² dt over one segment by Simpson's rule on the analytic acceleration vs the quadratic form.
  const int segment = 4;
  constexpr int kIntervals = 2000;
  const std::int64_t step_ns = kDt_ns / kIntervals;
  double integral = 0.0;
  for (int i = 0; i <= kIntervals; ++i) {
    const double weight = (i == 0 || i == kIntervals) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    integral += weight * spline.kinematics(kT0_ns + segment * kDt_ns + i * step_ns).a_W_mps2.squaredNorm();
  }
  integral *= nsToSeconds(step_ns) / 3.0;

  const Se3Spline::IncrementMatrix Q = Se3Spline::roughnessMatrix(2);
  double form = 0.0;
  for (int j = 1; j < kK; ++j) {
    for (int l = 1; l < kK; ++l) {
      const auto& c = spline.controlPositions();
      form += Q(j - 1, l - 1) * (c[segment + j] - c[segment + j - 1]).dot(c[segment + l] - c[segment + l - 1]);
    }
  }
  form /= std::pow(nsToSeconds(kDt_ns), 3);
  EXPECT_NEAR(form, integral, 1e-9 * integral);
  EXPECT_TRUE(Q.isApprox(Q.transpose(), 1e-14));
}

}  // namespace
}  // namespace vifusion::sim
