#include "vifusion/calib/pair_residuals.hpp"

#include <cmath>
#include <limits>

#include "vifusion/core/error.hpp"

namespace vifusion::calib {
namespace {

constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
constexpr int kStep = kStencilHalfWidth_px;

struct Stencil {
  float centre, left, right, up, down;
};

Stencil stencilAt(ImageView<const float> image, int x, int y) {
  return {image(x, y), image(x - kStep, y), image(x + kStep, y), image(x, y - kStep), image(x, y + kStep)};
}

bool allDepth(const Stencil& s) {
  return s.centre > 0.0F && s.left > 0.0F && s.right > 0.0F && s.up > 0.0F && s.down > 0.0F;
}

double curvature(const Stencil& s, bool along_x) {
  return along_x ? std::abs(s.right - 2.0 * s.centre + s.left) : std::abs(s.down - 2.0 * s.centre + s.up);
}

constexpr double kSpan = 2.0 * kStep;

/// The stencil's value at c + δ by its central-difference gradient.
double valueAtOffset(const Stencil& s, double dx, double dy) {
  return s.centre + (s.right - s.left) / kSpan * dx + (s.down - s.up) / kSpan * dy;
}

Eigen::Vector2d gradient(const Stencil& s) { return {(s.right - s.left) / kSpan, (s.down - s.up) / kSpan}; }

double gradientSquared(const Stencil& s) { return gradient(s).squaredNorm(); }

bool isSmoothSurface(const Stencil& s, double max_relative_curvature) {
  const double bound = max_relative_curvature * s.centre;
  return allDepth(s) && curvature(s, true) <= bound && curvature(s, false) <= bound;
}

}  // namespace

void PairResidualOptions::validate() const {
  if (!(max_relative_curvature > 0.0 && max_relative_curvature < 1.0)) {
    throw Error("pair-residual option 'max_relative_curvature' must be in (0, 1)");
  }
  if (!(max_intensity_curvature > 0.0)) throw Error("pair-residual option 'max_intensity_curvature' must be > 0");
}

void PairResidualImages::resize(int width, int height) {
  if (inverse_depth_residual_per_m.width() == width && inverse_depth_residual_per_m.height() == height) return;
  for (Image<float>* image : {&inverse_depth_residual_per_m, &depth_b_m, &inverse_depth_gradient_sq, &bias_sensitivity,
                              &grey_b_at_a, &grey_a, &grey_gradient_sq}) {
    image->resize(width, height);
  }
}

void computePairResiduals(const PinholeCamera& camera, ImageView<const float> inverse_depth_a,
                          ImageView<const float> grey_a, ImageView<const float> inverse_depth_b,
                          ImageView<const float> grey_b, const SE3d& T_b_a, const PairResidualOptions& options,
                          PairResidualImages& out) {
  const int width = inverse_depth_a.width;
  const int height = inverse_depth_a.height;
  out.resize(width, height);
  const Eigen::Matrix3d R_b_a = T_b_a.rotationMatrix();
  const Eigen::Vector3d t_b_a = T_b_a.translation();
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      out.inverse_depth_residual_per_m(x, y) = kNone;
      out.depth_b_m(x, y) = kNone;
      out.inverse_depth_gradient_sq(x, y) = kNone;
      out.bias_sensitivity(x, y) = kNone;
      out.grey_b_at_a(x, y) = kNone;
      out.grey_gradient_sq(x, y) = kNone;
      out.grey_a(x, y) = grey_a(x, y);
      const bool inside_a = x >= kStep && y >= kStep && x < width - kStep && y < height - kStep;
      if (!inside_a || !isSmoothSurface(stencilAt(inverse_depth_a, x, y), options.max_relative_curvature)) continue;

      const Eigen::Vector3d ray_b = R_b_a * camera.backProject({x, y}, 1.0);
      const double z_a = 1.0 / inverse_depth_a(x, y);
      const Eigen::Vector3d p_b = ray_b * z_a + t_b_a;
      if (!(p_b.z() > 0.0)) continue;
      Eigen::Matrix<double, 2, 3> J_uv_p;
      const Eigen::Vector2d uv_b = camera.project(p_b, &J_uv_p);
      if (!camera.isInside(uv_b, kStep + 1)) continue;
      const int cx = static_cast<int>(std::lround(uv_b.x()));
      const int cy = static_cast<int>(std::lround(uv_b.y()));
      const double dx = uv_b.x() - cx;
      const double dy = uv_b.y() - cy;

      const Stencil depth_b = stencilAt(inverse_depth_b, cx, cy);
      if (isSmoothSurface(depth_b, options.max_relative_curvature)) {
        out.inverse_depth_residual_per_m(x, y) = static_cast<float>(valueAtOffset(depth_b, dx, dy) - 1.0 / p_b.z());
        out.depth_b_m(x, y) = static_cast<float>(p_b.z());
        out.inverse_depth_gradient_sq(x, y) = static_cast<float>(gradientSquared(depth_b));
        // b moves p_b by −z_a²·ray_b: along its own ray (1/z(p_b) changes) and across b's image (u' moves on
        // the epipolar line, where ι_b has gradient ∇ι_b).
        const Eigen::Vector3d dp_b = -z_a * z_a * ray_b;
        const double through_depth = -dp_b.z() / (p_b.z() * p_b.z());
        const double through_image = gradient(depth_b).dot(J_uv_p * dp_b);
        out.bias_sensitivity(x, y) = static_cast<float>(1.0 + through_image - through_depth);
      }
      const Stencil intensity_b = stencilAt(grey_b, cx, cy);
      if (curvature(intensity_b, true) <= options.max_intensity_curvature &&
          curvature(intensity_b, false) <= options.max_intensity_curvature) {
        out.grey_b_at_a(x, y) = static_cast<float>(valueAtOffset(intensity_b, dx, dy));
        out.grey_gradient_sq(x, y) = static_cast<float>(gradientSquared(intensity_b));
      }
    }
  }
}

}  // namespace vifusion::calib
