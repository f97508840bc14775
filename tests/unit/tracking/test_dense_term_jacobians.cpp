// Numeric checks of the dense terms' analytic Jacobians through their CPU references (the GPU tests
// hold the shaders to these): with robust weights switched off, b = Σ w Jᵀ r is the gradient of the
// cost ½ Σ w r² with respect to the left perturbation δ of T_ref_cur, so central differences of the
// cost must reproduce b. The scene is a textured plane, on which ICP's projective association can
// change pixel without changing any residual, so the cost is smooth.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/tracking/icp_cpu.hpp"
#include "vifusion/tracking/photometric_cpu.hpp"
#include "vifusion/tracking/rotation_cpu.hpp"

namespace vifusion::tracking {
namespace {

using preprocess::GradientPixel;
using preprocess::NormalPixel;
using preprocess::VertexPixel;

// Plane n·X = c in the reference camera frame, facing the camera.
const Eigen::Vector3d kPlaneNormal = Eigen::Vector3d(0.15, -0.2, -1.0).normalized();
const double kPlaneOffset = kPlaneNormal.dot(Eigen::Vector3d(0.0, 0.0, 2.0));

/// Smooth texture as a function of the point on the plane (reference frame), 0..255.
double texture(const Eigen::Vector3d& X_ref) { return 128.0 + 60.0 * std::sin(4.0 * X_ref.x()) * std::cos(3.0 * X_ref.y()); }

struct View {
  Image<VertexPixel> vertices;
  Image<NormalPixel> normals;
  Image<float> intensity;
  Image<GradientPixel> gradients;
};

/// Ray-casts the plane from a camera at T_ref_cam (vertices and normals in that camera's frame).
/// Vertices closer than `margin_px` to the border are left invalid: the current view's points then
/// always project inside the reference image, so no pixel enters or leaves the sums under the small
/// perturbations of the numeric derivative (that would make the cost jump).
View render(const PinholeCamera& camera, const SE3d& T_ref_cam, int margin_px) {
  View view{Image<VertexPixel>(camera.width, camera.height, VertexPixel::Zero()),
            Image<NormalPixel>(camera.width, camera.height, NormalPixel::Zero()),
            Image<float>(camera.width, camera.height), Image<GradientPixel>(camera.width, camera.height, GradientPixel::Zero())};
  const SE3d T_cam_ref = T_ref_cam.inverse();
  const Eigen::Vector3d n_cam = T_cam_ref.rotationMatrix() * kPlaneNormal;
  const double c_cam = kPlaneOffset + n_cam.dot(T_cam_ref.translation());
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector3d ray = camera.backProject(Eigen::Vector2d(u, v), 1.0);
      const Eigen::Vector3d X = c_cam / n_cam.dot(ray) * ray;
      const bool inside = u >= margin_px && v >= margin_px && u < camera.width - margin_px && v < camera.height - margin_px;
      if (inside) view.vertices(u, v) << X.cast<float>(), 1.0f;
      view.normals(u, v) << n_cam.cast<float>(), 1.0f;
      view.intensity(u, v) = static_cast<float>(texture(T_ref_cam * X));
    }
  }
  for (int v = 1; v + 1 < camera.height; ++v) {
    for (int u = 1; u + 1 < camera.width; ++u) {
      view.gradients(u, v) = 0.5f * GradientPixel(view.intensity(u + 1, v) - view.intensity(u - 1, v),
                                                  view.intensity(u, v + 1) - view.intensity(u, v - 1));
    }
  }
  return view;
}

/// Central differences of the cost ½ Σ w r² (cost(T) returns Σ w r²) under T ← exp(δ)·T.
Eigen::Matrix<double, 6, 1> numericGradient(const std::function<double(const SE3d&)>& cost, const SE3d& T, double step) {
  Eigen::Matrix<double, 6, 1> gradient;
  for (int k = 0; k < 6; ++k) {
    Eigen::Matrix<double, 6, 1> delta = Eigen::Matrix<double, 6, 1>::Zero();
    delta[k] = step;
    gradient[k] = 0.5 * (cost(SE3d::exp(delta) * T) - cost(SE3d::exp(-delta) * T)) / (2.0 * step);
  }
  return gradient;
}

