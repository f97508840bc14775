#include "synthetic_frame.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

namespace vifusion::cli {
namespace {

// Scene in the camera frame (x right, y down, z forward), metres.
constexpr double kWallZ_m = 3.0;   // back wall plane z = 3
constexpr double kFloorY_m = 1.2;  // floor plane y = 1.2 (below the camera)
const Eigen::Vector3d kSphereCentre_m(0.4, 0.3, 1.8);
constexpr double kSphereRadius_m = 0.4;
constexpr double kCheckerSize_m = 0.2;

struct Hit {
  double t = std::numeric_limits<double>::infinity();  ///< ray parameter; ray direction has z = 1
  preprocess::Rgb8 colour;
};

void hitPlanes(const Eigen::Vector3d& ray, Hit& hit) {
  const double t_wall = kWallZ_m / ray.z();
  if (t_wall > 0.0 && t_wall < hit.t) {
    const Eigen::Vector3d p = t_wall * ray;
    const bool dark =
        (static_cast<int>(std::floor(p.x() / kCheckerSize_m)) + static_cast<int>(std::floor(p.y() / kCheckerSize_m))) %
            2 !=
        0;
    hit = {t_wall, dark ? preprocess::Rgb8{40, 60, 90} : preprocess::Rgb8{220, 215, 200}};
  }
  if (ray.y() > 1e-9) {
    const double t_floor = kFloorY_m / ray.y();
    if (t_floor < hit.t) {
      const Eigen::Vector3d p = t_floor * ray;
      const auto shade = static_cast<std::uint8_t>(110 + 60 * std::sin(8.0 * p.x()) * std::sin(8.0 * p.z()));
      hit = {t_floor, {shade, static_cast<std::uint8_t>(shade * 0.8), static_cast<std::uint8_t>(shade * 0.6)}};
    }
  }
}

void hitSphere(const Eigen::Vector3d& ray, Hit& hit) {
  // |t·ray − c|² = r²  →  a t² − 2 b t + c = 0
  const double a = ray.squaredNorm();
  const double b = ray.dot(kSphereCentre_m);
  const double c = kSphereCentre_m.squaredNorm() - kSphereRadius_m * kSphereRadius_m;
  const double discriminant = b * b - a * c;
  if (discriminant < 0.0) return;
  const double t = (b - std::sqrt(discriminant)) / a;
  if (t <= 0.0 || t >= hit.t) return;
  const Eigen::Vector3d normal = (t * ray - kSphereCentre_m) / kSphereRadius_m;
  const double light = std::clamp(-normal.dot(Eigen::Vector3d(0.3, 0.6, 0.74).normalized()), 0.1, 1.0);
  hit = {t,
         {static_cast<std::uint8_t>(230 * light), static_cast<std::uint8_t>(90 * light),
          static_cast<std::uint8_t>(60 * light)}};
}

}  // namespace

SyntheticFrame renderSyntheticFrame(int width, int height) {
  const double f = 525.0 * width / 640.0;
  SyntheticFrame frame{PinholeCamera::create(width, height, f, f, 0.5 * width - 0.5, 0.5 * height - 0.5),
                       Image<std::uint16_t>(width, height), Image<preprocess::Rgb8>(width, height)};
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const Eigen::Vector3d ray = frame.camera.backProject(Eigen::Vector2d(u, v), 1.0);  // z = 1
      Hit hit;
      hitPlanes(ray, hit);
      hitSphere(ray, hit);
      const double depth_mm = std::isfinite(hit.t) ? 1000.0 * hit.t : 0.0;  // z of the hit, since ray.z = 1
      frame.depth_mm(u, v) = static_cast<std::uint16_t>(std::min(depth_mm, 65535.0));
      frame.rgb(u, v) = hit.colour;
    }
  }
  return frame;
}

}  // namespace vifusion::cli
