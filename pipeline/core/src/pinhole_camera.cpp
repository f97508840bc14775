#include "vifusion/core/pinhole_camera.hpp"

#include <cassert>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace vifusion {
namespace {

template <typename T>
[[noreturn]] void throwInvalid(const char* name, T value, const char* requirement) {
  std::ostringstream os;
  os << "PinholeCamera: " << name << " = " << value << " is invalid (" << requirement << ")";
  throw std::invalid_argument(os.str());
}

}  // namespace

PinholeCamera PinholeCamera::create(int width, int height, double fx, double fy, double cx, double cy) {
  if (width <= 0) throwInvalid("width", width, "must be > 0");
  if (height <= 0) throwInvalid("height", height, "must be > 0");
  if (!std::isfinite(fx) || fx <= 0.0) throwInvalid("fx", fx, "must be finite and > 0");
  // fy < 0 is legitimate (ICL-NUIM renders with fy = −480); only zero and non-finite values are not.
  if (!std::isfinite(fy) || fy == 0.0) throwInvalid("fy", fy, "must be finite and non-zero");
  if (!std::isfinite(cx)) throwInvalid("cx", cx, "must be finite");
  if (!std::isfinite(cy)) throwInvalid("cy", cy, "must be finite");
  return PinholeCamera{width, height, fx, fy, cx, cy};
}

PinholeCamera PinholeCamera::atLevel(int level) const {
  // Each level keeps floor(size / 2) pixels; a level that would leave an empty image is a caller bug
  // in the pyramid plan, reported like any bad parameter.
  if (level < 0 || level >= 31 || (width >> level) <= 0 || (height >> level) <= 0) {
    throwInvalid("level", level, "must be >= 0 and leave at least one pixel");
  }
  const double scale = 1.0 / static_cast<double>(1 << level);
  // Pixel j of level l is the 5-tap Gaussian sample centred on level-0 pixel 2^l·j (the pyramid
  // kernels sample at even pixels, as cv::pyrDown), so coordinates scale without an offset.
  return PinholeCamera{.width = width >> level,
                       .height = height >> level,
                       .fx = fx * scale,
                       .fy = fy * scale,
                       .cx = cx * scale,
                       .cy = cy * scale};
}

Eigen::Vector2d PinholeCamera::project(const Eigen::Vector3d& p_C, Eigen::Matrix<double, 2, 3>* J_uv_p) const {
  assert(p_C.z() > 0.0);
  const double z_inv = 1.0 / p_C.z();
  const double x_n = p_C.x() * z_inv;  // normalised image coordinates
  const double y_n = p_C.y() * z_inv;
  if (J_uv_p != nullptr) {
    *J_uv_p << fx * z_inv, 0.0, -fx * x_n * z_inv,  //
        0.0, fy * z_inv, -fy * y_n * z_inv;
  }
  return {fx * x_n + cx, fy * y_n + cy};
}

Eigen::Vector3d PinholeCamera::backProject(const Eigen::Vector2d& uv, double z_m) const {
  return {(uv.x() - cx) / fx * z_m, (uv.y() - cy) / fy * z_m, z_m};
}

bool PinholeCamera::isInside(const Eigen::Vector2d& uv, double border_px) const {
  // Every comparison is false for NaN, so NaN coordinates are outside.
  return uv.x() >= border_px && uv.x() <= static_cast<double>(width - 1) - border_px && uv.y() >= border_px &&
         uv.y() <= static_cast<double>(height - 1) - border_px;
}

}  // namespace vifusion