class DenseTermJacobians : public ::testing::Test {
 protected:
  PinholeCamera camera_ = PinholeCamera::create(80, 60, 70.0, 70.0, 39.5, 29.5);
  SE3d T_ref_cur_true_ = SE3d::exp((Eigen::Matrix<double, 6, 1>() << 0.02, 0.01, -0.03, 0.01, -0.02, 0.015).finished());
  // Evaluate away from the optimum so that residuals, and the gradient, are not zero.
  SE3d T_ref_cur_ = SE3d::exp((Eigen::Matrix<double, 6, 1>() << 0.01, -0.005, 0.01, -0.006, 0.004, 0.005).finished()) *
                    T_ref_cur_true_;
  View reference_ = render(camera_, SE3d(), 0);
  View current_ = render(camera_, T_ref_cur_true_, 12);
};

TEST_F(DenseTermJacobians, IcpGradientMatchesCentralDifferencesOfTheCost) {
  IcpOptions options;
  options.huber_k = 1e9f;  // plain least squares: the weight must not depend on the residual
  const auto equations = [&](const SE3d& T) {
    return icpNormalEquationsCpu(current_.vertices.view(), current_.normals.view(), reference_.vertices.view(),
                                 reference_.normals.view(), IcpParams::make(T, camera_, options));
  };
  const NormalEquations6 at = equations(T_ref_cur_);
  ASSERT_GT(at.inliers, 1500.0);
  const Eigen::Matrix<double, 6, 1> numeric =
      numericGradient([&](const SE3d& T) { return equations(T).weighted_squared_residual; }, T_ref_cur_, 1e-4);
  EXPECT_LT((numeric - at.b).norm(), 1e-3 * at.b.norm()) << "analytic " << at.b.transpose() << "\nnumeric  "
                                                         << numeric.transpose();
}

TEST_F(DenseTermJacobians, PhotometricGradientMatchesCentralDifferencesOfTheCost) {
  PhotometricOptions options;
  options.huber_k = 1e9f;
  options.min_gradient = 0.0f;
  options.max_depth_difference_m = 1.0f;
  const auto equations = [&](const SE3d& T) {
    return photometricNormalEquationsCpu(current_.vertices.view(), current_.intensity.view(), reference_.intensity.view(),
                                         reference_.gradients.view(), reference_.vertices.view(),
                                         PhotometricParams::make(T, camera_, options));
  };
  const NormalEquations6 at = equations(T_ref_cur_);
  ASSERT_GT(at.inliers, 1500.0);
  const Eigen::Matrix<double, 6, 1> numeric =
      numericGradient([&](const SE3d& T) { return equations(T).weighted_squared_residual; }, T_ref_cur_, 1e-4);
  // The Jacobian uses the central-difference gradient image, the cost the bilinear interpolant's
  // slope; on this smooth texture they agree to about a percent.
  EXPECT_LT((numeric - at.b).norm(), 0.03 * at.b.norm()) << "analytic " << at.b.transpose() << "\nnumeric  "
                                                         << numeric.transpose();
}

