#include "pixel_shader.hpp"

#include <array>
#include <cmath>
#include <optional>

#include "vifusion/scene/pixel_footprint.hpp"
#include "vifusion/scene/texture.hpp"

namespace vifusion::scene {
namespace {

/// One face seen by an edge pixel's sub-rays.
struct FaceCoverage {
  SurfaceHit hit;                                         ///< the first sub-ray's hit on it
  Eigen::Vector3d direction_W = Eigen::Vector3d::Zero();  ///< that sub-ray's direction
  int count = 0;                                          ///< sub-rays that hit the face
  int du_half_steps = 0;                                  ///< sum of their offsets from the pixel centre [1/(2N) px]
  int dv_half_steps = 0;
};

constexpr std::size_t kMaxFacesPerPixel = RenderOptions::kMaxEdgeSamplesPerAxis * RenderOptions::kMaxEdgeSamplesPerAxis;

}  // namespace

RayFrame::RayFrame(const SE3d& T_W_C, const PinholeCamera& camera)
    : R_W_C(T_W_C.rotationMatrix()),
      origin_W(T_W_C.translation()),
      ddirection_du_W(R_W_C.col(0) / camera.fx),
      ddirection_dv_W(R_W_C.col(1) / camera.fy) {}

PixelShader::PixelShader(const LivingRoom& room, const PinholeCamera& camera, const RenderOptions& options)
    : room_(room),
      camera_(camera),
      options_(options),
      light_W_(options.light_direction_W.normalized()),
      footprint_scale_(std::sqrt(1.0 + 12.0 * options.optics_blur_sigma_px * options.optics_blur_sigma_px)),
      ambient_(static_cast<float>(options.ambient)),
      diffuse_(static_cast<float>(options.diffuse)) {}

Albedo PixelShader::shade(const RayFrame& frame, const Eigen::Vector3d& direction_W, const SurfaceHit& hit) const {
  if (hit.box == nullptr) return Albedo::Zero();
  const Eigen::Matrix2d J_st_px =
      options_.filter_textures ? Eigen::Matrix2d(footprint_scale_ * stJacobian(hit, direction_W, frame.ddirection_du_W,
                                                                               frame.ddirection_dv_W))
                               : Eigen::Matrix2d::Zero();
  const auto facing = static_cast<float>(hit.normal_W.dot(light_W_));
  return albedo(hit.material, hit.variant, hit.st_m, J_st_px) * (ambient_ + diffuse_ * 0.5F * (1.0F + facing));
}

Albedo PixelShader::resolveEdge(const RayFrame& frame, int u, int v, const SurfaceHit& centre,
                                std::span<const Box* const> candidates) const {
  const int n = options_.edge_samples_per_axis;
  // Optional, so that only the faces found are constructed (a SurfaceHit initialises all its fields).
  std::array<std::optional<FaceCoverage>, kMaxFacesPerPixel> faces;
  std::size_t face_count = 0;
  for (int j = 0; j < n; ++j) {
    for (int k = 0; k < n; ++k) {
      // Sub-pixel centres (2k + 1 − N)/(2N) [px], kept as integers so that sums are exact.
      const int du_half_steps = 2 * k + 1 - n;
      const int dv_half_steps = 2 * j + 1 - n;
      const Eigen::Vector3d direction_W = frame.direction(camera_, u, v, static_cast<double>(du_half_steps) / (2 * n),
                                                          static_cast<double>(dv_half_steps) / (2 * n));
      SurfaceHit hit;
      if (du_half_steps == 0 && dv_half_steps == 0) {
        hit = centre;
      } else if (!room_.intersectAmong(frame.origin_W, direction_W, candidates, &hit)) {
        room_.intersect(frame.origin_W, direction_W, &hit);
      }
      std::size_t f = 0;
      while (f < face_count && !sameFace(faces[f]->hit, hit)) ++f;
      if (f == face_count) faces[face_count++].emplace(FaceCoverage{hit, direction_W});
      FaceCoverage& face = *faces[f];
      ++face.count;
      face.du_half_steps += du_half_steps;
      face.dv_half_steps += dv_half_steps;
    }
  }
  // Summed in double, where adding a few floats is exact: the result does not depend on the order in
  // which faces were found (a flipped camera, fy < 0, visits the sub-rays in the opposite order).
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t f = 0; f < face_count; ++f) {
    const FaceCoverage& face = *faces[f];
    if (face.hit.box == nullptr) continue;  // nothing there: black
    const Eigen::Vector3d direction_W =
        frame.direction(camera_, u, v, static_cast<double>(face.du_half_steps) / (2 * n * face.count),
                        static_cast<double>(face.dv_half_steps) / (2 * n * face.count));
    // Where the centroid ray meets the face's plane, n·(p − p_hit) = 0, found from the sub-ray's hit.
    const Eigen::Vector3d hit_from_origin_W = face.hit.t * face.direction_W;
    SurfaceHit at_centroid = face.hit;
    at_centroid.t = face.hit.normal_W.dot(hit_from_origin_W) / face.hit.normal_W.dot(direction_W);
    const Eigen::Vector3d shift_W = at_centroid.t * direction_W - hit_from_origin_W;
    at_centroid.st_m += Eigen::Vector2d(face.hit.s_axis_W.dot(shift_W), face.hit.t_axis_W.dot(shift_W));
    const Albedo colour = shade(frame, direction_W, at_centroid);
    sum += face.count * colour.cast<double>();
  }
  return (sum / (n * n)).cast<float>();
}

}  // namespace vifusion::scene
