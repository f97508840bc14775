#include "vifusion/scene/renderer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vifusion::scene {
namespace {

/// Samples a motion-blurred pixel can average; beyond this the blur is smooth enough.
constexpr std::size_t kMaxBlurSamples = 64;

template <class T>
void checkSize(const ImageView<T>& view, const PinholeCamera& camera, const char* what) {
  if (!view.empty() && (view.width != camera.width || view.height != camera.height)) {
    throw std::invalid_argument(std::string("Renderer: ") + what + " image is " + std::to_string(view.width) + "x" +
                                std::to_string(view.height) + " but the camera is " + std::to_string(camera.width) +
                                "x" + std::to_string(camera.height));
  }
}

std::uint16_t toDepthUnits(double z_m, double depth_scale, double max_range_m, std::uint16_t /*tag*/) {
  if (!(z_m > 0.0) || z_m > max_range_m) return 0;
  const double units = std::nearbyint(z_m * depth_scale);
  return units > 65535.0 ? 0 : static_cast<std::uint16_t>(units);  // saturating values would lie
}

float toDepthUnits(double z_m, double /*depth_scale*/, double max_range_m, float /*tag*/) {
  return (z_m > 0.0 && z_m <= max_range_m) ? static_cast<float>(z_m) : 0.0F;
}

std::uint8_t toByte(float value) {
  return static_cast<std::uint8_t>(std::clamp(std::nearbyint(value * 255.0F), 0.0F, 255.0F));
}

/// The pose pieces a row loop needs, per sub-frame sample.
struct RayFrame {
  Eigen::Matrix3d R_W_C;
  Eigen::Vector3d origin_W;
};

}  // namespace

Renderer::Renderer(const LivingRoom& room, RowPool& pool, const RenderOptions& options)
    : room_(room), pool_(pool), options_(options), light_W_(options.light_direction_W.normalized()) {
  if (!(options.depth_scale > 0.0) || !(options.max_range_m > 0.0)) {
    throw std::invalid_argument("Renderer: depth_scale and max_range_m must be > 0");
  }
}

void Renderer::render(const SE3d& T_W_C, const PinholeCamera& camera, ImageView<Rgb8> rgb,
                      ImageView<std::uint16_t> depth) const {
  renderImpl<std::uint16_t>(std::span(&T_W_C, 1), camera, rgb, depth);
}

void Renderer::render(const SE3d& T_W_C, const PinholeCamera& camera, ImageView<Rgb8> rgb,
                      ImageView<float> depth_m) const {
  renderImpl<float>(std::span(&T_W_C, 1), camera, rgb, depth_m);
}

void Renderer::renderBlurred(std::span<const SE3d> T_W_C_samples, const PinholeCamera& camera, ImageView<Rgb8> rgb,
                             ImageView<std::uint16_t> depth) const {
  renderImpl<std::uint16_t>(T_W_C_samples, camera, rgb, depth);
}

void Renderer::renderBlurred(std::span<const SE3d> T_W_C_samples, const PinholeCamera& camera, ImageView<Rgb8> rgb,
                             ImageView<float> depth_m) const {
  renderImpl<float>(T_W_C_samples, camera, rgb, depth_m);
}

template <class Depth>
void Renderer::renderImpl(std::span<const SE3d> T_W_C_samples, const PinholeCamera& camera, ImageView<Rgb8> rgb,
                          ImageView<Depth> depth) const {
  if (T_W_C_samples.empty() || T_W_C_samples.size() > kMaxBlurSamples) {
    throw std::invalid_argument("Renderer: between 1 and " + std::to_string(kMaxBlurSamples) +
                                " poses per frame, got " + std::to_string(T_W_C_samples.size()));
  }
  checkSize(rgb, camera, "colour");
  checkSize(depth, camera, "depth");
  // Poses are unpacked on the stack: the row workers read them, nothing is allocated per frame.
  std::array<RayFrame, kMaxBlurSamples> frames;
  const std::size_t samples = T_W_C_samples.size();
  for (std::size_t i = 0; i < samples; ++i) {
    frames[i] = {T_W_C_samples[i].rotationMatrix(), T_W_C_samples[i].translation()};
  }
  const std::size_t depth_sample = samples / 2;
  const float inverse_samples = 1.0F / static_cast<float>(samples);
  const auto ambient = static_cast<float>(options_.ambient);
  const auto diffuse = static_cast<float>(options_.diffuse);

  pool_.forRows(camera.height, [&](int row_begin, int row_end) {
    for (int v = row_begin; v < row_end; ++v) {
      const double y_n = (static_cast<double>(v) - camera.cy) / camera.fy;
      for (int u = 0; u < camera.width; ++u) {
        const double x_n = (static_cast<double>(u) - camera.cx) / camera.fx;
        Albedo colour = Albedo::Zero();
        for (std::size_t i = 0; i < samples; ++i) {
          // Direction with unit camera z, so the ray parameter of the hit is its depth.
          const Eigen::Vector3d direction_W =
              frames[i].R_W_C.col(2) + x_n * frames[i].R_W_C.col(0) + y_n * frames[i].R_W_C.col(1);
          SurfaceHit hit;
          const bool found = room_.intersect(frames[i].origin_W, direction_W, &hit);
          if (i == depth_sample && !depth.empty()) {
            depth(u, v) = toDepthUnits(found ? hit.t : 0.0, options_.depth_scale, options_.max_range_m, Depth{});
          }
          if (found && !rgb.empty()) {
            const auto facing = static_cast<float>(hit.normal_W.dot(light_W_));
            colour += albedo(hit.material, hit.variant, hit.st_m) * (ambient + diffuse * 0.5F * (1.0F + facing));
          }
        }
        if (!rgb.empty()) {
          colour *= inverse_samples;
          rgb(u, v) = Rgb8{toByte(colour.x()), toByte(colour.y()), toByte(colour.z())};
        }
      }
    }
  });
}

}  // namespace vifusion::scene