// The rotation pre-alignment's residual depends on the rotation only: b's rotation half is the gradient
// of its cost under R ← exp(φ)·R, and its translation half is zero. The views differ by a pure rotation
// (small enough, 0.9 px at the border, that every interior pixel stays inside the other image).
TEST_F(DenseTermJacobians, RotationGradientMatchesCentralDifferencesOfTheCost) {
  const Eigen::Quaterniond q_prev_cur_true = SE3d::exp((Eigen::Matrix<double, 6, 1>() << 0, 0, 0, 0.006, -0.008, 0.004).finished()).quaternion();
  const View previous = render(camera_, SE3d(), 0);
  const View current = render(camera_, SE3d(q_prev_cur_true, Eigen::Vector3d::Zero()), 0);
  PhotometricOptions options;
  options.huber_k = 1e9f;
  options.min_gradient = 0.0f;
  const auto equations = [&](const SE3d& T) {
    return rotationNormalEquationsCpu(current.intensity.view(), previous.intensity.view(), previous.gradients.view(),
                                      RotationParams::make(T.quaternion(), camera_, options));
  };
  const SE3d at_pose(SE3d::exp((Eigen::Matrix<double, 6, 1>() << 0, 0, 0, -0.004, 0.003, 0.005).finished()).quaternion() *
                         q_prev_cur_true,
                     Eigen::Vector3d::Zero());
  const NormalEquations6 at = equations(at_pose);
  ASSERT_GT(at.inliers, 3000.0);
  EXPECT_EQ(at.b.head<3>().norm(), 0.0);
  const Eigen::Matrix<double, 6, 1> numeric =
      numericGradient([&](const SE3d& T) { return equations(T).weighted_squared_residual; }, at_pose, 1e-4);
  EXPECT_LT(numeric.head<3>().norm(), 1e-9) << "translation does not enter the homography";
  // As for the photometric term: the central-difference gradient image against the bilinear slope.
  EXPECT_LT((numeric.tail<3>() - at.b.tail<3>()).norm(), 0.03 * at.b.norm()) << "analytic " << at.b.transpose()
                                                                               << "\nnumeric  " << numeric.transpose();
}

}  // namespace
}  // namespace vifusion::tracking

namespace vifusion::tracking {
namespace {

// Gauss-Newton on the photometric term alone, from the identity, must land on the true motion: the
// term is unbiased when intensity is consistent with geometry (a bias here would make every
// frame-to-model alignment drift).
TEST(DenseTermAlignment, PhotometricGaussNewtonRecoversTheTrueMotion) {
  const PinholeCamera camera = PinholeCamera::create(160, 120, 140.0, 140.0, 79.5, 59.5);
  const SE3d T_ref_cur_true =
      SE3d::exp((Eigen::Matrix<double, 6, 1>() << 0.012, -0.006, 0.01, 0.004, -0.006, 0.003).finished());
  const View reference = render(camera, SE3d(), 0);
  const View current = render(camera, T_ref_cur_true, 0);
  PhotometricOptions options;
  options.min_gradient = 0.0f;
  SE3d T_ref_cur;
  for (int iteration = 0; iteration < 30; ++iteration) {
    const NormalEquations6 system = photometricNormalEquationsCpu(
        current.vertices.view(), current.intensity.view(), reference.intensity.view(), reference.gradients.view(),
        reference.vertices.view(), PhotometricParams::make(T_ref_cur, camera, options));
    const Eigen::Matrix<double, 6, 1> delta = system.H.ldlt().solve(-system.b);
    T_ref_cur = SE3d::exp(delta) * T_ref_cur;
  }
  const Eigen::Matrix<double, 6, 1> error = (T_ref_cur * T_ref_cur_true.inverse()).log();
  EXPECT_LT(error.head<3>().norm(), 2e-4) << error.transpose();
  EXPECT_LT(error.tail<3>().norm(), 1e-4) << error.transpose();
}

}  // namespace
}  // namespace vifusion::tracking

