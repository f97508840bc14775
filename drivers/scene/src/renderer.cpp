#include "vifusion/scene/renderer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "pixel_shader.hpp"

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

/// Columns per tile and rows per pool job: the centre hits of a tile's rows (and one row and column
/// of halo around them) live on the worker's stack, so rendering allocates nothing. The halo rows are
/// cast twice, by both jobs that border them: 2 rays in 32 rows.
constexpr int kTileWidth = 128;
constexpr int kChunkRows = 32;

/// Centre-ray hits of one image row over a tile and one column either side (index 0 is u_begin − 1);
/// box == nullptr where the ray hits nothing.
using HitRow = std::array<SurfaceHit, kTileWidth + 2>;

/// Whether the pixel at index c of `here` is on an edge: a 4-neighbour's centre ray hits another face
/// (or nothing). A straight edge that crosses the pixel always separates its centre from one of theirs.
bool onEdge(const HitRow& above, const HitRow& here, const HitRow& below, std::size_t c) {
  const SurfaceHit& centre = here[c];
  return !(sameFace(centre, above[c]) && sameFace(centre, below[c]) && sameFace(centre, here[c - 1]) &&
           sameFace(centre, here[c + 1]));
}

/// The boxes the 3×3 centre rays around index c hit, each once; returns how many.
std::size_t boxesAround(const HitRow& above, const HitRow& here, const HitRow& below, std::size_t c,
                        std::array<const Box*, 9>* boxes) {
  std::size_t count = 0;
  for (const HitRow* row : {&above, &here, &below}) {
    for (std::size_t n = c - 1; n <= c + 1; ++n) {
      const Box* box = (*row)[n].box;
      if (box != nullptr && std::find(boxes->begin(), boxes->begin() + count, box) == boxes->begin() + count) {
        (*boxes)[count++] = box;
      }
    }
  }
  return count;
}

}  // namespace

void RenderOptions::validate() const {
  const auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("RenderOptions: " + what);
  };
  require(depth_scale > 0.0 && std::isfinite(depth_scale), "depth_scale must be finite and > 0");
  require(max_range_m > 0.0, "max_range_m must be > 0");
  require(light_direction_W.allFinite() && light_direction_W.norm() > 0.0,
          "light_direction_W must be finite and non-zero");
  require(ambient >= 0.0 && diffuse >= 0.0 && std::isfinite(ambient + diffuse),
          "ambient and diffuse must be finite and >= 0");
  require(optics_blur_sigma_px >= 0.0 && optics_blur_sigma_px <= kMaxOpticsBlurSigma_px,
          "optics_blur_sigma_px must be in [0, " + std::to_string(kMaxOpticsBlurSigma_px) + "]");
  require(edge_samples_per_axis >= 1 && edge_samples_per_axis <= kMaxEdgeSamplesPerAxis,
          "edge_samples_per_axis must be in [1, " + std::to_string(kMaxEdgeSamplesPerAxis) + "], got " +
              std::to_string(edge_samples_per_axis));
}

Renderer::Renderer(const LivingRoom& room, RowPool& pool, const RenderOptions& options)
    : room_(room), pool_(pool), options_((options.validate(), options)) {}

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
  for (std::size_t i = 0; i < samples; ++i) frames[i] = RayFrame(T_W_C_samples[i], camera);
  const std::size_t depth_sample = samples / 2;
  const float inverse_samples = 1.0F / static_cast<float>(samples);
  const PixelShader shader(room_, camera, options_);
  // Edges are found by comparing a pixel's centre hit with its neighbours' (onEdge), so the rows above
  // and below and the columns either side are cast too; depth-only and plain renders skip them.
  const bool find_edges = !rgb.empty() && options_.edge_samples_per_axis > 1;
  const int halo = find_edges ? 1 : 0;

  pool_.forRows(
      camera.height,
      [&](int row_begin, int row_end) {
        std::array<Albedo, kChunkRows * kTileWidth> colour_sums;
        std::array<HitRow, 3> rows;
        for (int u_begin = 0; u_begin < camera.width; u_begin += kTileWidth) {
          const int u_end = std::min(u_begin + kTileWidth, camera.width);
          const auto castRow = [&](const RayFrame& frame, int v, HitRow& row) {
            for (int u = u_begin - halo; u < u_end + halo; ++u) {
              SurfaceHit& hit = row[static_cast<std::size_t>(u - u_begin + 1)];
              hit = SurfaceHit{};
              room_.intersect(frame.origin_W, frame.direction(camera, u, v), &hit);
            }
          };
          if (!rgb.empty()) std::fill(colour_sums.begin(), colour_sums.end(), Albedo::Zero());
          // Depth alone needs only its own sub-frame: the others would cast rays for nothing.
          const std::size_t first_sample = rgb.empty() ? depth_sample : 0;
          const std::size_t end_sample = rgb.empty() ? depth_sample + 1 : samples;
          for (std::size_t i = first_sample; i < end_sample; ++i) {
            const RayFrame& frame = frames[i];
            // Rolling window over the rows v − 1, v, v + 1 (only v without edge finding).
            HitRow* above = &rows[0];
            HitRow* here = &rows[1];
            HitRow* below = &rows[2];
            if (find_edges) {
              castRow(frame, row_begin - 1, *above);
              castRow(frame, row_begin, *here);
            }
            for (int v = row_begin; v < row_end; ++v) {
              if (find_edges) {
                castRow(frame, v + 1, *below);
              } else {
                castRow(frame, v, *here);
              }
              for (int u = u_begin; u < u_end; ++u) {
                const auto c = static_cast<std::size_t>(u - u_begin + 1);
                const SurfaceHit& centre = (*here)[c];
                if (i == depth_sample && !depth.empty()) {
                  depth(u, v) = toDepthUnits(centre.box != nullptr ? centre.t : 0.0, options_.depth_scale,
                                             options_.max_range_m, Depth{});
                }
                if (rgb.empty()) continue;
                Albedo& sum = colour_sums[static_cast<std::size_t>((v - row_begin) * kTileWidth + (u - u_begin))];
                if (!find_edges || !onEdge(*above, *here, *below, c)) {
                  sum += shader.shade(frame, frame.direction(camera, u, v), centre);
                  continue;
                }
                std::array<const Box*, 9> candidates{};
                const std::size_t count = boxesAround(*above, *here, *below, c, &candidates);
                sum += shader.resolveEdge(frame, u, v, centre, std::span(candidates.data(), count));
              }
              std::swap(above, here);  // the old row above becomes the scratch for the next row below
              std::swap(here, below);
            }
          }
          if (rgb.empty()) continue;
          for (int v = row_begin; v < row_end; ++v) {
            for (int u = u_begin; u < u_end; ++u) {
              const Albedo colour =
                  colour_sums[static_cast<std::size_t>((v - row_begin) * kTileWidth + (u - u_begin))] * inverse_samples;
              rgb(u, v) = Rgb8{toByte(colour.x()), toByte(colour.y()), toByte(colour.z())};
            }
          }
        }
      },
      kChunkRows);
}

}  // namespace vifusion::scene
