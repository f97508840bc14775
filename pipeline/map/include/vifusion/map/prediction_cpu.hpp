#pragma once
// Model prediction on the CPU: the references of map_predict_splat.comp (both passes),
// map_predict_attributes.comp and map_pyramid_subsample.comp, with the same float arithmetic in
// the same order, so splat winners agree exactly with the GPU. Also the parameter blocks the
// kernels read (std430 mirrors of shaders/include/map/{view,prediction}.glsl).

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <span>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/map/surfel.hpp"

namespace vifusion::map {

/// World → camera pose, level-0 intrinsics and current frame (MapView in view.glsl).
struct MapView {
  float T_C_W_rows[3][4] = {};           ///< rows of the 3×4 transform world → camera [m]
  float fx = 0, fy = 0, cx = 0, cy = 0;  ///< level-0 intrinsics [px]; fy may be negative
  float inv_fx = 0, inv_fy = 0;          ///< 1/fx, 1/fy [1/px]
  std::int32_t width = 0, height = 0;    ///< level-0 image size [px]
  std::uint32_t frame = 0;               ///< current frame number
  std::uint32_t pad[3] = {};

  static MapView make(const SE3d& T_C_W, const PinholeCamera& camera, std::uint32_t frame);
};
static_assert(sizeof(MapView) == 96);
static_assert(offsetof(MapView, fx) == 48);
static_assert(offsetof(MapView, inv_fx) == 64);
static_assert(offsetof(MapView, width) == 72);
static_assert(offsetof(MapView, frame) == 80);

/// Which surfels a prediction renders (PredictionParams::surfels; kPredictActive, kPredictInactive and
/// kPredictStable in prediction.glsl, which states the rules).
enum class PredictedSurfels : std::uint32_t {
  kActive = 0,  ///< active (updated within δ_t) and stable, every active one while the map is young: tracking's model
  kInactive = 1,  ///< inactive (not updated within δ_t) and stable: local loop closure's inactive model
  kStable = 2,    ///< every stable surfel, whatever its age: localisation-only tracking's model (nothing fuses)
};

/// PredictionParams::created_before that keeps every surfel.
inline constexpr std::uint32_t kAnyCreationFrame = 0xffffffffu;

/// PredictionParams in prediction.glsl.
struct PredictionParams {
  MapView view;
  float confidence_threshold = 0;          ///< stable when confidence ≥ this
  std::uint32_t time_window_frames = 0;    ///< δ_t: active when updated within this many frames
  std::uint32_t young_map_frames = 0;      ///< before this frame every active surfel is rendered
  float min_depth_m = 0;                   ///< nearer surfel centres are not rendered [m]
  float max_depth_m = 0;                   ///< nor farther ones [m]
  std::int32_t max_half_footprint_px = 0;  ///< footprint cap: (2·cap + 1)² pixels
  std::uint32_t surfels = static_cast<std::uint32_t>(PredictedSurfels::kActive);  ///< a PredictedSurfels value
  std::uint32_t created_before = kAnyCreationFrame;  ///< and only surfels created before this frame
};
static_assert(sizeof(PredictionParams) == 128);
static_assert(offsetof(PredictionParams, confidence_threshold) == 96);
static_assert(offsetof(PredictionParams, max_half_footprint_px) == 116);
static_assert(offsetof(PredictionParams, surfels) == 120);
static_assert(offsetof(PredictionParams, created_before) == 124);

/// "No surfel" in the splat id image (kNoSurfel in prediction.glsl).
inline constexpr std::uint32_t kNoSurfel = 0xffffffffu;

// Geometry helpers shared by the prediction and cleanup references (view.glsl).
Eigen::Vector3f transformPointCpu(const MapView& view, const Eigen::Vector3f& p_W);
Eigen::Vector3f rotateVectorCpu(const MapView& view, const Eigen::Vector3f& n_W);
Eigen::Vector2f projectPointCpu(const MapView& view, const Eigen::Vector3f& p_C);
std::uint32_t framesSinceCpu(const MapView& view, float frame);
/// prediction.glsl's isRendered: whether `params` selects the surfel.
bool isRenderedCpu(const Surfel& surfel, const PredictionParams& params);

/// Both splat passes: per pixel the smallest splat key (prediction.glsl: centre pixels first, then
/// the disk intersection depth; 0xffffffff = none) and the lowest index of the surfels with that key
/// (kNoSurfel = none).
/// Images are level-0 sized; surfels are the live ones (surfel_count of them).
void splatModelCpu(std::span<const Surfel> surfels, const PredictionParams& params, ImageView<std::uint32_t> depth_bits,
                   ImageView<std::uint32_t> ids);

/// The resolve pass: level-0 model maps in the camera frame from the splat ids (vertex w: the depth the surfel
/// was observed from, map_predict_attributes.comp).
void resolveModelCpu(std::span<const Surfel> surfels, const PredictionParams& params,
                     ImageView<const std::uint32_t> ids, ImageView<Eigen::Vector4f> vertices,
                     ImageView<Eigen::Vector4f> normals, ImageView<float> intensity);

/// Level-l maps from level 0 by point sampling: dst(x, y) = src(2^l·x, 2^l·y).
void subsampleModelCpu(ImageView<const Eigen::Vector4f> vertices0, ImageView<const Eigen::Vector4f> normals0,
                       ImageView<const float> intensity0, int level, ImageView<Eigen::Vector4f> vertices,
                       ImageView<Eigen::Vector4f> normals, ImageView<float> intensity);

}  // namespace vifusion::map
