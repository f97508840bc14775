// DepthRegistration: validation, the identity test and the shader's push constants.

#include "vifusion/preprocess/depth_registration.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {
namespace {

/// |‖q‖ − 1| accepted for T_C_D's rotation: SE3d keeps q normalised, so anything larger is a corrupt
/// value (NaN, or a matrix read as a quaternion), not rounding.
constexpr double kUnitQuaternionTolerance = 1e-6;

std::string field(const std::string& name) { return "depth registration '" + name + "'"; }

/// Runs PinholeCamera's own checks and reports them under the camera's field name.
void validateCamera(const PinholeCamera& camera, const char* name) {
  try {
    PinholeCamera::create(camera.width, camera.height, camera.fx, camera.fy, camera.cx, camera.cy);
  } catch (const std::invalid_argument& error) {
    throw Error(field(name) + ": " + error.what());
  }
}

bool sameIntrinsics(const PinholeCamera& a, const PinholeCamera& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy;
}

Eigen::Matrix3d cameraMatrix(const PinholeCamera& camera) {
  Eigen::Matrix3d K;
  K << camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0;
  return K;
}

}  // namespace

void DepthRegistration::validate() const {
  validateCamera(depth, "depth");
  validateCamera(colour, "colour");
  const Eigen::Quaterniond& q = T_C_D.quaternion();
  if (!q.coeffs().allFinite() || std::abs(q.norm() - 1.0) > kUnitQuaternionTolerance) {
    throw Error(field("T_C_D") + ": rotation is not a finite unit quaternion (norm " + std::to_string(q.norm()) + ")");
  }
  const Eigen::Vector3d& t = T_C_D.translation();
  if (!t.allFinite() || !(t.norm() <= kMaxRegistrationBaseline_m)) {
    throw Error(field("T_C_D") + ": translation of " + std::to_string(t.norm()) +
                " m is not finite or beyond 1 m (millimetres given as metres?)");
  }
  static_assert(kMaxDepthScale_m == 0.01, "the message below quotes the bound");
  if (!(depth_scale_m > 0.0 && depth_scale_m <= kMaxDepthScale_m)) {
    throw Error(field("depth_scale_m") + " must be in (0, 0.01] m per unit, got " + std::to_string(depth_scale_m));
  }
}

bool DepthRegistration::isIdentity() const {
  // Eigen's angle-axis of q is in [0, π] (q and −q give the same angle).
  const double rotation_rad = Eigen::AngleAxisd(T_C_D.quaternion()).angle();
  return sameIntrinsics(depth, colour) && rotation_rad <= kIdentityRotation_rad &&
         T_C_D.translation().norm() <= kIdentityTranslation_m;
}

RegisterDepthParams DepthRegistration::kernelParams() const {
  const Eigen::Matrix3d H = cameraMatrix(colour) * T_C_D.rotationMatrix() * cameraMatrix(depth).inverse();
  const Eigen::Vector3d e = cameraMatrix(colour) * T_C_D.translation() / depth_scale_m;
  const auto f = [](double value) { return static_cast<float>(value); };
  RegisterDepthParams params;
  params.depth_width = depth.width;
  params.depth_height = depth.height;
  params.colour_width = colour.width;
  params.colour_height = colour.height;
  params.h00 = f(H(0, 0)), params.h01 = f(H(0, 1)), params.h02 = f(H(0, 2));
  params.h10 = f(H(1, 0)), params.h11 = f(H(1, 1)), params.h12 = f(H(1, 2));
  params.h20 = f(H(2, 0)), params.h21 = f(H(2, 1)), params.h22 = f(H(2, 2));
  params.e_x = f(e.x());
  params.e_y = f(e.y());
  params.e_z = f(e.z());
  return params;
}

void registerDepthToColourCpu(ImageView<const std::uint16_t> depth_raw, const DepthRegistration& registration,
                              ImageView<std::uint16_t> registered_raw) {
  registration.validate();
  registerDepthCpu(depth_raw, registration.kernelParams(), registered_raw);
}

}  // namespace vifusion::preprocess
