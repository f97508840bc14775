#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "vifusion/calib/pair_residuals.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::calib {
namespace {

const PinholeCamera kCamera = PinholeCamera::create(160, 120, 120.0, 120.0, 79.5, 59.5);

/// A wall z_W = wall_z_m (split into a near half z_W = near_z_m for x_W < edge_x_m) with grey 100 + 20·x_W,
/// seen by a camera looking along +z_W from T_W_C: inverse depth and grey per pixel.
struct View {
  Image<float> inverse_depth{kCamera.width, kCamera.height};
  Image<float> grey{kCamera.width, kCamera.height};
};

View render(const SE3d& T_W_C, double wall_z_m, double near_z_m = 0.0, double edge_x_m = -1e9) {
  View view;
  const Eigen::Matrix3d R_W_C = T_W_C.rotationMatrix();
  const Eigen::Vector3d t_W_C = T_W_C.translation();
  for (int y = 0; y < kCamera.height; ++y) {
    for (int x = 0; x < kCamera.width; ++x) {
      const Eigen::Vector3d ray_W = R_W_C * kCamera.backProject({x, y}, 1.0);
      double s = (wall_z_m - t_W_C.z()) / ray_W.z();  // depth along the optical axis, ray_C.z = 1
      Eigen::Vector3d p_W = t_W_C + s * ray_W;
      if (near_z_m > 0.0) {
        const double s_near = (near_z_m - t_W_C.z()) / ray_W.z();
        const Eigen::Vector3d p_near = t_W_C + s_near * ray_W;
        if (p_near.x() < edge_x_m) {
          s = s_near;
          p_W = p_near;
        }
      }
      view.inverse_depth(x, y) = static_cast<float>(1.0 / s);
      view.grey(x, y) = static_cast<float>(100.0 + 20.0 * p_W.x());
    }
  }
  return view;
}

SE3d pose(double rx, double ry, const Eigen::Vector3d& t) {
  Vector6d xi;
  xi << t, rx, ry, 0.0;
  return SE3d::exp(xi);
}

TEST(PairResiduals, ASlantedWallSeenTwiceLeavesNoResidual) {
  // Rotated by 0.3 rad, the wall's inverse depth changes across the image: the gradient correction has work.
  const SE3d T_W_a = pose(0.05, 0.3, {0.0, 0.0, 0.0});
  const SE3d T_W_b = pose(0.02, 0.26, {0.07, -0.03, 0.12});
  const View a = render(T_W_a, 2.0);
  const View b = render(T_W_b, 2.0);
  PairResidualImages out;
  computePairResiduals(kCamera, a.inverse_depth.view(), a.grey.view(), b.inverse_depth.view(), b.grey.view(),
                       T_W_b.inverse() * T_W_a, PairResidualOptions{}, out);
  int depth_residuals = 0;
  int grey_residuals = 0;
  double largest_depth = 0.0;
  double largest_grey = 0.0;
  for (int y = 0; y < kCamera.height; ++y) {
    for (int x = 0; x < kCamera.width; ++x) {
      if (std::isfinite(out.inverse_depth_residual_per_m(x, y))) {
        ++depth_residuals;
        largest_depth = std::max(largest_depth, std::abs(double{out.inverse_depth_residual_per_m(x, y)}));
        EXPECT_GT(out.inverse_depth_gradient_sq(x, y), 0.0F);
      }
      if (std::isfinite(out.grey_b_at_a(x, y))) {
        ++grey_residuals;
        largest_grey = std::max(largest_grey, std::abs(double{out.grey_b_at_a(x, y)} - a.grey(x, y)));
      }
    }
  }
  EXPECT_GT(depth_residuals, kCamera.width * kCamera.height / 2);
  EXPECT_GT(grey_residuals, kCamera.width * kCamera.height / 2);
  EXPECT_LT(largest_depth, 2e-5);  // float rounding of ι ≈ 0.5 1/m; the simulator's noise is 1.4e-3
  EXPECT_LT(largest_grey, 0.02);   // grey is projective, not affine, in the pixel: second order over ½ px
}

TEST(PairResiduals, BiasSensitivityMatchesNumericDifferentiation) {
  // k = ∂r_ι/∂b: add b to both frames' inverse depth (a bias the calibration left in) and difference the
  // residuals. The wall is slanted and b moves towards it and sideways, so all three parts of k are at work.
  const SE3d T_W_a = pose(0.05, 0.3, {0.0, 0.0, 0.0});
  const SE3d T_W_b = pose(0.02, 0.26, {0.15, -0.03, 0.4});
  const View a = render(T_W_a, 2.5);
  const View b = render(T_W_b, 2.5);
  constexpr float kBias_per_m = 1e-3F;
  View a_biased = a;
  View b_biased = b;
  for (std::size_t i = 0; i < a.inverse_depth.pixelCount(); ++i) {
    a_biased.inverse_depth.data()[i] += kBias_per_m;
    b_biased.inverse_depth.data()[i] += kBias_per_m;
  }
  const SE3d T_b_a = T_W_b.inverse() * T_W_a;
  PairResidualImages clean, biased;
  computePairResiduals(kCamera, a.inverse_depth.view(), a.grey.view(), b.inverse_depth.view(), b.grey.view(), T_b_a,
                       PairResidualOptions{}, clean);
  computePairResiduals(kCamera, a_biased.inverse_depth.view(), a_biased.grey.view(), b_biased.inverse_depth.view(),
                       b_biased.grey.view(), T_b_a, PairResidualOptions{}, biased);
  int compared = 0;
  double largest_k = 0.0;
  double worst = 0.0;
  for (std::size_t i = 0; i < clean.bias_sensitivity.pixelCount(); ++i) {
    const double k = clean.bias_sensitivity.data()[i];
    const double r0 = clean.inverse_depth_residual_per_m.data()[i];
    const double r1 = biased.inverse_depth_residual_per_m.data()[i];
    if (!std::isfinite(k) || !std::isfinite(r0) || !std::isfinite(r1)) continue;
    const double numeric = (r1 - r0) / kBias_per_m;
    EXPECT_NEAR(numeric, k, 0.005) << i;  // float ι (1e-7 of 1e-3 per value) and b²-order terms
    largest_k = std::max(largest_k, std::abs(k));
    worst = std::max(worst, std::abs(numeric - k));
    ++compared;
  }
  EXPECT_GT(compared, kCamera.width * kCamera.height / 3);
  EXPECT_GT(largest_k, 0.2);  // the motion does change depth: k is far from 0
  std::printf("largest k %.3f, worst error %.2e\n", largest_k, worst);
}

TEST(PairResidualsGates, ADepthEdgeInTheStencilGivesNoResidual) {
  // The near half (1 m) ends at x_W = 0; b sees the edge near its centre column.
  const SE3d T_W_a = pose(0.0, 0.0, {0.0, 0.0, 0.0});
  const SE3d T_W_b = pose(0.0, 0.0, {0.05, 0.0, 0.05});
  const View a = render(T_W_a, 3.0, 1.0, 0.0);
  const View b = render(T_W_b, 3.0, 1.0, 0.0);
  PairResidualImages out;
  computePairResiduals(kCamera, a.inverse_depth.view(), a.grey.view(), b.inverse_depth.view(), b.grey.view(),
                       T_W_b.inverse() * T_W_a, PairResidualOptions{}, out);
  const int row = kCamera.height / 2;
  // In a the edge falls between columns 79 and 80 (cx = 79.5): every stencil holding both is gated.
  const int edge_column_a = 80;
  for (int x = edge_column_a - kStencilHalfWidth_px; x < edge_column_a + kStencilHalfWidth_px; ++x) {
    EXPECT_TRUE(std::isnan(out.inverse_depth_residual_per_m(x, row))) << x;
  }
  // Far from the edge on both sides, residuals are there and zero.
  EXPECT_NEAR(out.inverse_depth_residual_per_m(edge_column_a - 20, row), 0.0F, 2e-5F);
  EXPECT_NEAR(out.inverse_depth_residual_per_m(edge_column_a + 30, row), 0.0F, 2e-5F);
}

TEST(PairResidualsGates, MissingDepthAndTheImageBorderGiveNoResidual) {
  const SE3d T_W_a = pose(0.0, 0.0, {0.0, 0.0, 0.0});
  View a = render(T_W_a, 2.0);
  View b = render(T_W_a, 2.0);
  b.inverse_depth(80, 60) = 0.0F;
  PairResidualImages out;
  computePairResiduals(kCamera, a.inverse_depth.view(), a.grey.view(), b.inverse_depth.view(), b.grey.view(), SE3d(),
                       PairResidualOptions{}, out);
  EXPECT_TRUE(std::isnan(out.inverse_depth_residual_per_m(80, 60)));   // its own tap
  EXPECT_TRUE(std::isnan(out.inverse_depth_residual_per_m(82, 60)));   // a stencil tap
  EXPECT_TRUE(std::isnan(out.inverse_depth_residual_per_m(0, 60)));    // stencil off the image
  EXPECT_FALSE(std::isnan(out.inverse_depth_residual_per_m(81, 61)));  // not in any stencil of (80, 60)
  EXPECT_FLOAT_EQ(out.grey_b_at_a(80, 60), a.grey(80, 60));            // grey needs no depth in b
}

TEST(PairResidualOptions, RejectsGatesOutOfRange) {
  EXPECT_THROW((PairResidualOptions{.max_relative_curvature = 0.0, .max_intensity_curvature = 32.0}.validate()), Error);
  EXPECT_THROW((PairResidualOptions{.max_relative_curvature = 0.1, .max_intensity_curvature = -1.0}.validate()), Error);
  EXPECT_NO_THROW(PairResidualOptions{}.validate());
}

}  // namespace
}  // namespace vifusion::calib