namespace vifusion::tracking {
namespace {

/// Photometric Gauss-Newton from the identity; `support_radius_px` overrides the level's default.
SE3d alignPhotometric(const PinholeCamera& camera, const View& reference, const View& current, int support_radius_px) {
  PhotometricOptions options;
  options.min_gradient = 0.0f;
  SE3d T_ref_cur;
  for (int iteration = 0; iteration < 30; ++iteration) {
    PhotometricParams params = PhotometricParams::make(T_ref_cur, camera, options);
    params.support_radius_px = support_radius_px;
    const NormalEquations6 system =
        photometricNormalEquationsCpu(current.vertices.view(), current.intensity.view(), reference.intensity.view(),
                                      reference.gradients.view(), reference.vertices.view(), params);
    T_ref_cur = SE3d::exp(Eigen::Matrix<double, 6, 1>(system.H.ldlt().solve(-system.b))) * T_ref_cur;
  }
  return T_ref_cur;
}

// The tracking-health ratio is ICP inliers over candidates; a candidate must be a pixel that lands on
// the model prediction, so that a view half outside the map (a fast turn into unmapped space) still
// reads as aligned, while a misaligned view does not.
TEST(DenseTermAlignment, IcpCandidatesArePixelsThatLandOnTheModel) {
  const PinholeCamera camera = PinholeCamera::create(80, 60, 70.0, 70.0, 39.5, 29.5);
  View reference = render(camera, SE3d(), 0);
  const View current = render(camera, SE3d(), 0);
  for (int v = 0; v < camera.height; ++v) {
    for (int u = camera.width / 2; u < camera.width; ++u) reference.vertices(u, v) = VertexPixel::Zero();
  }
  const auto equations = [&](const SE3d& T_ref_cur) {
    return icpNormalEquationsCpu(current.vertices.view(), current.normals.view(), reference.vertices.view(),
                                 reference.normals.view(), IcpParams::make(T_ref_cur, camera, IcpOptions{}));
  };
  const NormalEquations6 aligned = equations(SE3d());
  EXPECT_EQ(aligned.candidates, camera.width * camera.height / 2);
  EXPECT_EQ(aligned.inliers, aligned.candidates);
  // 0.3 m off along the optical axis: every pixel still lands on the model, none within the 10 cm gate.
  const NormalEquations6 misaligned = equations(SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.0, 0.0, 0.3)));
  EXPECT_GT(misaligned.candidates, 0.3 * camera.width * camera.height);
  EXPECT_EQ(misaligned.inliers, 0.0);
}

// A predicted model view has holes where no stable surfel projects: no vertex and intensity 0 there,
// so the reference's gradient image sees a strong edge along every hole's border that the current
// frame does not have. Sampling across it biased the alignment (sim:living_room_1 frame 186: 136 mm
// at the coarsest level, with half of the view unpredicted). The support gate must keep those
// samples out, and the term must then find the true motion as on a complete reference.
TEST(DenseTermAlignment, PhotometricIgnoresTheBordersOfHolesInTheReference) {
  const PinholeCamera camera = PinholeCamera::create(160, 120, 140.0, 140.0, 79.5, 59.5);
  const SE3d T_ref_cur_true =
      SE3d::exp((Eigen::Matrix<double, 6, 1>() << 0.012, -0.006, 0.01, 0.004, -0.006, 0.003).finished());
  View reference = render(camera, SE3d(), 0);
  const View current = render(camera, T_ref_cur_true, 0);
  // Unpredicted: the left third, and diagonal bands of missing pixels elsewhere, like the ragged rim of
  // a prediction that lags the view (surfels become stable one by one).
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      if ((u / 4 + v / 4) % 5 == 0 || u < camera.width / 3) {
        reference.vertices(u, v) = VertexPixel::Zero();
        reference.intensity(u, v) = 0.0f;
      }
    }
  }
  for (int v = 1; v + 1 < camera.height; ++v) {
    for (int u = 1; u + 1 < camera.width; ++u) {
      reference.gradients(u, v) = 0.5f * GradientPixel(reference.intensity(u + 1, v) - reference.intensity(u - 1, v),
                                                       reference.intensity(u, v + 1) - reference.intensity(u, v - 1));
    }
  }
  ASSERT_EQ(PhotometricParams::make(SE3d(), camera, PhotometricOptions{}).support_radius_px, 2);
  ASSERT_EQ(PhotometricParams::make(SE3d(), camera, PhotometricOptions{}, 1).support_radius_px, 3);

  const Eigen::Matrix<double, 6, 1> ungated =
      (alignPhotometric(camera, reference, current, 0) * T_ref_cur_true.inverse()).log();
  EXPECT_GT(ungated.head<3>().norm(), 5e-3) << "the holes' borders no longer bias an ungated term: "
                                            << ungated.transpose();
  const Eigen::Matrix<double, 6, 1> gated =
      (alignPhotometric(camera, reference, current, 2) * T_ref_cur_true.inverse()).log();
  EXPECT_LT(gated.head<3>().norm(), 4e-4) << gated.transpose();
  EXPECT_LT(gated.tail<3>().norm(), 2e-4) << gated.transpose();
}

}  // namespace
}  // namespace vifusion::tracking
