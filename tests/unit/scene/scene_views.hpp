#pragma once
// Cameras, views and image measures shared by the scene tests.

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/scene/living_room.hpp"
#include "vifusion/scene/look_at.hpp"
#include "vifusion/scene/row_pool.hpp"

namespace vifusion::scene::test {

/// The standard furnished room, built once per test binary.
inline const LivingRoom& room() {
  static const LivingRoom instance;
  return instance;
}

/// Two row workers, as on the target machine.
inline RowPool& pool() {
  static RowPool instance(2);
  return instance;
}

/// ICL-NUIM intrinsics (negative fy, as the dataset renders).
inline PinholeCamera iclCamera() { return PinholeCamera::create(640, 480, 481.2, -480.0, 319.5, 239.5); }
/// The same with positive fy.
inline PinholeCamera uprightCamera() { return PinholeCamera::create(640, 480, 481.2, 480.0, 319.5, 239.5); }

/// A busy view from the camera region: sofa, table, rug, bookshelf, TV, walls, floor.
inline SE3d furnishedView() { return lookAt(Eigen::Vector3d(2.2, 1.6, 1.5), Eigen::Vector3d(-1.0, 0.6, -3.0)); }
/// The white_wall situation: at x = 2.3 looking +x, 1.55 m from the wall.
inline SE3d whiteWallView() { return lookAt(Eigen::Vector3d(2.3, 1.35, -0.2), Eigen::Vector3d(3.85, 1.35, -0.2)); }

/// Mean of R, G, B on the 0–255 scale.
inline Image<float> grey(const Image<Rgb8>& rgb) {
  Image<float> out(rgb.width(), rgb.height());
  for (int y = 0; y < rgb.height(); ++y) {
    for (int x = 0; x < rgb.width(); ++x) {
      const Rgb8 p = rgb(x, y);
      out(x, y) = (static_cast<float>(p.r) + static_cast<float>(p.g) + static_cast<float>(p.b)) / 3.0F;
    }
  }
  return out;
}

/// 2×2 box average, the simplest pyramid step.
inline Image<float> halve(const Image<float>& in) {
  Image<float> out(in.width() / 2, in.height() / 2);
  for (int y = 0; y < out.height(); ++y) {
    for (int x = 0; x < out.width(); ++x) {
      out(x, y) = 0.25F * (in(2 * x, 2 * y) + in(2 * x + 1, 2 * y) + in(2 * x, 2 * y + 1) + in(2 * x + 1, 2 * y + 1));
    }
  }
  return out;
}

/// Mean |∇I| with central differences over the interior [grey levels per pixel].
inline double meanGradient(const Image<float>& image) {
  double sum = 0.0;
  int count = 0;
  for (int y = 1; y + 1 < image.height(); ++y) {
    for (int x = 1; x + 1 < image.width(); ++x) {
      const double gx = 0.5 * (image(x + 1, y) - image(x - 1, y));
      const double gy = 0.5 * (image(x, y + 1) - image(x, y - 1));
      sum += std::hypot(gx, gy);
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

}  // namespace vifusion::scene::test
